"""Lattice deformation in FreeCAD: a Lattice feature (seed 002's FFD lattice, editable in the 3D
view) and a Deform feature that applies it to an FRep solid, a FreeCAD solid or a mesh.

- Lattice: a Part::FeaturePython drawn as its control net (edges between neighbouring control
  points, a vertex per point). The rest box comes from its Target's bounding box grown by
  Margin, or from RestMin/RestMax when there is no target. The deformation is stored as
  Offsets, one displacement per control point from its rest position (index i along x slowest,
  k along z fastest), so it follows the target when the target changes size; Amount scales
  every offset (0: the rest lattice, 1: as edited) and is what expressions and spreadsheets
  drive to animate a bend. A control point can also get a property of its own
  (expose_point: `Point_i_j_k`, a vector offset in the group "Control points") so that an
  expression or a spreadsheet drives it, e.g. `Point_1_0_1.z = Controls.lift`. Double-click the
  lattice to drag control points (each drag one undo step).
- Deform: the `ffd` node over its Base with the rest box, divisions and points taken from its
  Lattice, so FRep solids, Part solids and volumes are pulled back through the lattice's
  inverse (exact, no gaps). A plain Mesh feature as Base is deformed vertex by vertex instead
  (forward map), its result checked like any mesh.

Scripting:
    import FRepLattice
    lattice = FRepLattice.make_lattice(doc, target=part, divisions=(3, 1, 1))
    FRepLattice.move_point(lattice, (1, 0, 0), (0, 0, 0.5))   # by an offset
    bent = FRepLattice.make_deform(doc, part, lattice)
    doc.recompute()
"""

import FreeCAD

import FRepFeatures
import FRepMeshing
import FRepProperties as props
import FRepSolids
import FRepTree
from FRepPaths import frepcore
from FRepErrors import one_line_errors
from FRepProxy import FeatureProxy

GROUP = "Lattice"
MAX_DIVISIONS = 64
FFD_PARAMS = ("rest_min", "rest_max", "divisions_x", "divisions_y", "divisions_z", "points")


def is_lattice(obj):
    return isinstance(getattr(obj, "Proxy", None), LatticeFeature)


def _target_box(obj):
    """The bounding box of what the lattice is fitted to, in document coordinates."""
    t = obj.Target
    if FRepTree.is_frep_feature(t):
        bounds = FRepTree.shape_of(t).bounds()
        if bounds["empty"] or not bounds["bounded"]:
            raise ValueError("%s: its target '%s' has no finite extent to fit the lattice to; "
                             "set Target empty and give RestMin and RestMax" % (obj.Label, t.Label))
        lo, hi = bounds["box"]
        return FreeCAD.BoundBox(FreeCAD.Vector(*lo), FreeCAD.Vector(*hi))
    if t.isDerivedFrom("Mesh::Feature"):
        return t.Mesh.BoundBox
    if hasattr(t, "Shape") and not t.Shape.isNull():
        return t.Shape.BoundBox
    raise ValueError("%s: its target '%s' (%s) has no shape or mesh to fit the lattice to"
                     % (obj.Label, t.Label, t.TypeId))


POINT_GROUP = "Control points"


def point_property(i, j, k):
    """The name of control point (i, j, k)'s own offset property (expose_point)."""
    return "Point_%d_%d_%d" % (i, j, k)


def exposed_points(obj):
    """{(i, j, k): property name} of the control points with a property of their own."""
    out = {}
    d = divisions(obj)
    for name in obj.PropertiesList:
        if name.startswith("Point_") and obj.getGroupOfProperty(name) == POINT_GROUP:
            try:
                ijk = tuple(int(v) for v in name[6:].split("_"))
            except ValueError:
                continue
            if len(ijk) == 3 and all(0 <= ijk[a] <= d[a] for a in range(3)):
                out[ijk] = name
    return out


def divisions(obj):
    return (obj.DivisionsX, obj.DivisionsY, obj.DivisionsZ)


def point_count(obj):
    d = divisions(obj)
    return (d[0] + 1) * (d[1] + 1) * (d[2] + 1)


def point_index(obj, i, j, k):
    d = divisions(obj)
    return (i * (d[1] + 1) + j) * (d[2] + 1) + k


