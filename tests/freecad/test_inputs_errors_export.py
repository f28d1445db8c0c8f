"""Part primitive inputs, the error classes and their messages, checked export and cancel."""

import os

import FreeCAD
import Part  # noqa: F401  (registers Part::Box and the other primitives)
import pytest

from conftest import ball_mesh
import FRepExamples
import FRepExport
import FRepFeatures as F
import FRepMeshing
import FRepPolygonize
import FRepTree
from FRepPaths import frepcore


def rotated(x, y, z, angle):
    return FreeCAD.Placement(FreeCAD.Vector(x, y, z),
                             FreeCAD.Rotation(FreeCAD.Vector(1, 2, 3), angle))


PART_CASES = [
    ("Part::Box", dict(Length=2, Width=1, Height=0.5)),
    ("Part::Sphere", dict(Radius=1.2)),
    ("Part::Cylinder", dict(Radius=0.5, Height=2)),
    ("Part::Cone", dict(Radius1=1, Radius2=0.3, Height=1.5)),
    ("Part::Torus", dict(Radius1=1.5, Radius2=0.4)),
    ("Part::Ellipsoid", dict(Radius1=0.6, Radius2=1.2, Radius3=0.9)),
]


@pytest.mark.parametrize("angle", [0, 50])
@pytest.mark.parametrize("type_id,props", PART_CASES, ids=[c[0] for c in PART_CASES])
def test_part_primitive_matches_frep_primitive(doc, type_id, props, angle):
    prim = doc.addObject(type_id, "Prim")
    for k, v in props.items():
        setattr(prim, k, v)
    prim.Placement = rotated(0.3, -0.2, 0.5, angle)
    doc.recompute()
    exact = prim.Shape
    shape = FRepTree.shape_of(prim)
    mesh = shape.mesh(cells=96)
    assert mesh.volume() == pytest.approx(exact.Volume, rel=0.01)
    # The same place and orientation: the bounding boxes agree to about a cell.
    bb = exact.optimalBoundingBox()
    points = mesh.points
    for a, (l, h) in enumerate(((bb.XMin, bb.XMax), (bb.YMin, bb.YMax), (bb.ZMin, bb.ZMax))):
        assert min(p[a] for p in points) == pytest.approx(l, abs=0.04)
        assert max(p[a] for p in points) == pytest.approx(h, abs=0.04)
    # Accepted as an input of an FRep operation.
    t = F.make("translate", doc, inputs=[prim], offset=(1, 0, 0))
    doc.recompute()
    assert t.isValid(), t.getStatusString()


def test_partial_part_primitive_enters_as_a_solid(doc):
    # Not the exact FRep sphere (half of it is cut away): its tessellated solid instead.
    s = doc.addObject("Part::Sphere", "Half")
    s.Radius = 2
    s.Angle3 = 180
    t = F.make("translate", doc, inputs=[s], offset=(0, 0, 0))
    doc.recompute()
    assert t.isValid(), t.getStatusString()
    shape = FRepTree.shape_of(t)
    assert shape(0, 1, 0) == pytest.approx(1.0, abs=0.02)  # inside the kept half (y > 0)
    assert shape(0, -1, 0) < 0  # the half cut away


def error_of(obj):
    assert not obj.isValid()
    return obj.getStatusString()


def test_bad_parameter_names_feature_property_and_range(doc):
    s = F.make("sphere", doc, name="Ball", radius=1)
    s.Radius = 0
    doc.recompute()
    assert error_of(s) == ("Ball: property 'Radius' = 0 mm is out of range; "
                           "allowed: (0, inf) mm")
    c = F.make("cylinder", doc, name="Rod")
    c.Axis = FreeCAD.Vector(0, 0, 0)
    doc.recompute()
    assert "Rod: property 'Axis'" in error_of(c) and "not all zero" in error_of(c)
    m = F.make("mesh_sdf", doc, name="Scan")
    doc.recompute()
    assert error_of(m) == ("Scan: property 'Path' = \"\" is empty; allowed: a file path "
                           "(relative paths: from the model file's folder)")


