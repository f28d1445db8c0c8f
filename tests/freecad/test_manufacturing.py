"""Manufacturing output in the workbench: several FRep features into one checked
3MF, a broken mesh repaired into a new feature (the input kept), the printability report."""

import FreeCAD
import Mesh
import pytest

import FRepExamples
import FRepExport
import FRepFeatures as F
import FRepManufacturing
import FRepMeshing
import FRepPolygonize
from FRepPaths import frepcore


def test_several_features_export_into_one_3mf_each_its_own_object(doc, tmp_path):
    part = FRepExamples.build_csg(doc)
    ball = F.make("translate", doc, inputs=[F.make("sphere", doc, radius=0.5)], offset=(4, 0, 0))
    doc.recompute()
    out = str(tmp_path / "two.3mf")
    report = FRepExport.export_objects([part, ball], out, cells=32)
    assert report["written"] and report["printable"]
    back = frepcore.read_3mf(out)
    assert [n for n, _ in back["objects"]] == [part.Label, ball.Label]
    assert back["metadata"]["Title"] == doc.Label
    ball_mesh = back["objects"][1][1]
    assert ball_mesh.check()["printable"]
    lo, hi = ball_mesh.check()["bbox"][:3], ball_mesh.check()["bbox"][3:]
    assert (lo[0] + hi[0]) / 2 == pytest.approx(4, abs=0.02)
    # FreeCAD's export filter for .3mf is ours
    assert FreeCAD.getExportType("3mf") and "FRepExport" in FreeCAD.getExportType("3mf")


def test_a_polygonize_feature_exports_to_3mf_with_its_own_settings(doc, tmp_path):
    part = FRepExamples.build_csg(doc)
    p = FRepPolygonize.make(part, doc, Cells=40)
    doc.recompute()
    out = str(tmp_path / "p.3mf")
    report = FRepExport.export_objects([p], out)
    assert report["written"]
    assert report["triangles"] == p.Mesh.CountFacets


def broken_ball(doc):
    """A Mesh feature with a hole and an inside-out half, as an STL from elsewhere might be."""
    ball = frepcore.sphere(5).mesh(bbox=((-6, -6, -6), (6, 6, 6)), resolution=0.5)
    tris = [t if i % 2 else (t[0], t[2], t[1]) for i, t in enumerate(ball.triangles)][5:]
    obj = doc.addObject("Mesh::Feature", "Broken")
    # through FreeCAD's binary mesh (Mesh.Mesh of Python facets harmonises them, slowly)
    obj.Mesh = FRepMeshing.to_freecad_mesh(frepcore.Mesh(ball.points, tris))
    obj.Placement.Base = FreeCAD.Vector(20, 0, 0)
    doc.recompute()
    return obj


def test_a_broken_mesh_is_repaired_into_a_new_feature_and_the_input_kept(doc):
    obj = broken_ball(doc)
    before = obj.Mesh.copy()
    assert not FRepManufacturing.frepcore_mesh(obj).check()["printable"]
    out, report = FRepManufacturing.repair(obj, progress=lambda f: True)
    assert out is not None, report["text"]
    assert report["printable"] and not report["printable_before"]
    assert any("filled" in a for a in report["actions"])
    assert FRepManufacturing.frepcore_mesh(out).check()["printable"]
    assert obj.Mesh.CountFacets == before.CountFacets  # the input untouched
    # world coordinates: the input's placement is in the repaired mesh
    assert out.Mesh.BoundBox.Center.x == pytest.approx(20, abs=0.1)
    assert out.Label == "Broken repaired"


def test_a_mesh_that_cannot_be_repaired_makes_nothing_and_says_why(doc):
    sheet = doc.addObject("Mesh::Feature", "Sheet")
    sheet.Mesh = Mesh.Mesh([[(0, 0, 0), (1, 0, 0), (0, 1, 0)]])
    doc.recompute()
    count = len(doc.Objects)
    out, report = FRepManufacturing.repair(sheet, progress=lambda f: True)
    assert out is None and not report["printable"]
    assert report["reasons"]
    assert len(doc.Objects) == count
    with pytest.raises(ValueError, match="not a mesh"):
        FRepManufacturing.frepcore_mesh(doc.addObject("Part::Box", "Box"))


