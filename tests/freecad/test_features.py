"""FRep features in a headless FreeCAD document: creation from the registry, persistence,
undo, recompute scope, expressions, Bypass and cycle refusal."""

import math
import os

import FreeCAD
import pytest

import FRepExamples
import FRepFeatures as F
import FRepMeshing
import FRepProperties as P
import FRepTree
from FRepPaths import frepcore


def mesh_signature(mesh):
    return (mesh.CountPoints, mesh.CountFacets,
            tuple(round(c, 6) for p in mesh.Points for c in (p.x, p.y, p.z)),
            tuple(mesh.Topology[1]))


def sample_file_params(type_id, folder):
    """A file for the types that read one (mesh_sdf, vdb_grid): a ball written by frepcore."""
    ball = frepcore.sphere(1.0)
    if type_id == "mesh_sdf":
        path = os.path.join(str(folder), "ball.stl")
        ball.export(path, cells=24)
        return {"path": path}
    if type_id == "vdb_grid":
        path = os.path.join(str(folder), "ball.vdb")
        ball.to_vdb(path, cells=24)
        return {"path": path}
    return {}


@pytest.mark.parametrize("type_id", sorted(F.NODE_TYPES))
def test_every_registry_type_is_a_feature(doc, type_id, tmp_path):
    info = F.NODE_TYPES[type_id]
    inputs = [F.make("sphere", doc, center=(0.3 * i, 0, 0)) for i in range(info["inputs"]["min"])]
    obj = F.make(type_id, doc, inputs=inputs, **sample_file_params(type_id, tmp_path))
    doc.recompute()
    assert obj.isValid(), obj.getStatusString()
    assert obj.Proxy.FREP_TYPE == type_id
    for p in info["params"]:
        name = P.property_name(p["name"])
        assert name in obj.PropertiesList
        assert obj.getTypeIdOfProperty(name) == P.property_type(p)
        assert p["doc"] in obj.getDocumentationOfProperty(name)
    assert ("Bypass" in obj.PropertiesList) == (info["inputs"]["min"] > 0)
    assert obj.Mesh.CountFacets > 0  # visible: it has a preview


def test_save_reopen_recompute_gives_identical_mesh(doc, tmp_path):
    part = FRepExamples.build_csg(doc)
    doc.recompute()
    before = mesh_signature(part.Mesh)
    path = str(tmp_path / "csg.FCStd")
    doc.saveAs(path)
    FreeCAD.closeDocument(doc.Name)
    reopened = FreeCAD.openDocument(path)
    try:
        part = reopened.getObject("Part")
        assert isinstance(part.Proxy, F.FEATURE_CLASSES["difference"])
        assert mesh_signature(part.Mesh) == before  # saved with the document
        for o in reopened.Objects:
            o.touch()
        reopened.recompute()
        assert part.isValid(), part.getStatusString()
        assert mesh_signature(part.Mesh) == before  # and rebuilt identically
    finally:
        FreeCAD.closeDocument(reopened.Name)


def test_undo_redo_parameter_change(doc):
    doc.UndoMode = 1
    s = F.make("sphere", doc, radius=1)
    doc.recompute()
    v1 = s.Mesh.Volume
    doc.openTransaction("radius")
    s.Radius = 2
    doc.commitTransaction()
    doc.recompute()
    v2 = s.Mesh.Volume
    assert v2 > 7 * v1
    doc.undo()
    doc.recompute()
    assert s.Radius.Value == 1
    assert s.Mesh.Volume == pytest.approx(v1, rel=1e-6)
    doc.redo()
    doc.recompute()
    assert s.Radius.Value == 2
    assert s.Mesh.Volume == pytest.approx(v2, rel=1e-6)


