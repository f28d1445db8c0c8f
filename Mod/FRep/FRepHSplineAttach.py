"""Attachments in FreeCAD (seed 003, 2.4): an Attachment feature (a Mesh feature) joining a
cylinder hspline to a parent hspline around a rectangle of the parent's level-0 CVs, through
a Catmull-Clark seam (frepcore.attach_cylinder). It links both hsplines, so editing either
recomputes the joined surface.

Scripting:
    import FRepHSplineAttach as A
    body = H.make_plane(doc, 10, 10, 90, 90)
    limb, joint = A.attach_new_cylinder(doc, body, (3, 6, 3, 6), rows=5, height=30)
    doc.recompute()
"""

import FreeCAD

import FRepHSpline as H
import FRepMeshing
from FRepPaths import frepcore
from FRepErrors import one_line_errors
from FRepProxy import FeatureProxy

GROUP = "Attachment"


def ring(rect):
    """The parent CVs around rectangle (i0, i1, j0, j1), in the order a cylinder's CVs go
    around: +i, +j, -i, -j from (i0, j0)."""
    i0, i1, j0, j1 = rect
    return ([(i, j0) for i in range(i0, i1)] + [(i1, j) for j in range(j0, j1)] +
            [(i, j1) for i in range(i1, i0, -1)] + [(i0, j) for j in range(j1, j0, -1)])


def with_level(parent, level):
    """The parent's hierarchy with a grid on `level` (made by knot insertion where it has no
    such level: the surface does not change), as the attachment's seam uses it."""
    h = H._shared(parent)
    return h if h.level_count > level else h.with_level(level)


def convert_rectangle(parent, rect, from_level, to_level):
    """The rectangle of one level's grid nearest, by its corners' parameters, to a rectangle
    of another's."""
    h = with_level(parent, max(from_level, to_level))
    nu, nv = h.grid_size(to_level)
    i0, i1, j0, j1 = rect
    (u0, v0), (u1, v1) = h.reference(from_level, i0, j0), h.reference(from_level, i1, j1)
    near_u = lambda u: min(range(nu), key=lambda i: abs(h.reference(to_level, i, 0)[0] - u))
    near_v = lambda v: min(range(nv), key=lambda j: abs(h.reference(to_level, 0, j)[1] - v))
    return (near_u(u0), near_u(u1), near_v(v0), near_v(v1))