def test_missing_input_names_property(doc):
    u = F.make("union", doc, name="Join", inputs=[F.make("sphere", doc)])
    doc.recompute()
    assert error_of(u) == ("Join: property 'Shapes' needs at least 2 inputs (FRep features, "
                           "Part primitives, solids or meshes); it has 1")
    t = F.make("translate", doc, name="Move")
    doc.recompute()
    assert "Move: property 'Base' needs at least 1 input" in error_of(t)


def test_non_frep_input_is_refused(doc):
    sheet = doc.addObject("Spreadsheet::Sheet", "Sheet")
    u = F.make("union", doc, name="Join", inputs=[F.make("sphere", doc), sheet])
    doc.recompute()
    assert "'Sheet' (Spreadsheet::Sheet) is not an FRep input; accepted: FRep features" in \
        error_of(u)


def test_empty_result(doc):
    i = F.make("intersection", doc, name="Nothing",
               inputs=[F.make("sphere", doc), F.make("sphere", doc, center=(5, 0, 0))])
    doc.recompute()
    assert error_of(i).startswith("Nothing: the result is empty")


def test_unbounded_result_previews_but_cannot_be_polygonized(doc, tmp_path):
    c = F.make("complement", doc, name="Outside", inputs=[F.make("sphere", doc)])
    doc.recompute()
    assert c.isValid() and c.Mesh.CountFacets > 0  # shown clipped
    p = FRepPolygonize.make(c, doc, name="Mesh")
    doc.recompute()
    message = error_of(p)
    assert message.startswith("Mesh: property 'AutoBounds': cannot bound 'Outside'")
    assert "unbounded towards -x, +x, -y, +y, -z, +z" in message
    out = str(tmp_path / "out.stl")
    with pytest.raises(ValueError, match="unbounded"):
        FRepExport.export_objects([c], out)
    assert not os.path.exists(out)


def test_a_consumed_unbounded_input_is_not_warned_of(doc, monkeypatch):
    # an infinite cylinder drilled through a box: the cylinder alone is unbounded, and the
    # preview says so while it is shown; once a Difference consumes it, it is not
    said = []
    monkeypatch.setattr(FreeCAD.Console, "PrintWarning", said.append)
    hole = F.make("cylinder", doc, name="Hole", radius=0.3, length=0)
    doc.recompute()
    assert [w for w in said if w.startswith("Hole: the solid is unbounded towards -z, +z")]
    said.clear()
    block = F.make("box", doc, name="Block", size=(2, 2, 2), corner=(-1, -1, -1))
    drilled = F.make("difference", doc, name="Drilled", inputs=[block, hole])
    doc.recompute()
    hole.Radius = 0.4
    doc.recompute()
    assert drilled.isValid() and drilled.Mesh.CountFacets > 0
    assert not hole.Visibility and hole.Mesh.CountFacets == 0
    assert not [w for w in said if "unbounded" in w], said