class LatticeFeature(FeatureProxy):
    def setup(self, obj):
        add = obj.addProperty
        have = obj.PropertiesList
        if "Target" not in have:
            add("App::PropertyLink", "Target", GROUP,
                "The object the rest box is fitted to (its bounding box grown by Margin); "
                "empty: the rest box is RestMin to RestMax.")
        if "Margin" not in have:
            add("App::PropertyFloat", "Margin", GROUP,
                "How far the rest box reaches beyond the target, as a fraction of the "
                "target's largest side (keep the solid inside the rest box).")
            obj.Margin = 0.05
        for name, default in (("RestMin", (-1, -1, -1)), ("RestMax", (1, 1, 1))):
            if name not in have:
                add("App::PropertyVector", name, GROUP,
                    "The rest box's %s corner (fitted to the target when there is one)."
                    % ("lowest" if name == "RestMin" else "highest"))
                setattr(obj, name, FreeCAD.Vector(*default))
        for axis in "XYZ":
            name = "Divisions" + axis
            if name not in have:
                add("App::PropertyIntegerConstraint", name, GROUP,
                    "Lattice cells along %s (control points: one more); 1 to %d. Changing it "
                    "resets the offsets." % (axis.lower(), MAX_DIVISIONS))
                setattr(obj, name, (2, 1, MAX_DIVISIONS, 1))
        if "Offsets" not in have:
            add("App::PropertyVectorList", "Offsets", GROUP,
                "How far each control point is moved from its rest position (i along x "
                "slowest, k along z fastest); empty: the undeformed lattice.")
        if "Amount" not in have:
            add("App::PropertyFloat", "Amount", GROUP,
                "Scales every offset: 0 the rest lattice, 1 the lattice as edited. Drive it "
                "with an expression or a spreadsheet to animate the deformation.")
            obj.Amount = 1.0

    def onChanged(self, obj, prop):
        if "Restore" in obj.State:
            return
        if prop in ("DivisionsX", "DivisionsY", "DivisionsZ") and getattr(obj, "Offsets", None) and \
                len(obj.Offsets) != point_count(obj):
            obj.Offsets = []
            FreeCAD.Console.PrintWarning("%s: the divisions changed, so the lattice is back at "
                                         "rest (its offsets no longer matched)\n" % obj.Label)
        if prop == "Target":
            mode = 1 if obj.Target is not None else 0  # fitted corners are read-only
            obj.setEditorMode("RestMin", mode)
            obj.setEditorMode("RestMax", mode)

    # -- the lattice --------------------------------------------------------------------------
    def rest_box(self, obj):
        """(rest_min, rest_max) as tuples: fitted to the target, or the properties."""
        if obj.Target is None:
            lo, hi = tuple(obj.RestMin), tuple(obj.RestMax)
        else:
            b = _target_box(obj)
            pad = max(b.XLength, b.YLength, b.ZLength) * max(obj.Margin, 0.0)
            pad = pad if pad > 0 else 1e-3
            lo = (b.XMin - pad, b.YMin - pad, b.ZMin - pad)
            hi = (b.XMax + pad, b.YMax + pad, b.ZMax + pad)
        bad = [a for a in range(3) if not lo[a] < hi[a]]
        if bad:
            raise ValueError("%s: the rest box is empty along %s; RestMax must exceed RestMin on "
                             "every axis" % (obj.Label, "xyz"[bad[0]]))
        return lo, hi

    def lattice(self, obj):
        """The lattice as a frepcore.Lattice (offsets scaled by Amount)."""
        lo, hi = self.rest_box(obj)
        rest = frepcore.Lattice(lo, hi, divisions(obj))
        offsets = list(obj.Offsets)
        exposed = exposed_points(obj)
        if not offsets and not exposed:
            return rest
        if not offsets:
            offsets = [FreeCAD.Vector()] * point_count(obj)
        if len(offsets) != point_count(obj):
            raise ValueError("%s: property 'Offsets' has %d vectors; a %d x %d x %d lattice has %d "
                             "control points (or leave it empty)" % (
                                 obj.Label, len(offsets), obj.DivisionsX, obj.DivisionsY,
                                 obj.DivisionsZ, point_count(obj)))
        for ijk, name in exposed.items():  # a point's own property wins over Offsets
            offsets[point_index(obj, *ijk)] = getattr(obj, name)
        a = obj.Amount
        points = [(p[0] + a * o.x, p[1] + a * o.y, p[2] + a * o.z)
                  for p, o in zip(rest.rest_points(), offsets)]
        return frepcore.Lattice(lo, hi, divisions(obj), points)

    # For the edit panel and the draggers, which do not import this module.
    def expose_point(self, obj, index):
        return expose_point(obj, index)

    def nudge_point(self, obj, index, delta):
        """Moves control point (i, j, k) by delta (an offset change, one property change)."""
        move_point(obj, index, point_offset(obj, index) + FreeCAD.Vector(delta))

    @one_line_errors
    def execute(self, obj):
        import Part
        lattice = self.lattice(obj)
        fold = lattice.find_fold()
        if fold:
            raise ValueError("%s: %s" % (obj.Label, fold))
        d = divisions(obj)
        pts = [FreeCAD.Vector(*p) for p in lattice.points]

        def at(i, j, k):
            return pts[(i * (d[1] + 1) + j) * (d[2] + 1) + k]

        edges = []
        for i in range(d[0] + 1):
            for j in range(d[1] + 1):
                for k in range(d[2] + 1):
                    for di, dj, dk in ((1, 0, 0), (0, 1, 0), (0, 0, 1)):
                        if i + di <= d[0] and j + dj <= d[1] and k + dk <= d[2]:
                            a, b = at(i, j, k), at(i + di, j + dj, k + dk)
                            if (a - b).Length > 1e-12:
                                edges.append(Part.LineSegment(a, b).toShape())
        vertices = [Part.Vertex(p) for p in pts]
        obj.Shape = Part.Compound(edges + vertices)


