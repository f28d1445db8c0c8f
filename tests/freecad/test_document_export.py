"""`frepcad export part.FCStd --set ...`: headless document export through FreeCAD."""

import os
import subprocess

import FreeCAD
import pytest

import FRepExamples
from FRepPaths import frepcore


@pytest.fixture
def sheet_document(tmp_path):
    doc = FreeCAD.newDocument("SheetDoc")
    mesh = FRepExamples.build_csg_spreadsheet(doc)
    mesh.Cells = 40
    doc.recompute()
    path = str(tmp_path / "part.FCStd")
    doc.saveAs(path)
    FreeCAD.closeDocument(doc.Name)
    return path


def frepcad(*args):
    return subprocess.run([os.environ["FREPCAD_BIN"], "export"] + list(args),
                          capture_output=True, text=True, timeout=300)


def volume(path):
    return frepcore.read_mesh(path).volume()


def test_set_changes_the_result(sheet_document, tmp_path):
    plain, bigger, moved = (str(tmp_path / n) for n in ("plain.stl", "ball.stl", "cube.stl"))
    r = frepcad(sheet_document, "-o", plain)
    assert r.returncode == 0, r.stderr
    assert "verdict: printable" in r.stdout and "FreeCAD" not in r.stdout
    r = frepcad(sheet_document, "-o", bigger, "--set", "Parameters.Ball=1.5")
    assert r.returncode == 0, r.stderr
    assert volume(bigger) > volume(plain) * 1.05
    # A plain property and a spreadsheet cell at once; --object picks the feature.
    r = frepcad(sheet_document, "--set", "Part.Bypass=true", "--set", "Parameters.Size=1.8",
                "--set", "Parameters.Ball=1.6",
                "--object", "Part", "--cells", "40", "-o", moved, "--quiet")
    assert r.returncode == 0, r.stderr
    assert r.stdout == ""
    # No holes (bypassed), a smaller cube inside the ball: 1.8^3 exactly, up to the mesh.
    assert volume(moved) == pytest.approx(1.8 ** 3, rel=0.01)


def test_bad_overrides_are_clear_errors_and_write_nothing(sheet_document, tmp_path):
    out = str(tmp_path / "never.stl")
    cases = [
        (["--set", "Ball.Radius=2"], "driven by the expression 'Parameters.Ball'"),
        (["--set", "Nope.Radius=1"], "no object 'Nope'"),
        (["--set", "Parameters.Ball=-1"], "Ball: property 'Radius' = -1 mm is out of range"),
        (["--set", "Cube.Colour=1"], "has no property 'Colour'"),
        (["--object", "Missing"], "--object Missing: no such object"),
        (["--set", "Ball.Center=1,2"], "a vector takes three numbers x,y,z; got 2"),
        (["--set", "Ball.Center=1,2,nan"], "nan is not a finite number"),
        (["--set", "Ball.Center=1 deg,2,3"], "'1 deg' is not a number"),
        (["--set", "Parameters.Ball="], "a value is needed after '='"),
        (["--set", "Part.Bypass=maybe"], "'maybe' is not a yes or no; allowed: 1, true"),
        (["--set", "Part.Placement=1"], "App::PropertyPlacement cannot be set from the "
                                        "command line"),
        (["--set", "Ball.Center=1,2," + "9" * 100000], "(100000 characters)"),
    ]
    for extra, message in cases:
        r = frepcad(sheet_document, "-o", out, *extra)
        assert r.returncode == 2, (extra, r.stdout, r.stderr)
        assert message in r.stderr, (extra, r.stderr)
        # one line, however FreeCAD reported it on its console, and no value echoed whole
        assert len(r.stderr.strip().splitlines()) == 1, r.stderr
        assert len(r.stderr) < 400, len(r.stderr)
        assert not os.path.exists(out)


def test_a_value_that_is_not_utf8_is_one_line_and_leaves_no_temporary_home(sheet_document,
                                                                           tmp_path):
    private = tmp_path / "tmp"
    private.mkdir()
    r = subprocess.run([os.environ["FREPCAD_BIN"], "export", sheet_document, "-o",
                        str(tmp_path / "x.stl"), "--set", b"Ball.Center=\xff,1,1"],
                       capture_output=True, timeout=300, env=dict(os.environ, TMPDIR=str(private)))
    err = r.stderr.decode("utf-8", "replace")
    assert r.returncode == 2, err
    assert "is not UTF-8 text" in err and len(err.strip().splitlines()) == 1, err
    assert list(private.iterdir()) == []
    # a failed export through FreeCAD removes its temporary home too
    r = subprocess.run([os.environ["FREPCAD_BIN"], "export", sheet_document, "-o",
                        str(tmp_path / "x.stl"), "--set", "Nope.X=1"],
                       capture_output=True, timeout=300, env=dict(os.environ, TMPDIR=str(private)))
    assert r.returncode == 2 and list(private.iterdir()) == []