def test_polygonize_warns_of_parts_thinner_than_a_cell(doc, monkeypatch):
    # a fin 0.3 cell thick between two layers of grid points (20 cells across [-1, 1] mm)
    fin = F.make("box", doc, name="Fin", size=(0.03, 0.3, 0.3), corner=(-0.015, 0.6, 0.6))
    part = F.make("union", doc, name="Part", inputs=[F.make("sphere", doc, radius=0.5), fin])
    p = FRepPolygonize.make(part, doc, name="Mesh", AutoBounds=False, Cells=20,
                            BoundsMin=FreeCAD.Vector(-1, -1, -1),
                            BoundsMax=FreeCAD.Vector(1, 1, 1))
    said = []
    monkeypatch.setattr(FreeCAD.Console, "PrintWarning", said.append)
    doc.recompute()
    assert p.isValid() and p.Triangles > 0
    thin = [w for w in said if "thinner than a cell" in w]
    assert len(thin) == 1 and thin[0].startswith("Mesh: solid thinner than a cell passes "
                                                 "between the grid's points at 9 grid edges")
    assert ", 0.65, 0.65)" in thin[0]
    # refined, the fin is meshed (a second piece) and the warning gives way to a message
    assert p.Refine == "Off"
    before = p.Mesh.Volume
    told = []
    monkeypatch.setattr(FreeCAD.Console, "PrintMessage", told.append)
    said.clear()
    p.Refine = "Thin parts"
    doc.recompute()
    assert p.isValid(), p.getStatusString()
    assert p.Mesh.Volume - before == pytest.approx(0.0027, rel=0.2)
    assert not [w for w in said if "thinner than a cell" in w]
    assert [m for m in told if m.startswith("Mesh: ") and "meshed again at half a cell" in m]
    # a fin round a point of the quarter-cell grid needs two levels
    assert p.RefineLevels == 1
    fin.Corner = FreeCAD.Vector(0.01, 0.6, 0.6)
    doc.recompute()
    one = p.Mesh.Volume
    told.clear()
    p.RefineLevels = 2
    doc.recompute()
    assert p.isValid(), p.getStatusString()
    assert p.Mesh.Volume - one == pytest.approx(0.0027, rel=0.2)
    # the report view says what the deeper level meshed
    assert [m for m in told if m.startswith("Mesh: ") and "smaller cubes below that, down to "
            "a cell / 4" in m], told
    p.RefineLevels = 4
    doc.recompute()
    assert not p.isValid() and ("property 'RefineLevels' must be a whole number from 1 to 3, "
                                "got 4" in p.getStatusString())
    p.RefineLevels = 2
    p.Refine = "Off"
    doc.recompute()
    assert not p.isValid() and ("'RefineLevels' 2 applies to a refinement: set 'Refine' to"
                                in p.getStatusString())
    p.RefineLevels = 1
    fin.Corner = FreeCAD.Vector(-0.015, 0.6, 0.6)
    # a part with nothing thin says nothing
    said.clear()
    fin.Size = FreeCAD.Vector(0.3, 0.3, 0.3)
    doc.recompute()
    assert not [w for w in said if "thinner than a cell" in w]


def test_polygonize_and_export_checked(doc, tmp_path):
    part = FRepExamples.build_csg(doc)
    p = FRepPolygonize.make(part, doc, Cells=64)
    doc.recompute()
    assert p.isValid(), p.getStatusString()
    assert p.Triangles == p.Mesh.CountFacets > 10000
    out = str(tmp_path / "csg.stl")
    report = FRepExport.export_objects([p], out)
    assert report["printable"] and os.path.getsize(out) == 84 + 50 * report["triangles"]
    # The exported solid is the reference model: same volume as the JSON export path.
    reference, _ = frepcore.load(os.path.join(os.environ["FREP_SOURCE_DIR"], "examples",
                                              "csg.json"))
    assert report["volume"] == pytest.approx(reference.mesh(cells=64).volume(), rel=1e-3)


def test_polygonize_mesher_chooses_the_mesher(doc, tmp_path):
    part = FRepExamples.build_csg(doc)
    p = FRepPolygonize.make(part, doc, Cells=48)
    doc.recompute()
    assert p.Mesher == "Cubes" and p.isValid(), p.getStatusString()
    cubes = p.Triangles
    p.Mesher = "Marching tetrahedra"
    doc.recompute()
    assert p.isValid() and p.Triangles > 2.5 * cubes
    out = str(tmp_path / "tetra.stl")
    assert FRepExport.export_objects([p], out)["triangles"] == p.Triangles


def older_polygonize(doc, part, name, older):
    """A Polygonize feature as a document saved with the older property names holds it:
    `older` maps each to (FreeCAD type, enumeration or None, value)."""
    p = FRepPolygonize.make(part, doc, name=name, Cells=32)
    taken = {"Method": "Mesher", "FewerTriangles": "DropFlatVertices",
             "RefineThinParts": "Refine"}
    for prop, (kind, choices, value) in older.items():
        p.removeProperty(taken[prop])
        p.addProperty(kind, prop, "Polygonize", "")
        if choices:
            setattr(p, prop, choices)
        setattr(p, prop, value)
    p.Proxy.onDocumentRestored(p)
    return p


