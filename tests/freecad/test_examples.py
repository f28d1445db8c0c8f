"""The example documents in examples/ (written by examples/make_documents.py): they open,
recompute, describe exactly the reference solid of examples/csg.json, and the spreadsheet
drives the part."""

import os
import random

import FreeCAD
import pytest

import FRepTree
from FRepPaths import frepcore

EXAMPLES = os.path.join(os.environ["FREP_SOURCE_DIR"], "examples")
OBJECTS = {"Cube": "box", "Ball": "sphere", "Core": "intersection", "HoleX": "cylinder",
           "HoleY": "cylinder", "HoleZ": "cylinder", "Part": "difference"}


@pytest.fixture(params=["csg", "csg_spreadsheet"])
def example(request):
    doc = FreeCAD.openDocument(os.path.join(EXAMPLES, request.param + ".FCStd"))
    yield request.param, doc
    FreeCAD.closeDocument(doc.Name)


def sample_points(n=4000, reach=1.6, seed=7):
    rng = random.Random(seed)
    return [(rng.uniform(-reach, reach), rng.uniform(-reach, reach),
             rng.uniform(-reach, reach)) for _ in range(n)]


def recompute_all(doc):
    """Recomputes every feature from scratch; none may fail."""
    for obj in doc.Objects:
        obj.touch()
    doc.recompute()
    assert not [o.Label for o in doc.Objects if "Invalid" in o.State]


def field_difference(feature, json_path, points, offset=(0, 0, 0)):
    """Largest difference between the feature's field at points + offset (its Placement in
    a layout) and the JSON model's field at points."""
    reference, _ = frepcore.load(json_path)
    dx, dy, dz = offset
    mine = FRepTree.shape_of(feature).values([(x + dx, y + dy, z + dz) for x, y, z in points])
    return max(abs(a - b) for a, b in zip(mine, reference.values(points)))


def test_example_is_the_exact_reference_solid(example):
    name, doc = example
    for obj_name, type_id in OBJECTS.items():
        obj = doc.getObject(obj_name)
        assert obj is not None and obj.Proxy.FREP_TYPE == type_id, (name, obj_name)
    recompute_all(doc)
    # Same tree, same formulas: equal to rounding (the Placement adds an identity transform).
    assert field_difference(doc.getObject("Part"), os.path.join(EXAMPLES, "csg.json"),
                            sample_points()) < 1e-12


def test_saved_meshes_are_there_and_printable(example):
    name, doc = example
    shown = doc.getObject("PartMesh" if name == "csg_spreadsheet" else "Part")
    assert shown.Visibility and shown.Mesh.CountFacets > 1000
    path = os.path.join(os.environ.get("TMPDIR", "/tmp"), "frep-example-%s.ply" % os.getpid())
    try:
        shown.Mesh.write(path)
        report = frepcore.read_mesh(path).check(name)
    finally:
        if os.path.exists(path):
            os.remove(path)
    assert report["printable"], report["text"]


def test_spreadsheet_drives_the_part():
    doc = FreeCAD.openDocument(os.path.join(EXAMPLES, "csg_spreadsheet.FCStd"))
    try:
        sheet, mesh = doc.getObject("Parameters"), doc.getObject("PartMesh")
        assert doc.getObject("HoleX").Radius.Value == pytest.approx(sheet.get("Hole"))
        volume = mesh.Mesh.Volume
        sheet.set("Hole", "0.3")
        doc.recompute()
        for axis in "XYZ":
            assert doc.getObject("Hole" + axis).Radius.Value == pytest.approx(0.3)
        # Smaller holes: more material.
        assert mesh.Mesh.Volume > volume + 0.3
    finally:
        FreeCAD.closeDocument(doc.Name)


@pytest.mark.parametrize("name", ["twist", "helix", "gyroid"])
def test_reference_documents_hold_their_json_model(name):
    doc = FreeCAD.openDocument(os.path.join(EXAMPLES, name + ".FCStd"))
    try:
        top = doc.getObject(name) or [o for o in doc.Objects if o.Label == name][0]
        recompute_all(doc)
        assert field_difference(top, os.path.join(EXAMPLES, name + ".json"),
                                sample_points(2000, reach=2.0)) < 1e-12
        assert top.Mesh.CountFacets > 1000
    finally:
        FreeCAD.closeDocument(doc.Name)


def test_showcase_document_holds_every_showcase_model():
    folder = os.path.join(EXAMPLES, "showcase")
    names = sorted(n[:-5] for n in os.listdir(folder) if n.endswith(".json"))
    doc = FreeCAD.openDocument(os.path.join(EXAMPLES, "showcase.FCStd"))
    try:
        recompute_all(doc)
        shown = {o.Label: o for o in doc.Objects if o.Visibility}
        assert sorted(shown) == names
        for name in names:
            # The feature is the model moved by its Placement in the layout.
            base = shown[name].Placement.Base
            assert field_difference(shown[name], os.path.join(folder, name + ".json"),
                                    sample_points(300, reach=1.2),
                                    (base.x, base.y, base.z)) < 1e-9
    finally:
        FreeCAD.closeDocument(doc.Name)


