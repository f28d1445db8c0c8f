"""Any FreeCAD solid or mesh as an FRep input: a PartDesign part infilled and exported
printable, recomputed when the part changes, meshes and partial primitives as inputs, and
refusals that say what is accepted."""

import os

import FreeCAD
import Mesh  # noqa: F401  (registers Mesh::Feature)
import Part
import pytest

from conftest import ball_mesh
import FRepExamples
import FRepFeatures as F
import FRepSolids
import FRepTree
from FRepPaths import frepcore


def export_volume(shape, path, cells=96):
    report = shape.export(path, cells=cells)
    assert report["printable"], report["text"]
    return report["volume"]


def test_partdesign_part_infilled_exports_printable_and_follows_the_part(doc, tmp_path):
    body, infill = FRepExamples.build_bracket_infill(doc, wall=1.5, cell=5.0)
    doc.recompute()
    assert body.isValid() and infill.isValid(), infill.getStatusString()
    solid = body.Shape.Volume
    part = FRepTree.shape_of(infill)
    infilled = export_volume(part, str(tmp_path / "infill.stl"))
    skin = export_volume(frepcore.shell(FRepTree.shape_of(body), thickness=1.5),
                         str(tmp_path / "skin.stl"))
    # The skin alone < skin plus lattice < the solid part (every figure from a checked mesh).
    assert skin < infilled < solid, (skin, infilled, solid)
    assert infilled > skin * 1.1  # the lattice adds material, not only the skin
    # The holes stay holes: the bracket's field is the PartDesign shape, not its box.
    assert part(10, 12, 5) < 0

    # Changing the Body's pad recomputes the infill through the dependency graph.
    builds = len(FRepSolids.BUILDS)
    pad = doc.getObject("Pad")
    pad.Length = 14
    doc.recompute()
    assert infill.isValid(), infill.getStatusString()
    assert len(FRepSolids.BUILDS) == builds + 1  # the changed part tessellated again
    top = FRepTree.shape_of(infill).bounds()["box"][1][2]
    assert top == pytest.approx(14, abs=0.1)

    # An FRep-only change reuses the part's field (no new tessellation).
    infill.Cell = 5
    doc.recompute()
    assert infill.isValid(), infill.getStatusString()
    assert len(FRepSolids.BUILDS) == builds + 1


def test_mesh_feature_and_part_solid_are_inputs(doc, tmp_path):
    feature = doc.addObject("Mesh::Feature", "Ball")
    feature.Mesh = ball_mesh(tmp_path, 32)
    feature.Placement.Base = FreeCAD.Vector(3, 0, 0)
    solid = doc.addObject("Part::Feature", "Block")
    solid.Shape = Part.makeBox(1, 1, 1, FreeCAD.Vector(-0.5, -0.5, -0.5))
    u = F.make("union", doc, inputs=[feature, solid])
    doc.recompute()
    assert u.isValid(), u.getStatusString()
    s = FRepTree.shape_of(u)
    assert s(3, 0, 0) == pytest.approx(1.0, abs=0.05)  # the mesh, placed
    assert s(0, 0, 0) == pytest.approx(0.5, abs=1e-3)  # the box: its exact distance
    assert s(1.5, 0, 0) < 0
    assert FRepTree.is_frep_input(feature) and FRepTree.is_frep_input(solid)


def test_objects_without_a_solid_are_refused_naming_what_is_accepted(doc):
    face = doc.addObject("Part::Feature", "Flat")
    face.Shape = Part.makePlane(1, 1)
    u = F.make("union", doc, name="Join", inputs=[F.make("sphere", doc), face])
    doc.recompute()
    assert not u.isValid()
    assert "'Flat' (Part::Feature) is not an FRep input; accepted:" in u.getStatusString()
    assert "solids" in u.getStatusString()