def test_a_document_with_the_older_property_names_keeps_its_settings(doc):
    part = FRepExamples.build_csg(doc)
    p = older_polygonize(doc, part, "Older", {
        "Method": ("App::PropertyEnumeration", ["Cubes", "Marching tetrahedra"],
                   "Marching tetrahedra"),
        "FewerTriangles": ("App::PropertyBool", None, False),
        "RefineThinParts": ("App::PropertyEnumeration",
                            ["Off", "Thin parts", "Thin parts and tips"], "Thin parts and tips")})
    assert not {"Method", "FewerTriangles", "RefineThinParts"} & set(p.PropertiesList)
    assert (p.Mesher, p.DropFlatVertices, p.Refine) == ("Marching tetrahedra", False,
                                                         "Thin parts and tips")
    assert FRepPolygonize.settings_of(p) == frepcore.MeshSettings(
        mesher="tetra", drop_flat_vertices=False, refine="tips")
    # a document from before 0.3 stored the one method it had: it moves to the default
    q = older_polygonize(doc, part, "Oldest", {
        "Method": ("App::PropertyEnumeration", ["Marching tetrahedra"], "Marching tetrahedra")})
    assert q.Mesher == "Cubes" and "Method" not in q.PropertiesList
    assert list(q.getEnumerationsOfProperty("Mesher")) == ["Cubes", "Marching tetrahedra"]


def test_every_meshing_option_is_a_property_with_the_tables_default(doc):
    part = FRepExamples.build_csg(doc)
    p = FRepPolygonize.make(part, doc, Cells=32)
    assert FRepPolygonize.settings_of(p) == frepcore.MeshSettings()
    for row in frepcore.mesh_settings_table():
        name = FRepPolygonize.PROPERTY_OF_OPTION[row["name"]]
        assert name in p.PropertiesList
        assert p.getDocumentationOfProperty(name), name


def test_polygonize_with_a_tolerance_simplifies_and_exports_alike(doc, tmp_path):
    part = FRepExamples.build_csg(doc)
    full = FRepPolygonize.make(part, doc, Cells=48)
    doc.recompute()
    simple = FRepPolygonize.make(part, doc, name="Simple", Cells=48)
    simple.Tolerance = 0.005
    doc.recompute()
    assert simple.isValid(), simple.getStatusString()
    assert 5 * simple.Triangles < full.Triangles
    assert simple.Triangles == simple.Mesh.CountFacets
    # the export of the feature is the same simplified mesh, checked
    out = str(tmp_path / "simple.stl")
    written = FRepExport.export_objects([simple], out)
    assert written["printable"] and written["triangles"] == simple.Triangles
    # sharp features off: still simplified, a different mesh
    simple.SharpFeatures = False
    doc.recompute()
    assert simple.isValid() and 5 * simple.Triangles < full.Triangles
    # no tolerance: the mesher's mesh, chamfered without sharp features, as the full one with
    simple.Tolerance = 0
    doc.recompute()
    assert simple.Triangles < full.Triangles
    simple.SharpFeatures = True
    doc.recompute()
    assert simple.Triangles == full.Triangles


def assert_reopened_with(doc, tmp_path, prop, on, off):
    """Saved and reopened, the feature `on` has the boolean property `prop` set, `off` not."""
    path = str(tmp_path / (prop + ".FCStd"))
    doc.saveCopy(path)
    again = FreeCAD.openDocument(path)
    try:
        assert getattr(again.getObject(on.Name), prop)
        assert not getattr(again.getObject(off.Name), prop)
    finally:
        FreeCAD.closeDocument(again.Name)


def test_polygonize_straightens_creases_and_exports_alike(doc, tmp_path, monkeypatch):
    # the twist (a box turned by 180 degrees over its height): its helical creases
    box = F.make("box", doc, corner=(-0.5, -0.5, -1), size=(1, 1, 2))
    twist = F.make("twist", doc, inputs=[box], axis=(0, 0, 1), rate=90)
    plain = FRepPolygonize.make(twist, doc, Cells=48)
    straight = FRepPolygonize.make(twist, doc, name="Straight", Cells=48)
    assert not straight.StraightenCreases
    told = []
    monkeypatch.setattr(FreeCAD.Console, "PrintMessage", told.append)
    straight.StraightenCreases = True
    doc.recompute()
    assert straight.isValid(), straight.getStatusString()
    # the report view says what it did
    assert [m for m in told if m.startswith("Straight: creases straightened: ")
            and "vertices merged onto them" in m]
    # vertices either side of the creases merged onto them
    assert straight.Triangles < plain.Triangles
    assert straight.Triangles == straight.Mesh.CountFacets
    assert abs(straight.Mesh.Volume - 2.0) < 0.01
    out = str(tmp_path / "straight.stl")
    written = FRepExport.export_objects([straight], out)
    assert written["printable"] and written["triangles"] == straight.Triangles
    assert written["straightened"]["merged"] > 0
    # saved and reopened, each keeps its setting
    assert_reopened_with(doc, tmp_path, "StraightenCreases", on=straight, off=plain)
    # without sharp features it cannot find the creases: the error names both properties
    straight.SharpFeatures = False
    doc.recompute()
    assert not straight.isValid()
    message = straight.getStatusString()
    assert "StraightenCreases" in message and "SharpFeatures" in message
    straight.StraightenCreases = False
    doc.recompute()
    assert straight.isValid(), straight.getStatusString()