def test_leaf_change_recomputes_only_its_chain(doc):
    FRepExamples.build_csg(doc)
    doc.recompute()
    F.EXECUTIONS.clear()
    doc.getObject("Ball").Radius = 1.25
    doc.recompute()
    assert [n for _, n in F.EXECUTIONS] == ["Ball", "Core", "Part"]
    F.EXECUTIONS.clear()
    doc.getObject("HoleZ").Radius = 0.4
    doc.recompute()
    assert [n for _, n in F.EXECUTIONS] == ["HoleZ", "Part"]


def test_expression_driven_parameter_over_ten_frames(doc):
    sheet = doc.addObject("Spreadsheet::Sheet", "Anim")
    sheet.set("A1", "0")
    sheet.setAlias("A1", "frame")
    a = F.make("sphere", doc, radius=1)
    b = F.make("sphere", doc, radius=0.8)
    blend = F.make("blend_union", doc, inputs=[a, b])
    b.setExpression("Center.x", "0.5 + Anim.frame * 0.15")
    volumes = []
    for frame in range(10):
        sheet.set("frame", str(frame))
        doc.recompute()
        assert blend.isValid(), blend.getStatusString()
        volumes.append(blend.Mesh.Volume)
    assert len(set(round(v, 6) for v in volumes)) == 10
    # The spheres move apart: the blended volume grows until they separate.
    assert volumes[-1] > volumes[0]


def test_bypass_passes_first_input_through(doc):
    s = F.make("sphere", doc, radius=1)
    t = F.make("translate", doc, inputs=[s], offset=(5, 0, 0))
    doc.recompute()
    assert t.Mesh.BoundBox.Center.x == pytest.approx(5, abs=0.05)
    t.Bypass = True
    doc.recompute()
    assert t.Mesh.BoundBox.Center.x == pytest.approx(0, abs=0.05)
    d = F.make("difference", doc, inputs=[F.make("box", doc), F.make("sphere", doc)])
    d.Bypass = True
    doc.recompute()
    assert d.Mesh.Volume == pytest.approx(1.0, rel=0.02)  # the unit box, unchanged


def test_link_making_a_cycle_is_refused(doc):
    a, b = F.make("sphere", doc), F.make("box", doc)
    u = F.make("union", doc, inputs=[a, b])
    t = F.make("translate", doc, inputs=[u])
    with pytest.raises(ValueError, match="would make a cycle"):
        F.set_inputs(u, [a, t])
    assert list(u.Shapes) == [a, b]
    # Assigning the property directly is reverted, with the message in the report view.
    u.Shapes = [a, t]
    assert list(u.Shapes) == [a, b]
    t.Base = t
    assert t.Base == u
    doc.recompute()
    assert u.isValid() and t.isValid()


def test_shared_input_and_deep_chain(doc):
    s = F.make("sphere", doc, radius=0.5)
    shape = s
    for i in range(20):
        shape = F.make("translate", doc, inputs=[shape], offset=(0.1, 0, 0))
    both = F.make("union", doc, inputs=[shape, s], hide_inputs=False)
    doc.recompute()
    assert both.isValid(), both.getStatusString()
    tree = FRepTree.shape_of(both)
    assert tree(2.0, 0, 0) > 0 and tree(0, 0, 0) > 0


def test_preview_resolution_is_per_document(doc):
    s = F.make("sphere", doc)
    doc.recompute()
    coarse = s.Mesh.CountFacets
    FRepMeshing.set_preview_cells(doc, 2 * FRepMeshing.preview_cells(doc))
    assert s.Mesh.CountFacets > 3 * coarse
    with pytest.raises(ValueError, match="allowed: 4 to 4096"):
        FRepMeshing.set_preview_cells(doc, 1)


def test_hidden_feature_gets_its_preview_when_shown(doc):
    s = F.make("sphere", doc)
    t = F.make("translate", doc, inputs=[s])
    doc.recompute()
    assert s.Visibility is False and s.Mesh.CountFacets == 0
    F.EXECUTIONS.clear()
    s.Visibility = True
    assert s.Mesh.CountFacets > 0
    assert [n for _, n in F.EXECUTIONS] == ["Sphere"]  # not its dependents
    assert "Touched" not in t.State