def test_open_mesh_is_refused_pointing_to_repair_not_taken_as_overlapping(doc, tmp_path):
    ball = ball_mesh(tmp_path, 16)
    ball.removeFacets([0, 1, 2])  # a few triangles gone: open
    feature = doc.addObject("Mesh::Feature", "Dented")
    feature.Mesh = ball
    builds = len(FRepSolids.BUILDS)
    o = F.make("offset", doc, name="Grow", inputs=[feature])
    doc.recompute()
    assert not o.isValid()
    why = o.getStatusString()
    assert why.startswith("Dented: cannot be an FRep input: Dented (Mesh::Feature): the mesh "
                          "is open ("), why
    assert why.endswith("border edges), so it has no inside; select it and use FRep > Repair "
                        "mesh to mend it (FRep > Printability lists every defect)"), why
    assert "frepcad" not in why
    assert len(FRepSolids.BUILDS) == builds  # no level set built in its place


def test_solid_tolerance_is_a_document_setting(doc):
    cyl = doc.addObject("Part::Feature", "Rod")
    cyl.Shape = Part.makeCylinder(2, 5)
    t = F.make("translate", doc, inputs=[cyl])
    doc.recompute()
    assert t.isValid(), t.getStatusString()
    coarse = FRepSolids.solid_tolerance(doc, cyl.Shape)
    assert coarse == pytest.approx(1e-3 * cyl.Shape.BoundBox.DiagonalLength)
    FRepSolids.set_solid_tolerance(doc, 0.5)
    doc.recompute()
    assert FRepSolids.solid_tolerance(doc) == 0.5
    # A coarse tessellation: the polygon's flats come inside the circle.
    flat = FRepTree.shape_of(t)(0, 0, 2.5)
    assert 1.5 < flat < 2.0
    with pytest.raises(ValueError):
        FRepSolids.set_solid_tolerance(doc, -1)
    FRepSolids.set_solid_tolerance(doc, None)
    assert FRepSolids.solid_tolerance(doc, cyl.Shape) == pytest.approx(coarse)


def test_vdb_files_import_as_a_feature_and_solids_export_as_level_sets(doc, tmp_path):
    import FRepExport
    import FRepImport
    ball = F.make("sphere", doc, name="Ball", radius=2)
    doc.recompute()
    path = str(tmp_path / "ball.vdb")
    report = FRepExport.export_objects([ball], path, progress=lambda f: True, cells=40)
    assert report["written"] and "level set" in report["text"]
    grid = FRepImport.import_vdb(path, doc)
    doc.recompute()
    assert grid.isValid(), grid.getStatusString()
    assert grid.Proxy.FREP_TYPE == "vdb_grid" and grid.Grid == "surface"
    assert grid.Mesh.CountFacets > 0  # its surface is shown
    assert FRepTree.shape_of(grid)(0, 0, 1.9) == pytest.approx(0.1, abs=0.05)
    # A relative Path is read from the document's folder.
    doc.saveAs(str(tmp_path / "volume.FCStd"))
    grid.Path = "ball.vdb"
    doc.recompute()
    assert grid.isValid(), grid.getStatusString()
    grid.Path = "nothing.vdb"
    doc.recompute()
    assert not grid.isValid() and "nothing.vdb" in grid.getStatusString()
    # A file whose damaged leaf crashes OpenVDB's reader: frepcad reads it first, FreeCAD lives.
    damaged = os.path.join(os.path.dirname(__file__), "..", "data", "damaged_leaf.vdb")
    grid.Path = damaged
    doc.recompute()
    assert not grid.isValid() and "the OpenVDB file is damaged" in grid.getStatusString()
    with pytest.raises(OSError, match="damaged_leaf.vdb: the OpenVDB file is damaged"):
        FRepImport.import_vdb(damaged, doc)