def make_lattice(doc, target=None, divisions=(2, 2, 2), margin=0.05, rest=None, name="Lattice"):
    """A Lattice feature fitted to target (or spanning rest = (min, max))."""
    obj = doc.addObject("Part::FeaturePython", name)
    LatticeFeature(obj)
    if FreeCAD.GuiUp:
        import FRepLatticeView
        FRepLatticeView.ViewProviderLattice(obj.ViewObject)
    obj.DivisionsX, obj.DivisionsY, obj.DivisionsZ = divisions
    obj.Margin = margin
    if rest is not None:
        obj.RestMin, obj.RestMax = FreeCAD.Vector(*rest[0]), FreeCAD.Vector(*rest[1])
    if target is not None:
        obj.Target = target
    return obj


def _require_point(lattice_obj, index):
    i, j, k = index
    d = divisions(lattice_obj)
    if not (0 <= i <= d[0] and 0 <= j <= d[1] and 0 <= k <= d[2]):
        raise ValueError("%s: control point (%d, %d, %d) does not exist; allowed: (0...%d, "
                         "0...%d, 0...%d)" % (lattice_obj.Label, i, j, k, d[0], d[1], d[2]))


def expose_point(lattice_obj, index):
    """Gives control point (i, j, k) a vector property of its own (its offset, starting from
    the current one) that expressions and spreadsheets can drive; returns its name."""
    _require_point(lattice_obj, index)
    name = point_property(*index)
    if name not in lattice_obj.PropertiesList:
        current = list(lattice_obj.Offsets)
        start = current[point_index(lattice_obj, *index)] if current else FreeCAD.Vector()
        lattice_obj.addProperty("App::PropertyVector", name, POINT_GROUP,
                                "Control point (%d, %d, %d)'s offset from its rest position; "
                                "it takes the place of its entry in Offsets" % tuple(index))
        setattr(lattice_obj, name, start)
    return name


def point_offset(lattice_obj, index):
    """Control point (i, j, k)'s offset from its rest position, before Amount scales it."""
    _require_point(lattice_obj, index)
    name = point_property(*index)
    if name in exposed_points(lattice_obj).values():
        return FreeCAD.Vector(getattr(lattice_obj, name))
    offsets = list(lattice_obj.Offsets)
    return FreeCAD.Vector(offsets[point_index(lattice_obj, *index)]) if offsets else FreeCAD.Vector()