def test_frepcore_tree_matches_json_reference(doc):
    part = FRepExamples.build_csg(doc)
    doc.recompute()
    reference, _ = frepcore.load(os.path.join(os.environ["FREP_SOURCE_DIR"], "examples",
                                              "csg.json"))
    tree = FRepTree.shape_of(part)
    points = [(x * 0.37, y * 0.41, z * 0.29) for x in range(-4, 5) for y in range(-4, 5)
              for z in range(-4, 5)]
    assert tree.values(points) == reference.values(points)


def test_preview_hand_over_matches_freecads_own_topology(doc, tmp_path):
    """The preview reaches FreeCAD as a .bms with frepcore's facet neighbours; they must be
    exactly those FreeCAD computes itself from the same triangles (read from a PLY)."""
    import Mesh
    shape = FRepTree.shape_of(FRepExamples.build_csg(doc))
    mesh = shape.mesh(cells=40)
    ply, ours, theirs = (str(tmp_path / n) for n in ("m.ply", "ours.bms", "theirs.bms"))
    mesh.write(ply, "ply")
    Mesh.Mesh(ply).write(theirs)
    FRepMeshing.to_freecad_mesh(mesh).write(ours)
    with open(ours, "rb") as a, open(theirs, "rb") as b:
        assert a.read() == b.read()
    assert FRepMeshing.to_freecad_mesh(mesh).isSolid()


def test_parameter_properties_do_not_clash_with_the_features_own(doc):
    """A registry parameter named like an input link or a FreeCAD property would overwrite
    it (taper's start point was once called 'base', colliding with the link 'Base')."""
    reserved = {"Base", "Shapes", "Bypass", "Placement", "Label", "Label2", "Mesh",
                "Visibility", "ExpressionEngine", "Proxy"}
    for type_id, info in F.NODE_TYPES.items():
        names = {P.property_name(p["name"]) for p in info["params"]}
        taken = reserved if F.input_property(info) else reserved - {"Base", "Shapes"}
        assert not names & taken, (type_id, names & taken)


def test_sweep_follows_a_sketch(doc):
    """A sweep's PointsSource takes the path from a sketch (any edge or wire works)."""
    import Part
    import Sketcher
    sketch = doc.addObject("Sketcher::SketchObject", "Path")
    sketch.addGeometry(Part.LineSegment(FreeCAD.Vector(0, 0, 0), FreeCAD.Vector(2, 0, 0)))
    sketch.addGeometry(Part.ArcOfCircle(Part.Circle(FreeCAD.Vector(2, 1, 0),
                                                    FreeCAD.Vector(0, 0, 1), 1),
                                        -math.pi / 2, 0))
    sketch.addConstraint(Sketcher.Constraint("Coincident", 0, 2, 1, 1))
    doc.recompute()
    sweep = F.make("sweep", doc, radius1=0.25, radius2=0.25)
    sweep.PointsSource = sketch
    doc.recompute()
    assert sweep.isValid(), sweep.getStatusString()
    shape = FRepTree.shape_of(sweep)
    # On the straight part the field is exactly r - distance; on the arc within sampling.
    assert shape(1.0, 0.1, 0.0) == pytest.approx(0.15, abs=1e-9)
    assert shape(3.0, 1.0, 0.0) == pytest.approx(0.25, abs=2e-3)  # the arc's end
    assert shape(2 + math.cos(-0.7), 1 + math.sin(-0.7), 0.1) == pytest.approx(0.15, abs=3e-3)
    assert sweep.Mesh.CountFacets > 0
    # With segments "arcs" the line and the arc are followed exactly.
    sweep.Segments = "arcs"
    doc.recompute()
    assert sweep.isValid(), sweep.getStatusString()
    shape = FRepTree.shape_of(sweep)
    for t in (-1.5, -1.0, -0.7, -0.2, 0.0):
        p = (2 + 1.1 * math.cos(t), 1 + 1.1 * math.sin(t), 0.05)
        assert shape(*p) == pytest.approx(0.25 - math.hypot(0.1, 0.05), abs=1e-9), t
    assert shape(1.0, 0.1, 0.0) == pytest.approx(0.15, abs=1e-9)
    # a whole circle (a sketch circle) is swept as two exact halves: a torus
    ring = doc.addObject("Sketcher::SketchObject", "Ring")
    ring.addGeometry(Part.Circle(FreeCAD.Vector(0, 0, 0), FreeCAD.Vector(0, 0, 1), 2))
    doc.recompute()
    sweep.PointsSource = ring
    doc.recompute()
    assert sweep.isValid(), sweep.getStatusString()
    shape = FRepTree.shape_of(sweep)
    for t in (0.3, 2.0, 4.0, 5.9):
        assert shape(2.1 * math.cos(t), 2.1 * math.sin(t), 0) == pytest.approx(0.15, abs=1e-9)
    # An object without edges is refused with the property named.
    ball = F.make("sphere", doc, name="Ball")
    sweep.PointsSource = ball
    doc.recompute()
    assert not sweep.isValid()
    assert ("Sweep: property 'PointsSource' links 'Ball' (Mesh::FeaturePython), which has no "
            "edges" in sweep.getStatusString())