def test_infill_made_on_a_part_is_sized_from_it_and_previews_as_a_lattice(doc):
    block = doc.addObject("Part::Box", "Bracket")
    block.Length, block.Width, block.Height = 40, 25, 12
    infill = F.make("infill", doc, inputs=[block], sized=True)
    doc.recompute()
    assert infill.isValid(), infill.getStatusString()
    # the skin from the part's smallest side (12 mm), the cells ten preview cells (40 mm / 48
    # cells each), the sheets a preview cell and a half across, all in mm
    assert infill.Wall.Value >= 0.02 * 12 and infill.Cell.Value >= 0.1 * 12
    assert infill.Thickness.Value >= 1.5 * 40 / 48 - 1e-3
    assert infill.Thickness.Value < infill.Cell.Value / 4
    # a lattice, not specks: one connected preview with most of the box hollow
    mesh = infill.Mesh
    assert 0.15 * 40 * 25 * 12 < mesh.Volume < 0.6 * 40 * 25 * 12
    assert mesh.CountFacets < 200000
    assert len(mesh.getSeparateComponents()) <= 3
    # given values stay as given; without sized, the registry's defaults
    plain = F.make("infill", doc, inputs=[block], sized=True, cell=2.0)
    assert plain.Cell.Value == 2.0 and plain.Wall.Value == pytest.approx(0.48)
    assert plain.Thickness.Value == pytest.approx(0.3)
    assert F.make("infill", doc, inputs=[block]).Cell.Value == 1.0


def test_a_section_is_closed_wires_that_part_and_sketcher_use(doc, tmp_path):
    """A ring (a ball with a bore) cut across: two closed loops on the surface, a face of the
    right area from them, an extrusion of the right volume, and a sketch that takes their
    edges as external geometry; the plane moved, the wires follow; saved and reopened, the
    same."""
    import math
    import Sketcher  # noqa: F401  (registers Sketcher::SketchObject)
    import FRepSection
    ball = F.make("sphere", doc, name="Ball", radius=2)
    bore = F.make("cylinder", doc, name="Bore", radius=0.8, length=6)
    ring = F.make("difference", doc, name="Ring", inputs=[ball, bore])
    section = FRepSection.make(ring, doc, origin=(0, 0, 0.5), normal=(0, 0, 1))
    doc.recompute()
    assert section.isValid(), section.getStatusString()
    assert section.Loops == 2 and len(section.Shape.Wires) == 2
    assert all(w.isClosed() for w in section.Shape.Wires)
    outer, inner = sorted(section.Shape.Wires, key=lambda w: -w.Length)
    big = math.sqrt(4 - 0.25)
    assert outer.Length == pytest.approx(2 * math.pi * big, rel=2e-3)
    assert inner.Length == pytest.approx(2 * math.pi * 0.8, rel=2e-3)
    for v in outer.Vertexes[::25]:  # on the ball, in the plane
        assert v.Point.Length == pytest.approx(2, abs=1e-6) and v.Point.z == pytest.approx(0.5)
    face = Part.Face([outer, inner])
    assert face.Area == pytest.approx(math.pi * (big ** 2 - 0.64), rel=3e-3)
    extrusion = doc.addObject("Part::Extrusion", "Slab")
    extrusion.Base = section
    extrusion.Dir = FreeCAD.Vector(0, 0, 0.2)
    extrusion.Solid = True
    sketch = doc.addObject("Sketcher::SketchObject", "Sketch")
    sketch.Placement = FreeCAD.Placement(FreeCAD.Vector(0, 0, 0.5), FreeCAD.Rotation())
    sketch.addExternal("Section", "Edge1")
    doc.recompute()
    assert extrusion.Shape.Volume == pytest.approx(face.Area * 0.2, rel=1e-6)
    assert len(sketch.ExternalGeometry) == 1 and sketch.isValid()
    section.Origin = FreeCAD.Vector(0, 0, 1.9)  # the bore takes all of the ball up there
    doc.recompute()
    assert section.isValid() and section.Loops == 0 and section.Shape.isNull()
    assert not extrusion.isValid()  # (a clean refusal: an empty compound crashed FreeCAD 0.20)
    section.Origin = FreeCAD.Vector(0, 0, 5)  # the plane misses the solid's box
    doc.recompute()
    assert section.isValid() and section.Loops == 0
    section.Origin = FreeCAD.Vector(0, 0, 0.5)
    doc.recompute()
    path = str(tmp_path / "section.FCStd")
    doc.saveAs(path)
    FreeCAD.closeDocument(doc.Name)
    again = FreeCAD.openDocument(path)
    try:
        again.getObject("Section").touch()
        again.recompute()
        assert again.getObject("Section").Loops == 2
    finally:
        FreeCAD.closeDocument(again.Name)