def move_point(lattice_obj, index, offset):
    """Sets control point (i, j, k)'s offset from its rest position (one property change):
    its own property when it has one (expose_point), else its entry in Offsets."""
    i, j, k = index
    _require_point(lattice_obj, index)
    name = point_property(i, j, k)
    if name in exposed_points(lattice_obj).values():
        setattr(lattice_obj, name, FreeCAD.Vector(*offset))
        return
    offsets = list(lattice_obj.Offsets) or [FreeCAD.Vector()] * point_count(lattice_obj)
    offsets[point_index(lattice_obj, i, j, k)] = FreeCAD.Vector(*offset)
    lattice_obj.Offsets = offsets


_FFD = FRepFeatures.FEATURE_CLASSES["ffd"]


class DeformFeature(_FFD):
    """The ffd node with its lattice from a Lattice feature; a plain mesh is deformed
    vertex by vertex."""

    def setup(self, obj):
        super().setup(obj)
        if "Lattice" not in obj.PropertiesList:
            obj.addProperty("App::PropertyLink", "Lattice", props.INPUT_GROUP,
                            "The Lattice feature that deforms the input.")
        # the lattice's own values are the Lattice feature's business
        for p in FFD_PARAMS:
            obj.setEditorMode(props.property_name(p), 2)
        obj.setEditorMode("PointsSource", 2)

    def inputs(self, obj):
        return [i for i in (obj.Base, obj.Lattice) if i is not None]

    def _lattice(self, obj):
        if obj.Lattice is None or not is_lattice(obj.Lattice):
            raise ValueError("%s: property 'Lattice' must link a Lattice feature (FRep > Lattice)"
                             % obj.Label)
        return obj.Lattice.Proxy.lattice(obj.Lattice)

    def param_value(self, obj, param):
        if param["name"] not in FFD_PARAMS:
            return super().param_value(obj, param)
        lattice = self._lattice(obj)
        d = lattice.divisions
        return {"rest_min": lattice.rest_min, "rest_max": lattice.rest_max,
                "divisions_x": d[0], "divisions_y": d[1], "divisions_z": d[2],
                "points": lattice.points}[param["name"]]

    def mesh_input(self, obj):
        """The Base when it is a plain mesh (deformed vertex by vertex), else None."""
        b = obj.Base
        if b is not None and not FRepTree.is_frep_feature(b) and b.isDerivedFrom("Mesh::Feature"):
            return b
        return None

    def local_shape(self, obj, builder):
        if self.mesh_input(obj) is not None:
            # downstream FRep operations see the deformed mesh's exact signed distance
            return FRepSolids.solid_shape(obj)
        return super().local_shape(obj, builder)

    @one_line_errors
    def execute(self, obj):
        mesh_base = self.mesh_input(obj)
        if mesh_base is None:
            return super().execute(obj)
        FRepFeatures.EXECUTIONS.append((obj.Document.Name, obj.Name))
        lattice = self._lattice(obj)
        if mesh_base.Mesh.CountFacets == 0:
            raise ValueError("%s: the mesh '%s' is empty" % (obj.Label, mesh_base.Label))
        source = FRepSolids.as_frepcore_mesh(mesh_base.Mesh)
        deformed = FRepMeshing.run_with_progress(
            "Deforming %s" % mesh_base.Label,
            lambda progress: frepcore.deform_mesh(source, lattice, progress))
        obj.Placement = FreeCAD.Placement()  # the points are in document coordinates
        FRepMeshing.set_mesh(obj, FRepMeshing.to_freecad_mesh(deformed))


def make_deform(doc, base, lattice_obj, name="Deform"):
    """A Deform feature: base (an FRep feature, a solid or a mesh) bent by the Lattice."""
    obj = doc.addObject("Mesh::FeaturePython", name)
    DeformFeature(obj)
    if FreeCAD.GuiUp:
        import FRepViewProviders
        FRepViewProviders.ViewProviderFRep(obj.ViewObject)
    FRepFeatures.set_inputs(obj, [base])
    obj.Lattice = lattice_obj
    base.Visibility = False
    return obj