def test_polygonize_drops_flat_vertices_by_default_and_exports_alike(doc, tmp_path):
    part = FRepExamples.build_csg(doc)
    full = FRepPolygonize.make(part, doc, Cells=48, DropFlatVertices=False)
    fewer = FRepPolygonize.make(part, doc, name="Fewer", Cells=48)
    assert fewer.DropFlatVertices
    doc.recompute()
    assert fewer.isValid(), fewer.getStatusString()
    assert fewer.Triangles < 0.95 * full.Triangles
    assert fewer.Triangles == fewer.Mesh.CountFacets
    out = str(tmp_path / "fewer.stl")
    written = FRepExport.export_objects([fewer], out)
    assert written["printable"] and written["triangles"] == fewer.Triangles
    # saved and reopened, each keeps its setting; off, the full mesh
    assert_reopened_with(doc, tmp_path, "DropFlatVertices", on=fewer, off=full)
    fewer.DropFlatVertices = False
    doc.recompute()
    assert fewer.Triangles == full.Triangles


def test_export_filter_is_registered():
    # Registered by the workbench's Init.py for its three extensions.
    modules = FreeCAD.getExportType()
    assert {e for e, m in modules.items() if m == "FRepExport"} >= {"stl", "obj", "ply"}


def test_cancelled_export_leaves_no_file(doc, tmp_path):
    part = FRepExamples.build_csg(doc)
    doc.recompute()
    out = str(tmp_path / "cancel.stl")
    seen = []

    def cancel_midway(fraction):
        seen.append(fraction)
        return fraction < 0.2

    with pytest.raises(RuntimeError, match="cancelled; no file written"):
        FRepExport.export_objects([part], out, progress=cancel_midway, cells=400)
    assert seen and not os.path.exists(out)
    assert not [f for f in os.listdir(str(tmp_path))]  # no temporary left either


def test_cancelled_polygonize_keeps_previous_mesh(doc, monkeypatch):
    part = FRepExamples.build_csg(doc)
    p = FRepPolygonize.make(part, doc, Cells=32)
    doc.recompute()
    before = p.Mesh.CountFacets

    class CancelAtOnce:
        def __init__(self, text):
            pass

        def __call__(self, fraction):
            return False

        def close(self):
            pass

    monkeypatch.setattr(FRepMeshing, "progress_factory", CancelAtOnce)
    p.Cells = 300
    doc.recompute()
    assert "cancelled" in error_of(p)
    assert p.Mesh.CountFacets == before


def test_a_plain_mesh_feature_exports_as_it_is_after_the_check(doc, tmp_path):
    ball = doc.addObject("Mesh::Feature", "Scan")
    ball.Mesh = ball_mesh(tmp_path, 20)
    ball.Placement.Base = FreeCAD.Vector(5, 0, 0)
    target = str(tmp_path / "scan.stl")
    report = FRepExport.export_objects([ball], target)
    assert report["printable"] and report["written"]
    written = frepcore.read_mesh(target)
    assert written.triangle_count == ball.Mesh.CountFacets  # not meshed again
    assert min(p[0] for p in written.points) == pytest.approx(4.0, abs=0.01)  # placed
    # an open one is refused as it is, nothing written
    broken = ball.Mesh.copy()
    broken.removeFacets([0, 1])
    ball.Mesh = broken
    with pytest.raises(frepcore.NotPrintable, match="not printable"):
        FRepExport.export_objects([ball], str(tmp_path / "open.stl"))
    assert not (tmp_path / "open.stl").exists()