def test_a_point_sample_lies_on_the_surface(doc):
    """Points of a ball's surface, about a cell apart; more cells, more points."""
    import FRepPointSample
    ball = F.make("sphere", doc, name="Ball", radius=2, center=FreeCAD.Vector(1, 0, 0))
    sample = FRepPointSample.make(ball, doc, cells=24)
    doc.recompute()
    assert sample.isValid(), sample.getStatusString()
    points = sample.Points.Points
    assert sample.Count == len(points) > 500
    # on the surface to the mesh's single precision (its vertices are floats)
    assert max(abs((p - FreeCAD.Vector(1, 0, 0)).Length - 2) for p in points) < 1e-4
    coarse = sample.Count
    sample.Cells = 48
    doc.recompute()
    assert sample.Count > 3 * coarse
    sample.Cells = 2
    doc.recompute()
    assert not sample.isValid() and "'Cells' = 2 is out of range" in sample.getStatusString()


def test_partdesign_bracket_with_a_strut_infill_exports_printable(doc, tmp_path):
    """The bracket filled with octet struts (the infill's lattice CELL_struts, sized from the
    part as the toolbar does): a printable export lighter than the part and heavier than its
    skin, the holes kept."""
    body = FRepExamples.build_bracket(doc)
    doc.recompute()
    infill = F.make("infill", doc, inputs=[body], sized=True, lattice="octet_struts")
    doc.recompute()
    assert infill.isValid(), infill.getStatusString()
    assert infill.Lattice == "octet_struts"
    assert 0 < infill.Thickness.Value < infill.Cell.Value  # the struts' diameter, from the part
    part = FRepTree.shape_of(infill)
    infilled = export_volume(part, str(tmp_path / "struts.stl"), cells=128)
    skin = export_volume(frepcore.shell(FRepTree.shape_of(body), thickness=infill.Wall.Value),
                         str(tmp_path / "skin.stl"), cells=128)
    assert skin * 1.05 < infilled < body.Shape.Volume, (skin, infilled, body.Shape.Volume)
    assert part(10, 12, 5) < 0  # a hole stays a hole


def test_strut_infill_exports_as_a_beam_lattice_3mf(doc, tmp_path):
    """The Export command's beam lattice: the bracket infilled with octet struts written as
    beams clipped by its mesh, with its skin, read back by lib3mf with the same beam count; a
    solid that is no strut lattice is refused and leaves no file."""
    import FRepExport
    body = FRepExamples.build_bracket(doc)
    doc.recompute()
    infill = F.make("infill", doc, inputs=[body], sized=True, lattice="octet_struts")
    doc.recompute()
    path = str(tmp_path / "bracket_beams.3mf")
    report = FRepExport.export_objects([infill], path, cells=128, fmt="3mf-beams")
    assert report["written"] and report["printable"], report["text"]
    assert report["beams"] > 100 and report["skin_triangles"] > 0
    back = frepcore.read_3mf_beams(path)
    assert back == {"beams": report["beams"], "clipped": 0}  # (they end in the skin)
    assert not report["clipped"] and "ending in the middle of the skin" in report["summary"]
    assert report["mesh_tolerance"] > 0 and "simplified within" in report["summary"]
    meshed = str(tmp_path / "bracket.3mf")
    FRepExport.export_objects([infill], meshed, cells=128)
    assert os.path.getsize(path) < os.path.getsize(meshed)
    other = str(tmp_path / "body.3mf")
    with pytest.raises(ValueError, match="strut lattice"):
        FRepExport.export_objects([F.make("sphere", doc)], other, cells=32, fmt="3mf-beams")
    assert not os.path.exists(other)