def test_formula_feature_reports_the_column_and_combines_inputs(doc):
    """A formula is a feature with text properties; a typo names the property and the column,
    is fixed in place, and the inputs are the fields f1, f2, ..."""
    f = F.make("formula", doc, name="Bumps")
    doc.recompute()
    assert f.isValid(), f.getStatusString()
    assert f.Mesh.CountFacets > 0
    f.Formula = "r - sqrt(x^2 + y^2 + z^2) + a*sinn(k*x)"
    doc.recompute()
    assert not f.isValid()
    message = f.getStatusString()
    assert message.startswith("Bumps: property 'Formula' column 31: unknown function 'sinn'")
    assert message.endswith("\n  r - sqrt(x^2 + y^2 + z^2) + a*sinn(k*x)\n" + " " * 32 + "^")
    f.Formula = "r - sqrt(x^2 + y^2 + z^2)"
    f.Parameters = "r = 0.5 * 3"
    doc.recompute()
    assert f.isValid(), f.getStatusString()
    assert FRepTree.shape_of(f)(1.5, 0, 0) == pytest.approx(0, abs=1e-12)

    # a spreadsheet drives a parameter through an expression on the text property
    sheet = doc.addObject("Spreadsheet::Sheet", "Sheet")
    sheet.set("A1", "0.7")
    sheet.setAlias("A1", "R")
    f.setExpression("Parameters", "<<r = %s>> % Sheet.R")
    doc.recompute()
    assert f.Parameters == "r = 0.7"
    assert FRepTree.shape_of(f)(0.7, 0, 0) == pytest.approx(0, abs=1e-12)
    sheet.set("A1", "0.9")
    doc.recompute()
    assert FRepTree.shape_of(f)(0.9, 0, 0) == pytest.approx(0, abs=1e-12)

    a = F.make("sphere", doc, name="A", center=(-0.5, 0, 0))
    b = F.make("box", doc, name="B")
    join = F.make("formula", doc, name="Join", inputs=[a, b], formula="max(f1, f2)",
                  parameters="")
    doc.recompute()
    assert join.isValid(), join.getStatusString()
    s, sa, sb = (FRepTree.shape_of(o) for o in (join, a, b))
    for p in ((0, 0, 0), (-1.2, 0.3, 0.1), (0.9, 0.9, 0.9), (2, 0, 0)):
        assert s(*p) == pytest.approx(max(sa(*p), sb(*p)), abs=1e-12)
    join.Formula = "max(f1, f3)"
    doc.recompute()
    assert "Join: property 'Formula' column 9: unknown name 'f3'" in join.getStatusString()
    assert "this node has 2" in join.getStatusString()