def cylinder_over_ring(parent, rect, rows=5, height=30.0, taper=0.7, level=0):
    """A cylinder hspline whose CV k stands over ring CV k (of the parent's `level`): row 1 on
    the ring, the rows above it evenly up to `height` along the parent's normal there, round,
    `taper` times the ring's mean radius; row 0 below (it is dropped by the attachment)."""
    h = with_level(parent, level)
    points = [FreeCAD.Vector(*h.position(level, i, j)) for i, j in ring(rect)]
    centre = sum(points, FreeCAD.Vector()) * (1.0 / len(points))
    i0, i1, j0, j1 = rect
    u, v = h.reference(level, (i0 + i1) // 2, (j0 + j1) // 2)
    normal = FreeCAD.Vector(*h.evaluate(u, v)["normal"])
    # Above the ring the rows are round (a ring around a rectangle is not): each CV keeps
    # its ring CV's direction from the centre, at `taper` times the ring's mean radius.
    flat = [(p - centre) - normal * (p - centre).dot(normal) for p in points]
    radius = sum(f.Length for f in flat) / len(flat)
    positions = []
    for r in range(rows):
        for p, f in zip(points, flat):
            if r <= 1 or f.Length < 1e-12:
                q = centre + (p - centre) * (1.0 if r <= 1 else taper)
            else:
                q = centre + f * (taper * radius / f.Length)
            q = q + normal * (height * (r - 1) / (rows - 2))
            positions.append((q.x, q.y, q.z))
    n = len(points)
    knots_v = [0, 0, 0] + list(range(rows - 2)) + [rows - 3] * 3
    return frepcore.HSpline.from_grid(list(range(n)), float(n), knots_v, 0.0, positions)


class AttachmentFeature(FeatureProxy):
    # what its view provider (the FRep features' own) asks: the icon, the tree's children
    # and the task panel's fields (none: its settings are in the property view)
    FREP_TYPE = "hspline_attachment"

    def category(self):
        return "hspline"

    def inputs(self, obj):
        return [o for o in (obj.Parent, obj.Cylinder) if o is not None]

    def parameters(self):
        return []

    def setup(self, obj):
        have = obj.PropertiesList
        for name, doc in (("Parent", "The hspline the cylinder attaches to."),
                          ("Cylinder", "The cylinder hspline (periodic around), CV k over ring "
                                       "CV k.")):
            if name not in have:
                obj.addProperty("App::PropertyLink", name, GROUP, doc)
        for name, doc in (("I0", "The rectangle's first CV along u on the parent."),
                          ("I1", "Its last CV along u."),
                          ("J0", "Its first CV along v."), ("J1", "Its last CV along v.")):
            if name not in have:
                obj.addProperty("App::PropertyInteger", name, GROUP, doc)
        if "LimbHeight" not in have:
            obj.addProperty("App::PropertyLength", "LimbHeight", GROUP,
                            "The height above the ring of the cylinder the Attach command made "
                            "(its top row's); a new rectangle or seam level in its panel "
                            "rebuilds that cylinder. 0: the cylinder is the user's own and "
                            "keeps its CVs.")
        if "CloseEnd" not in have:
            obj.addProperty("App::PropertyBool", "CloseEnd", GROUP,
                            "Close the cylinder's free end with one face, rounded off by the "
                            "subdivision: on a closed parent (a torus) the result is a closed, "
                            "printable surface.")
            obj.CloseEnd = True
        if "SeamLevel" not in have:
            obj.addProperty("App::PropertyIntegerConstraint", "SeamLevel", GROUP,
                            "The parent's level the ring and the seam's net are taken on (0 to "
                            "3): each level doubles the CVs around the joint and keeps the "
                            "parent's detail up to it. I0..J1 count CVs of that level.")
            obj.SeamLevel = (0, 0, 3, 1)
        if "Subdivisions" not in have:
            obj.addProperty("App::PropertyIntegerConstraint", "Subdivisions", GROUP,
                            "Catmull-Clark steps (0 to 6): each makes four times the faces.")
            obj.Subdivisions = (3, 0, 6, 1)

    # For the Attach panel, which does not import this module.
    def parent_levels(self, obj):
        return H._shared(obj.Parent).level_count

    def parent_grid(self, obj, level=None):
        level = obj.SeamLevel if level is None else level
        return with_level(obj.Parent, level).grid_size(level)

    def tagged_rectangle(self, obj, level=None):
        """The rectangle of the parent's tagged CVs on `level` (default: the seam's); None
        when they span none."""
        return tagged_rectangle(obj.Parent, obj.SeamLevel if level is None else level)

    def set_rectangle(self, obj, rect):
        set_rectangle(obj, rect)

    def set_seam_level(self, obj, level):
        """A new seam level, the rectangle carried over to it; returns the new rectangle."""
        rect = convert_rectangle(obj.Parent, (obj.I0, obj.I1, obj.J0, obj.J1), obj.SeamLevel,
                                 level)
        obj.SeamLevel = level
        set_rectangle(obj, rect)
        return rect

    @one_line_errors
    def execute(self, obj):
        for name in ("Parent", "Cylinder"):
            if not H.is_hspline(getattr(obj, name)):
                raise ValueError("%s: property '%s' must link an HSpline" % (obj.Label, name))
        try:
            joined = frepcore.attach_cylinder(H._shared(obj.Parent), obj.I0, obj.I1, obj.J0,
                                              obj.J1, H._shared(obj.Cylinder), obj.Subdivisions,
                                              obj.CloseEnd, obj.SeamLevel)
        except ValueError as e:
            raise ValueError("%s: %s" % (obj.Label, e)) from None
        FRepMeshing.set_mesh(obj, FRepMeshing.to_freecad_mesh(joined["mesh"]))


def make_attachment(doc, parent, cylinder, rect, subdivisions=3, name="Attachment"):
    obj = doc.addObject("Mesh::FeaturePython", name)
    AttachmentFeature(obj)
    if FreeCAD.GuiUp:
        import FRepViewProviders
        FRepViewProviders.ViewProviderAttachment(obj.ViewObject)
    obj.Parent, obj.Cylinder = parent, cylinder
    obj.I0, obj.I1, obj.J0, obj.J1 = rect
    obj.Subdivisions = subdivisions
    for o in (parent, cylinder):
        o.Visibility = False
    return obj


def attach_new_cylinder(doc, parent, rect, rows=5, height=30.0, subdivisions=3, level=0):
    """A new cylinder hspline of `rows` rows (4 or more) standing `height` high on the ring
    around `rect` (CVs of the parent's `level`, the seam's), and the Attachment joining them.
    Returns (cylinder feature, attachment)."""
    if rows < 4:
        raise ValueError("%s: a limb needs 4 rows of CVs or more, not %d" % (parent.Label, rows))
    check_rectangle(parent, rect, level=level)
    limb = H.make_hspline(doc, cylinder_over_ring(parent, rect, rows, height, level=level),
                          name="Limb")
    joint = make_attachment(doc, parent, limb, rect, subdivisions)
    joint.SeamLevel = level
    joint.LimbHeight = height
    return limb, joint


def check_rectangle(parent, rect, label=None, level=0):
    """ValueError naming the rectangle's fault: it must lie inside the parent's grid on the
    seam's level and span at least one CV each way."""
    i0, i1, j0, j1 = rect
    nu, nv = with_level(parent, level).grid_size(level)
    who = label or parent.Label
    if not (0 <= i0 < i1 < nu):
        raise ValueError("%s: the rectangle's CVs along u must satisfy 0 <= I0 < I1 <= %d, "
                         "not I0 = %d, I1 = %d" % (who, nu - 1, i0, i1))
    if not (0 <= j0 < j1 < nv):
        raise ValueError("%s: the rectangle's CVs along v must satisfy 0 <= J0 < J1 <= %d, "
                         "not J0 = %d, J1 = %d" % (who, nv - 1, j0, j1))


def tagged_rectangle(parent, level=0):
    """The rectangle of the parent's tagged CVs of `level`; None when they span none."""
    tagged = [(i, j) for lv, i, j in H.tags(parent) if lv == level]
    if len({i for i, _ in tagged}) > 1 and len({j for _, j in tagged}) > 1:
        return (min(i for i, _ in tagged), max(i for i, _ in tagged),
                min(j for _, j in tagged), max(j for _, j in tagged))
    return None


def default_rectangle(parent):
    """The rectangle of the parent's tagged level-0 CVs, or a 2 x 2 one at its middle."""
    return default_placement(parent, 0)[1]


def default_placement(parent, shown_level=0):
    """(seam level, rectangle) for a new attachment: the rectangle the tagged CVs of the
    shown level span (a level up to the seam's limit of 3), else the tagged level-0 CVs',
    else 2 x 2 spans at the middle of level 0."""
    h = H._shared(parent)
    shown = h.level_count - 1 if shown_level < 0 else min(shown_level, h.level_count - 1)
    for level in ((shown, 0) if 0 < shown <= 3 else (0,)):
        rect = tagged_rectangle(parent, level)
        if rect is not None:
            return level, rect
    nu, nv = h.grid_size(0)
    return 0, (nu // 2 - 1, nu // 2 + 1, nv // 2 - 1, nv // 2 + 1)


def default_height(parent):
    """A limb a third of the parent's size high."""
    return round(max(parent.Shape.BoundBox.DiagonalLength / 3.0, 1e-3), 3)


def set_rectangle(obj, rect):
    """A new rectangle for an attachment; the cylinder the command made is built again over
    the new ring (one the user gave keeps its CVs: its CV count must match the ring)."""
    check_rectangle(obj.Parent, rect, obj.Label, obj.SeamLevel)
    if obj.LimbHeight > 0 and H.is_hspline(obj.Cylinder):
        rows = H._shared(obj.Cylinder).grid_size(0)[1]  # (as many rows as it had)
        H.store(obj.Cylinder, cylinder_over_ring(obj.Parent, rect, rows, float(obj.LimbHeight),
                                                 level=obj.SeamLevel))
        obj.Cylinder.touch()
    obj.I0, obj.I1, obj.J0, obj.J1 = rect