def test_same_options_as_json_models(sheet_document, tmp_path):
    """--resolution, --bbox, --format and --force reach FCStd exports too."""
    out = str(tmp_path / "box.obj")
    r = frepcad(sheet_document, "-o", out, "--format", "obj", "--resolution", "0.1",
                "--bbox", "-1", "-1", "-1", "1", "1", "1")
    assert r.returncode == 0, r.stderr
    mesh = frepcore.read_mesh(out)
    lo = [min(p[a] for p in mesh.points) for a in range(3)]
    hi = [max(p[a] for p in mesh.points) for a in range(3)]
    # the box cuts the solid (caps within a fraction of a 0.1 cell of its faces)
    assert all(-1.05 <= l <= -0.95 for l in lo) and all(0.95 <= h <= 1.05 for h in hi)
    r = frepcad(sheet_document, "-o", str(tmp_path / "x.stl"), "--cells", "8",
                "--resolution", "0.1")
    assert r.returncode == 2 and "not both" in r.stderr


def _zip(path, members):
    import zipfile
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        for name, data in members.items():
            z.writestr(name, data)


def test_damaged_and_hostile_documents_are_one_line_errors(sheet_document, tmp_path):
    import zipfile
    with zipfile.ZipFile(sheet_document) as z:
        xml = z.read("Document.xml").decode("utf-8")
    not_zip = tmp_path / "text.FCStd"
    not_zip.write_text("hello")
    no_xml = tmp_path / "noxml.FCStd"
    _zip(no_xml, {"GuiDocument.xml": "<x/>"})
    truncated = tmp_path / "cut.FCStd"
    _zip(truncated, {"Document.xml": xml[: len(xml) // 2]})
    # a zip bomb: a member whose central directory entry says it unpacks to 4 GB
    bomb = tmp_path / "bomb.FCStd"
    _zip(bomb, {"Document.xml": xml, "padding.bin": b"\0" * 16})
    data = bytearray(bomb.read_bytes())
    entry = data.rfind(b"PK\x01\x02")  # the last central directory entry: padding.bin
    data[entry + 24:entry + 28] = (0xFFFFFFF0).to_bytes(4, "little")
    bomb.write_bytes(bytes(data))
    unknown = tmp_path / "unknown.FCStd"
    _zip(unknown, {"Document.xml": xml.replace('type="Mesh::FeaturePython"',
                                               'type="Nowhere::NoSuchClass"', 1)})
    folder = tmp_path / "folder.FCStd"
    folder.mkdir()
    cases = [
        (not_zip, "not a FreeCAD document (an .FCStd file is a zip archive)"),
        (no_xml, "no Document.xml in the archive"),
        (truncated, "Document.xml is not well-formed XML"),
        (bomb, "unpacks to"),
        (unknown, "could not be loaded"),
        (folder, "is a folder"),
    ]
    out = str(tmp_path / "never.stl")
    for path, message in cases:
        r = frepcad(str(path), "-o", out)
        assert r.returncode == 2, (path, r.stdout, r.stderr)
        assert message in r.stderr, (path, r.stderr)
        assert "Traceback" not in r.stderr, r.stderr
        # FreeCAD itself may print what it could not load; ours is the one frepcad line
        ours = [line for line in r.stderr.splitlines() if line.startswith("frepcad:")]
        assert len(ours) == 1, r.stderr
        assert not os.path.exists(out)


def test_several_objects_of_a_document_into_one_3mf(tmp_path):
    import FRepFeatures as F
    doc = FreeCAD.newDocument("TwoParts")
    F.make("sphere", doc, name="Ball", radius=1)
    F.make("translate", doc, inputs=[F.make("box", doc, name="Block", size=(1, 1, 1))],
           name="Moved", offset=(3, 0, 0))
    doc.recompute()
    path = str(tmp_path / "two.FCStd")
    doc.saveAs(path)
    FreeCAD.closeDocument(doc.Name)
    out = str(tmp_path / "two.3mf")
    r = frepcad(path, "-o", out, "--object", "Ball", "--object", "Moved", "--cells", "24",
                "--units", "cm")
    assert r.returncode == 0, r.stderr
    back = frepcore.read_3mf(out)
    assert [n for n, _ in back["objects"]] == ["Ball", "Moved"]
    assert back["unit"] == "cm"
    assert all(m.check()["printable"] for _, m in back["objects"])
    # a unit is refused for other formats, naming the file
    r = frepcad(path, "-o", str(tmp_path / "x.stl"), "--object", "Ball", "--units", "cm")
    assert r.returncode == 2 and "3MF output only" in r.stderr


def test_an_empty_solid_is_not_printable(tmp_path):
    """Two balls that do not meet: nothing to print, the verdict a failed check gives (exit
    1, one line, nothing written), not bad input."""
    import FRepFeatures
    doc = FreeCAD.newDocument("EmptyDoc")
    a = FRepFeatures.make("sphere", doc, name="A", radius=1.0)
    b = FRepFeatures.make("sphere", doc, name="B", radius=1.0, center=FreeCAD.Vector(9, 0, 0))
    FRepFeatures.make("intersection", doc, inputs=[a, b], name="Nothing")
    doc.recompute()
    path = str(tmp_path / "empty.FCStd")
    doc.saveAs(path)
    FreeCAD.closeDocument(doc.Name)
    out = tmp_path / "empty.stl"
    r = frepcad(path, "--object", "Nothing", "-o", str(out))
    assert r.returncode == frepcore.EXIT_STATUS["not_printable"], (r.stdout, r.stderr)
    assert "Nothing: the result is empty" in r.stderr and len(r.stderr.splitlines()) == 1
    assert not out.exists()


EXAMPLES = os.path.join(os.path.dirname(__file__), "..", "..", "examples")


def test_with_no_object_every_visible_top_level_solid_exports(tmp_path):
    """lattice.FCStd holds two bent parts: their union in an STL (said on stderr), each its
    own object in a 3MF; the lattices and the parts' hidden inputs are not exported."""
    path = os.path.join(EXAMPLES, "lattice.FCStd")
    stl = str(tmp_path / "both.stl")
    r = frepcad(path, "-o", stl, "--cells", "40")
    assert r.returncode == 0, r.stderr
    assert "exporting the union of BentHoledBar, BentBlock" in r.stderr
    assert frepcore.read_mesh(stl).check()["components"] == 2
    three = str(tmp_path / "all.3mf")
    r = frepcad(path, "-o", three, "--cells", "40")
    assert r.returncode == 0, r.stderr
    assert "union" not in r.stderr
    assert sorted(name for name, _ in frepcore.read_3mf(three)["objects"]) == \
        ["BentBlock", "BentHoledBar"]
    # one of them by --object; a wrong name lists what can be exported
    r = frepcad(path, "-o", str(tmp_path / "one.stl"), "--object", "BentBlock", "--cells", "40")
    assert r.returncode == 0 and "union" not in r.stderr, r.stderr
    r = frepcad(path, "-o", str(tmp_path / "none.stl"), "--object", "Nothing")
    assert r.returncode == 2
    assert r.stderr.strip().endswith("it can export: Bar, Hole0, Hole1, Hole2, HoledBar, Block, "
                                     "BentHoledBar, BentBlock"), r.stderr
    r = frepcad(path, "-o", str(tmp_path / "none.stl"), "--object", "LatticeBlock")
    assert r.returncode == 2 and "is not a solid, mesh or FRep feature" in r.stderr


def test_an_hspline_document_exports_its_surface_as_it_is(tmp_path):
    """The hspline tutorial's surface is an open sheet: exported, it is tessellated and
    checked; not printable (its border edges), written with --force (exit status 1 still:
    what was written is not printable)."""
    path = os.path.join(EXAMPLES, "hspline.FCStd")
    out = str(tmp_path / "sheet.stl")
    r = frepcad(path, "-o", out)
    assert r.returncode == 1, r.stderr
    assert "border edges" in r.stdout and not os.path.exists(out)
    r = frepcad(path, "-o", out, "--force")
    assert r.returncode == 1 and "wrote %s" % out in r.stdout, r.stderr
    assert frepcore.read_mesh(out).triangle_count > 1000