def _copies_at(instancer, ball_radius, expected):
    """The instancer is a ball at each expected point (in document coordinates)."""
    shape = FRepTree.shape_of(instancer)
    for p in expected:
        assert shape(*p) == pytest.approx(ball_radius, abs=1e-9), p


def test_instancer_along_draft_arrays_meshes_and_clouds(doc):
    """The instancer's PositionsSource: a Draft ortho array (its copies), a Draft link array
    (its placements), a polar array of a Draft point (its vertices), mesh vertices and a point
    cloud, each moved by its own Placement."""
    import Draft
    import Mesh
    import Points
    box = doc.addObject("Part::Box", "Box")
    box.Placement.Base = FreeCAD.Vector(1, 2, 3)
    doc.recompute()
    array = Draft.make_ortho_array(box, v_x=FreeCAD.Vector(10, 0, 0),
                                   v_y=FreeCAD.Vector(0, 5, 0), v_z=FreeCAD.Vector(0, 0, 1),
                                   n_x=3, n_y=2, n_z=1, use_link=False)
    links = Draft.make_ortho_array(box, v_x=FreeCAD.Vector(0, 0, 4),
                                   v_y=FreeCAD.Vector(0, 5, 0), v_z=FreeCAD.Vector(0, 0, 1),
                                   n_x=2, n_y=1, n_z=1, use_link=True)
    # The point at the origin, turned about (-2, 0, 0): FreeCAD 1.0.0's arrays place the copies
    # of a Draft point away from the origin at twice its offset (0.20 at its offset); the
    # instancer follows the points the array shows, so the test keeps to what both agree on.
    point = Draft.make_point(0, 0, 0)
    polar = Draft.make_polar_array(point, number=4, angle=360,
                                   center=FreeCAD.Vector(-2, 0, 0), use_link=False)
    import Part
    mesh = doc.addObject("Mesh::Feature", "Cube")
    mesh.Mesh = Mesh.Mesh(Part.makeBox(2, 2, 2).tessellate(0.1))
    mesh.Placement.Base = FreeCAD.Vector(0, 0, 10)
    cloud = doc.addObject("Points::Feature", "Cloud")
    cloud.Points = Points.Points([FreeCAD.Vector(5, 5, 5), FreeCAD.Vector(6, 5, 5)])
    cloud.Placement.Base = FreeCAD.Vector(1, 0, 0)
    doc.recompute()

    ball = F.make("sphere", doc, name="Ball", radius=0.5)
    copies = F.make("instancer", doc, name="Copies", inputs=[ball])
    cases = [
        (array, [(1 + 10 * i, 2 + 5 * j, 3) for i in range(3) for j in range(2)]),
        (links, [(1, 2, 3), (1, 2, 7)]),
        (polar, [(0, 0, 0), (-2, 2, 0), (-4, 0, 0), (-2, -2, 0)]),
        (mesh, [(sx, sy, 10 + sz) for sx in (0, 2) for sy in (0, 2) for sz in (0, 2)]),
        (cloud, [(6, 5, 5), (7, 5, 5)]),
    ]
    for source, expected in cases:
        copies.PositionsSource = source
        doc.recompute()
        assert copies.isValid(), (source.Label, copies.getStatusString())
        assert copies.Mesh.CountFacets > 0
        _copies_at(copies, 0.5, expected)
        # exactly one copy per point
        positions = next(p for p in F.NODE_TYPES["instancer"]["params"]
                         if p["name"] == "positions")
        n = len(copies.Proxy.param_value(copies, positions))
        assert n == len(expected), source.Label

    empty = doc.addObject("Part::Feature", "Nothing")
    # a polar array of a brick: the copies are turned as the array turns them
    brick = doc.addObject("Part::Box", "Brick")
    brick.Length, brick.Width, brick.Height = 0.6, 0.2, 0.2
    brick.Placement.Base = FreeCAD.Vector(3, 0, 0)
    doc.recompute()
    ring = Draft.make_polar_array(brick, number=4, angle=360, center=FreeCAD.Vector(0, 0, 0),
                                  use_link=False)
    doc.recompute()
    bar = F.make("box", doc, name="Bar", corner=(0, -0.1, -0.1), size=(0.6, 0.2, 0.2))
    turned = F.make("instancer", doc, name="Turned", inputs=[bar])
    turned.PositionsSource = ring
    doc.recompute()
    assert turned.isValid(), turned.getStatusString()
    shape = FRepTree.shape_of(turned)
    # the bar sticks out along +x at (3, 0), along +y at (0, 3), along -x at (-3, 0), ...
    for (x, y) in ((3.5, 0), (0, 3.5), (-3.5, 0), (0, -3.5)):
        assert shape(x, y, 0) > 0, (x, y)
    for (x, y) in ((3, 0.5), (-0.5, 3), (-3, -0.5), (0.5, -3)):
        assert shape(x, y, 0) < 0, (x, y)
    copies.PositionsSource = empty
    doc.recompute()
    assert ("Copies: property 'PositionsSource' links 'Nothing' (Part::Feature), which has no "
            "points" in copies.getStatusString())


