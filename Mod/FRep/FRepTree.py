"""From document objects to one frepcore tree (seed 000's Algorithm 1, by type, never by name).

An FRep feature's shape is its node over its inputs' shapes, moved by its Placement. FreeCAD's
Part primitives (Box, Sphere, Cylinder, Cone, Torus, Ellipsoid) map to the exact FRep
primitive with their Placement. Every other solid (PartDesign Body, Part boolean, imported
STEP) and every Mesh feature enters as a signed-distance field (FRepSolids). Anything else is
refused with a message saying what is accepted.
"""

import FRepSolids
from FRepPaths import frepcore

PART_PRIMITIVES = ("Part::Box", "Part::Sphere", "Part::Cylinder", "Part::Cone", "Part::Torus",
                   "Part::Ellipsoid")


def is_frep_feature(obj):
    """An FRep node feature (its proxy builds a node); an hspline attachment, which has a type
    for its icon but is a plain mesh, is not one."""
    proxy = getattr(obj, "Proxy", None)
    return getattr(proxy, "FREP_TYPE", None) is not None and hasattr(proxy, "local_shape")


def is_frep_input(obj):
    return (is_frep_feature(obj) or getattr(obj, "TypeId", "") in PART_PRIMITIVES
            or FRepSolids.is_solid_input(obj))


ACCEPTED = ("FRep features, Part primitives, solids (PartDesign bodies, Part features, "
            "imported STEP) and closed meshes")


def describe(obj):
    return "'%s' (%s)" % (obj.Label, obj.TypeId)


class Builder:
    """Builds shapes for one recompute: shared inputs are built once, cycles are caught."""

    def __init__(self):
        self.cache = {}
        self.stack = []

    def shape(self, obj):
        """The object's solid in document coordinates."""
        key = (obj.Document.Name, obj.Name)
        if key in self.cache:
            return self.cache[key]
        if obj in self.stack:
            chain = " -> ".join(o.Label for o in self.stack + [obj])
            raise ValueError("%s: its inputs lead back to itself (%s); remove that link"
                             % (obj.Label, chain))
        self.stack.append(obj)
        try:
            if is_frep_feature(obj):
                s = placed(obj.Proxy.local_shape(obj, self), obj.Placement)
            elif obj.TypeId in PART_PRIMITIVES and _is_full_primitive(obj):
                s = placed(part_primitive(obj), obj.Placement)
            elif FRepSolids.is_solid_input(obj):
                s = FRepSolids.solid_shape(obj)  # already in document coordinates
            else:
                raise ValueError("%s is not an FRep input; accepted: %s" % (describe(obj), ACCEPTED))
        finally:
            self.stack.pop()
        self.cache[key] = s
        return s


def shape_of(obj):
    return Builder().shape(obj)


def placed(shape, placement):
    """shape moved by a FreeCAD Placement (exact: an affine node, no resampling)."""
    if placement.isIdentity():
        return shape
    m = placement.toMatrix()
    return frepcore.transform(shape, tuple(m.A[:12]))


def _is_full_primitive(obj):
    """A Part primitive the exact FRep primitive represents (no partial angles); a cut one
    (a quarter sphere) enters as a solid instead."""
    try:
        part_primitive(obj)
        return True
    except ValueError:
        return False


def _full_angles(obj, names_and_full):
    for name, full in names_and_full:
        v = getattr(obj, name).Value
        if abs(v - full) > 1e-9:
            raise ValueError("%s: property '%s' = %g deg; only the full solid (%g deg) is an "
                             "FRep primitive" % (describe(obj), name, v, full))


def part_primitive(obj):
    """The exact FRep primitive of a Part primitive, in its own (unplaced) coordinates."""
    t = obj.TypeId
    if t == "Part::Box":
        return frepcore.box((obj.Length.Value, obj.Width.Value, obj.Height.Value))
    if t == "Part::Sphere":
        _full_angles(obj, (("Angle1", -90), ("Angle2", 90), ("Angle3", 360)))
        return frepcore.sphere(obj.Radius.Value)
    if t == "Part::Cylinder":
        _full_angles(obj, (("Angle", 360),))
        h = obj.Height.Value
        return frepcore.cylinder(obj.Radius.Value, h, center=(0, 0, h / 2))
    if t == "Part::Cone":
        _full_angles(obj, (("Angle", 360),))
        return frepcore.cone(obj.Radius1.Value, obj.Radius2.Value, obj.Height.Value)
    if t == "Part::Torus":
        _full_angles(obj, (("Angle1", -180), ("Angle2", 180), ("Angle3", 360)))
        return frepcore.torus(obj.Radius1.Value, obj.Radius2.Value)
    if t == "Part::Ellipsoid":
        _full_angles(obj, (("Angle1", -90), ("Angle2", 90), ("Angle3", 360)))
        # FreeCAD: Radius1 along z, Radius2 along x, Radius3 along y (0 means Radius2).
        r1, r2, r3 = obj.Radius1.Value, obj.Radius2.Value, obj.Radius3.Value
        return frepcore.ellipsoid((r2, r3 if r3 > 0 else r2, r1))
    raise ValueError("%s is not a supported Part primitive" % describe(obj))