def test_printability_of_a_thin_walled_part(doc):
    # a 20 mm cup: a box with a 1 mm wall, open at the top through a difference
    outer = F.make("box", doc, corner=(0, 0, 0), size=(20, 20, 20))
    inner = F.make("box", doc, corner=(1, 1, 1), size=(18, 18, 30))
    cup = F.make("difference", doc, inputs=[outer, inner])
    p = FRepPolygonize.make(cup, doc, Cells=40)
    doc.recompute()
    assert p.isValid(), p.getStatusString()
    report = FRepManufacturing.printability(p, min_wall=1.5, material="petg")
    assert not report["printable"]
    assert any("thinner than 1.5" in r for r in report["reasons"])
    assert report["print"]["min_wall"] == pytest.approx(1.0, rel=0.1)
    assert len(report["thin"]) > 0.5 * p.Mesh.CountFacets
    assert report["print"]["mass_g"] == pytest.approx(
        1.27 * report["volume"] / 1000, rel=1e-6)
    with pytest.raises(ValueError, match="unknown material 'cheese'"):
        FRepManufacturing.printability(p, material="cheese")


def test_an_inside_out_mesh_that_freecads_own_check_passes_is_caught(doc):
    ball = frepcore.sphere(5).mesh(bbox=((-6, -6, -6), (6, 6, 6)), resolution=0.5)
    inside_out = frepcore.Mesh(ball.points, [(a, c, b) for a, b, c in ball.triangles])
    obj = doc.addObject("Mesh::Feature", "InsideOut")
    obj.Mesh = FRepMeshing.to_freecad_mesh(inside_out)
    # FreeCAD: a closed solid of positive volume (its Volume is unsigned)
    assert obj.Mesh.isSolid() and obj.Mesh.Volume > 500
    report = FRepManufacturing.printability(obj)
    assert not report["printable"] and not report["outward"]
    assert any("not outward" in r for r in report["reasons"])
    fixed, result = FRepManufacturing.repair(obj, progress=lambda f: True)
    assert fixed is not None and result["check"]["outward"]


def test_an_infills_cavities_are_reported_and_drained_through_its_skin(doc):
    # a 30 x 20 x 12 mm block hollowed to a 1 mm skin around a gyroid sheet, moved and turned
    # so that the holes must be placed in the infill's own coordinates
    block = F.make("box", doc, corner=(0, 0, 0), size=(30, 20, 12))
    infill = F.make("infill", doc, inputs=[block], wall=1.0, cell=6.0, thickness=0.8)
    infill.Placement = FreeCAD.Placement(FreeCAD.Vector(50, -5, 3),
                                         FreeCAD.Rotation(FreeCAD.Vector(0, 0, 1), 30))
    p = FRepPolygonize.make(infill, doc, Cells=150)
    doc.recompute()
    assert p.isValid(), p.getStatusString()
    assert FRepManufacturing.infill_of(p) == infill
    assert FRepManufacturing.infill_of(infill) == infill
    assert FRepManufacturing.infill_of(block) is None
    report = FRepManufacturing.printability(p)
    cavities = report["print"]["cavity_list"]
    assert report["print"]["cavities"] == len(cavities) >= 2
    volumes = [c["volume"] for c in cavities]
    assert volumes == sorted(volumes, reverse=True)
    assert sum(volumes) == pytest.approx(report["print"]["cavity_volume"])
    # the walls: a triangle is a cavity's wall exactly where the report says so
    walls = set(report["cavity_triangles"])
    assert 0 < len(walls) < p.Mesh.CountFacets
    assert {report["cavity_of"][i] for i in walls} == set(range(len(cavities)))
    # each drain point lies on the inside of the bottom skin (1 mm above the plate, z = 3)
    for c in cavities:
        assert c["drain_at"][2] == pytest.approx(4.0, abs=0.2)

    added = FRepManufacturing.drain_cavities(infill, report)
    assert added == len(cavities) and len(infill.DrainHoles) == added
    # in the infill's own coordinates: on the inside of its bottom skin, within the block
    for hole in infill.DrainHoles:
        assert hole.z == pytest.approx(1.0, abs=0.2)
        assert 0 < hole.x < 30 and 0 < hole.y < 20
    doc.recompute()
    assert p.isValid(), p.getStatusString()
    after = FRepManufacturing.printability(p)
    assert after["printable"]
    assert after["print"]["cavities"] == 0 and not after["cavity_triangles"]
    assert after["volume"] < report["volume"]  # the skin lost the holes' material


def test_drain_holes_from_a_linked_source_are_not_overwritten(doc):
    block = F.make("box", doc, corner=(0, 0, 0), size=(30, 20, 12))
    infill = F.make("infill", doc, inputs=[block], wall=1.0, cell=6.0, thickness=0.8)
    points = doc.addObject("Part::Vertex", "Where")
    infill.DrainHolesSource = points
    report = {"print": {"cavity_list": [{"volume": 1.0, "drain_at": [1.0, 1.0, 1.0]}]}}
    with pytest.raises(ValueError, match="property 'DrainHolesSource'"):
        FRepManufacturing.drain_cavities(infill, report)
    assert len(infill.DrainHoles) == 0