def test_a_blend_guide_covers_where_the_blend_acts_and_its_handles_set_the_reach(doc):
    import FRepBlendReach as R
    slab = F.make("box", doc, size=(20, 20, 10), corner=(-10, -10, -10))
    post = F.make("cylinder", doc, radius=4, length=20)
    blend = F.make("blend_union", doc, inputs=[slab, post], a0=1, a1=2, a2=2)
    doc.recompute()
    g = R.guide(blend)
    # the coat lies where the added term exceeds a tenth of a0, (f1/a1)^2 + (f2/a2)^2 <= 9,
    # and on the blend's surface (within its band of 1.5 cells); meshed vertices lie on the
    # boundary of that set, within the meshing's error
    pts = g["mesh"].points
    assert g["mesh"].triangle_count > 100
    f1 = FRepTree.shape_of(slab).values(pts)
    f2 = FRepTree.shape_of(post).values(pts)
    fb = FRepTree.shape_of(blend).values(pts)
    band = 1.5 * (20 + 2 * (0.1 * math.sqrt(20 ** 2 * 2 + 20 ** 2) + 6)) / R.GUIDE_CELLS
    for a, b, c in zip(f1, f2, fb):
        assert (a / 2) ** 2 + (b / 2) ** 2 <= 9 + 0.6
        assert abs(c) <= band * 1.15
    # nowhere far from the two circles where the post passes the slab's faces
    assert max(math.hypot(p[0], p[1]) for p in pts) < 4 + 3 * 2 + 1.5
    assert g["anchor"].z == pytest.approx(0, abs=1e-6)
    assert math.hypot(g["anchor"].x, g["anchor"].y) == pytest.approx(4, abs=1e-6)
    handles = {name: (point, d) for name, point, d, _ in g["handles"]}
    assert set(handles) == {"A1", "A2"}
    # A1: up the post, 2 mm from the slab's top; A2: out along the slab's top, 2 mm from the post
    p1, d1 = handles["A1"]
    assert d1.z == pytest.approx(1, abs=1e-9) and p1.z == pytest.approx(2, abs=1e-6)
    p2, d2 = handles["A2"]
    assert d2.z == pytest.approx(0, abs=1e-9) and math.hypot(p2.x, p2.y) == pytest.approx(6, abs=1e-6)
    # dropping the A1 handle 3 mm further up sets A1 to 5; the guide grows with it
    assert R.set_reach(blend, "A1", p1 + d1 * 3) == pytest.approx(5, abs=1e-6)
    doc.recompute()
    assert blend.A1 == pytest.approx(5) and blend.isValid()
    assert max(p[2] for p in R.guide(blend)["mesh"].points) > max(p[2] for p in pts) + 2
    with pytest.raises(ValueError, match="A1 must be more than 0"):
        R.set_reach(blend, "A1", g["anchor"])


