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
    ]
    for extra, message in cases:
        r = frepcad(sheet_document, "-o", out, *extra)
        assert r.returncode == 2, (extra, r.stdout, r.stderr)
        assert message in r.stderr, (extra, r.stderr)
        assert not os.path.exists(out)