def test_lattice_document_bends_a_part_and_a_mesh_printable(tmp_path):
    doc = FreeCAD.openDocument(os.path.join(EXAMPLES, "lattice.FCStd"))
    try:
        recompute_all(doc)
        part, mesh = doc.getObject("BentHoledBar"), doc.getObject("BentBlock")
        report = FRepTree.shape_of(part).export(str(tmp_path / "part.stl"), cells=96)
        assert report["printable"], report["text"]
        assert report["box"][1][2] > 8  # lifted by the lattice (the bar is 8 mm thick)
        path = str(tmp_path / "block.stl")
        mesh.Mesh.write(path)
        assert frepcore.read_mesh(path).check()["printable"]
        assert mesh.Mesh.BoundBox.ZMax > 8
    finally:
        FreeCAD.closeDocument(doc.Name)


def test_hspline_document_holds_the_tutorial_with_its_detail():
    import FRepHSpline
    doc = FreeCAD.openDocument(os.path.join(EXAMPLES, "hspline.FCStd"))
    try:
        obj = doc.getObject("Tutorial")
        text = FRepHSpline.hspline_of(obj).to_text()
        recompute_all(doc)
        h = FRepHSpline.hspline_of(obj)
        assert obj.isValid() and h.level_count == 4 and h.to_text() == text
        assert sorted(c[0] for c in h.select_non_zero()) == [1, 3, 3]
        assert obj.Shape.Faces and obj.Shape.BoundBox.ZMax > 8  # the lifted level-1 CV
    finally:
        FreeCAD.closeDocument(doc.Name)


@pytest.mark.parametrize("name", ["csg", "csg_spreadsheet", "twist", "helix", "gyroid",
                                  "showcase", "lattice", "hspline", "bracket"])
def test_examples_were_saved_from_the_gui(name):
    """Without GuiDocument.xml FreeCAD opens a document with every object shown, consumed
    inputs included; make_documents.py saves from the GUI so the inputs stay hidden."""
    import zipfile
    with zipfile.ZipFile(os.path.join(EXAMPLES, name + ".FCStd")) as z:
        assert "GuiDocument.xml" in z.namelist()


@pytest.mark.parametrize("name", ["csg", "twist", "helix", "gyroid"])
def test_json_models_import_as_the_same_solid(doc, name):
    """File > Open of a .json model: one feature per node, the same field exactly."""
    import FRepImport
    path = os.path.join(EXAMPLES, name + ".json")
    top = FRepImport.import_model(path, doc)
    recompute_all(doc)
    assert top.Label == name and top.Visibility
    assert all(not o.Visibility for o in doc.Objects if o is not top)
    assert field_difference(top, path, sample_points(2000, reach=2.0)) < 1e-12
    assert "FRepImport" in FreeCAD.getImportType("json")


def test_a_hyperfun_program_opens_as_features_with_its_values(doc, tmp_path):
    """File > Open of a .hf program: the set operations and the blend as their features, each
    primitive a Formula feature with HyperFun's expression, the same values everywhere, and
    a printable export; a mistake in the program is one line naming its line and column."""
    import FRepExport
    import FRepImport
    path = os.path.join(EXAMPLES, "mount.hf")
    top = FRepImport.import_model(path, doc)
    recompute_all(doc)
    assert top.Label == "mount" and top.Visibility
    assert top.Proxy.FREP_TYPE == "difference"
    types = sorted(o.Proxy.FREP_TYPE for o in doc.Objects if hasattr(o, "Proxy"))
    assert types.count("formula") == 8 and "blend_union" in types
    # the features carry the program's names: its variables, else the library call
    labels = sorted(o.Label for o in doc.Objects if o is not top)
    for name in ("plate", "boss", "body", "bore", "holes", "hfBlock", "hfCylinderZ"):
        assert name in labels, labels
    points = [(x * 15, y * 8, z * 10 + 5) for x, y, z in sample_points(2000, reach=1.6)]
    assert field_difference(top, path, points) < 1e-9
    report = FRepExport.export_objects([top], str(tmp_path / "mount.stl"), cells=64)
    assert report["printable"] and report["written"], report["text"]
    assert "FRepImport" in FreeCAD.getImportType("hf")
    bad = tmp_path / "bad.hf"
    bad.write_text("my_model(x[3], a[1])\n{\n  my_model = hfSphere(x, 2);\n}\n")
    with pytest.raises(ValueError, match=r"^bad.hf:3:14: hfsphere takes 3 arguments, not 2$"):
        FRepImport.import_model(str(bad), doc)