def test_strut_lattice_in_a_part_saves_reopens_and_changes_cell(doc, tmp_path):
    """An octet lattice cut to a block: a closed preview; the cell type and the radius change
    it; the document saves and reopens with the same preview."""
    lattice = F.make("strut_lattice", doc, cell_type="octet", cell=(2.0, 2.0, 2.0), radius=0.25,
                     node_radius=0.35)
    block = F.make("box", doc, corner=(0, 0, 0), size=(8.0, 6.0, 4.0))
    part = F.make("intersection", doc, inputs=[lattice, block])
    doc.recompute()
    assert part.isValid(), part.getStatusString()
    octet = part.Mesh.CountFacets
    assert octet > 1000 and part.Mesh.isSolid() and not part.Mesh.hasNonManifolds()
    assert part.Mesh.BoundBox.XLength == pytest.approx(8.0, abs=0.2)
    lattice.CellType = "kelvin"
    doc.recompute()
    assert part.isValid() and part.Mesh.CountFacets != octet
    volume = part.Mesh.Volume
    lattice.Radius = 0.35
    doc.recompute()
    assert part.Mesh.Volume > 1.3 * volume  # thicker struts
    before = mesh_signature(part.Mesh)
    path = str(tmp_path / "struts.FCStd")
    doc.saveAs(path)
    reopened = FreeCAD.openDocument(path)
    try:
        again = reopened.getObject(part.Name)
        assert reopened.getObject(lattice.Name).CellType == "kelvin"
        reopened.recompute()
        assert mesh_signature(again.Mesh) == before
    finally:
        FreeCAD.closeDocument(reopened.Name)


def test_voronoi_foam_in_a_part_changes_with_seed_and_blend_and_reopens(doc, tmp_path):
    """A Voronoi foam cut to a block: a closed preview; another seed gives another foam, a
    blend adds solid at the joints, a bad blend fails with one line naming it; the document
    saves and reopens with the same preview."""
    foam = F.make("voronoi_foam", doc, cell=(2.0, 2.0, 2.0), radius=0.25, seed=3)
    block = F.make("box", doc, corner=(0, 0, 0), size=(8.0, 6.0, 4.0))
    part = F.make("intersection", doc, inputs=[foam, block])
    doc.recompute()
    assert part.isValid(), part.getStatusString()
    first = mesh_signature(part.Mesh)
    assert part.Mesh.CountFacets > 1000 and part.Mesh.isSolid()
    assert not part.Mesh.hasNonManifolds()
    foam.Seed = 4
    doc.recompute()
    assert part.isValid() and mesh_signature(part.Mesh) != first
    volume = part.Mesh.Volume
    foam.Blend = 0.2
    doc.recompute()
    assert part.isValid() and part.Mesh.Volume > 1.02 * volume
    foam.Blend = 1.5  # more than half the 2 mm cell
    doc.recompute()
    assert not foam.isValid()
    assert "property 'Blend' = 1.5 is more than half" in foam.getStatusString()
    foam.Blend = 0.2
    doc.recompute()
    assert part.isValid()
    before = mesh_signature(part.Mesh)
    path = str(tmp_path / "foam.FCStd")
    doc.saveAs(path)
    reopened = FreeCAD.openDocument(path)
    try:
        again = reopened.getObject(part.Name)
        assert reopened.getObject(foam.Name).Seed == 4
        reopened.recompute()
        assert mesh_signature(again.Mesh) == before
    finally:
        FreeCAD.closeDocument(reopened.Name)
