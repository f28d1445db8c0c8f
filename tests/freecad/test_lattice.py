"""Lattice deformation in FreeCAD: a Lattice fitted to an FRep part and to a mesh, Deform
features bending both printable, offsets that save, reopen and undo, Amount driven by an
expression, folds and wrong inputs refused with the reason, and only dependents
recomputed."""

import FreeCAD
import pytest

import FRepExamples
import FRepFeatures as F
import FRepLattice
import FRepTree
from FRepPaths import frepcore


def test_a_lattice_bends_an_frep_part_and_a_mesh_printable(doc, tmp_path):
    part, mesh, lattices = FRepExamples.build_lattice_bend(doc, lift=12.0)
    doc.recompute()
    for o in (part, mesh) + tuple(lattices):
        assert o.isValid(), "%s: %s" % (o.Label, o.getStatusString())
    # The FRep part is exact: its bounds rose with the lattice, its holes are still holes.
    shape = FRepTree.shape_of(part)
    box = shape.bounds()["box"]
    assert box[1][2] > 4 + 0.5 * 12  # the middle lifted by most of the control points' lift
    assert shape(0, 0, 0) < shape(0, 0, 6.9) or shape(0, 0, 0) < 0
    report = shape.export(str(tmp_path / "bent-part.stl"), cells=96)
    assert report["printable"], report["text"]
    # The mesh, deformed vertex by vertex, is printable and rose alike.
    assert mesh.Mesh.CountFacets > 1000
    assert mesh.Mesh.BoundBox.ZMax > 4 + 0.5 * 12
    fc_mesh = frepcore.read_mesh(_written(mesh.Mesh, tmp_path / "bent-mesh.stl"))
    assert fc_mesh.check()["printable"]
    # Both bent alike: their tops agree within a few percent of the lift.
    part_top = max(p[2] for p in frepcore.read_mesh(str(tmp_path / "bent-part.stl")).points)
    assert abs(mesh.Mesh.BoundBox.ZMax - part_top) < 0.05 * 12


def _written(freecad_mesh, path):
    freecad_mesh.write(str(path))
    return str(path)


def test_offsets_save_reopen_and_undo(doc, tmp_path):
    bar = F.make("box", doc, corner=(-10, -2, -2), size=(20, 4, 4))
    lattice = FRepLattice.make_lattice(doc, target=bar, divisions=(2, 1, 1))
    bent = FRepLattice.make_deform(doc, bar, lattice)
    doc.recompute()
    rest_top = FRepTree.shape_of(bent).bounds()["box"][1][2]
    doc.UndoMode = 1
    doc.openTransaction("lift")
    FRepLattice.move_point(lattice, (1, 0, 1), (0, 0, 5))
    FRepLattice.move_point(lattice, (1, 1, 1), (0, 0, 5))
    doc.commitTransaction()
    doc.recompute()
    lifted_top = FRepTree.shape_of(bent).bounds()["box"][1][2]
    assert lifted_top > rest_top + 1
    path = str(tmp_path / "lattice.FCStd")
    bent_name, lattice_name = bent.Name, lattice.Name
    doc.saveAs(path)
    name = doc.Name
    FreeCAD.closeDocument(name)
    again = FreeCAD.openDocument(path)
    try:
        again.recompute()
        b = again.getObject(bent_name)
        assert b.isValid(), b.getStatusString()
        assert FRepTree.shape_of(b).bounds()["box"][1][2] == pytest.approx(lifted_top, abs=1e-6)
        assert len(again.getObject(lattice_name).Offsets) == 12
    finally:
        FreeCAD.closeDocument(again.Name)


def test_undo_restores_the_lattice(doc):
    bar = F.make("box", doc, corner=(-10, -2, -2), size=(20, 4, 4))
    lattice = FRepLattice.make_lattice(doc, target=bar, divisions=(2, 1, 1))
    bent = FRepLattice.make_deform(doc, bar, lattice)
    doc.recompute()
    doc.UndoMode = 1
    top = FRepTree.shape_of(bent).bounds()["box"][1][2]
    doc.openTransaction("lift")
    FRepLattice.move_point(lattice, (1, 1, 1), (0, 0, 5))
    doc.commitTransaction()
    doc.recompute()
    assert FRepTree.shape_of(bent).bounds()["box"][1][2] > top + 0.5
    doc.undo()
    doc.recompute()
    assert list(lattice.Offsets) == []
    assert FRepTree.shape_of(bent).bounds()["box"][1][2] == pytest.approx(top, abs=1e-6)


def test_amount_is_driven_by_an_expression_and_only_dependents_recompute(doc):
    bar = F.make("box", doc, corner=(-10, -2, -2), size=(20, 4, 4))
    other = F.make("sphere", doc, radius=1, center=(40, 0, 0))
    lattice = FRepLattice.make_lattice(doc, target=bar, divisions=(2, 1, 1))
    for j in (0, 1):
        for k in (0, 1):
            FRepLattice.move_point(lattice, (1, j, k), (0, 0, 6))
    bent = FRepLattice.make_deform(doc, bar, lattice)
    doc.recompute()
    full = FRepTree.shape_of(bent).bounds()["box"][1][2]
    sheet = doc.addObject("Spreadsheet::Sheet", "Controls")
    sheet.set("A1", "0.5")
    sheet.setAlias("A1", "bend")
    lattice.setExpression("Amount", "Controls.bend")
    del F.EXECUTIONS[:]
    doc.recompute()
    half = FRepTree.shape_of(bent).bounds()["box"][1][2]
    assert lattice.Amount == pytest.approx(0.5)
    assert 2 < half < full - 1  # halfway up
    names = {n for _, n in F.EXECUTIONS}
    assert bent.Name in names and other.Name not in names


def test_folds_and_wrong_inputs_are_refused_with_the_reason(doc):
    bar = F.make("box", doc, corner=(-10, -2, -2), size=(20, 4, 4))
    lattice = FRepLattice.make_lattice(doc, target=bar, divisions=(4, 1, 1))
    for j in (0, 1):
        for k in (0, 1):
            FRepLattice.move_point(lattice, (2, j, k), (40, 0, 0))  # past its neighbours
    bent = FRepLattice.make_deform(doc, bar, lattice)
    doc.recompute()
    assert "Invalid" in lattice.State
    assert "folds over itself in cell (" in lattice.getStatusString() or \
        "folds over itself" in bent.getStatusString()
    lattice.Offsets = []
    doc.recompute()
    assert lattice.isValid() and bent.isValid()
    # Offsets of the wrong length, then a Deform without a lattice.
    lattice.Offsets = [FreeCAD.Vector()] * 3
    doc.recompute()
    assert "has 3 vectors; a 4 x 1 x 1 lattice has 20" in lattice.getStatusString()
    lattice.Offsets = []
    bent.Lattice = None
    doc.recompute()
    assert "must link a Lattice feature" in bent.getStatusString()
    # Changing the divisions resets offsets that no longer match.
    bent.Lattice = lattice
    FRepLattice.move_point(lattice, (1, 0, 0), (0, 0, 1))
    lattice.DivisionsX = 3
    assert list(lattice.Offsets) == []
    with pytest.raises(ValueError, match="does not exist"):
        FRepLattice.move_point(lattice, (9, 0, 0), (0, 0, 1))


def test_a_volume_feature_is_deformed_through_the_lattice(doc, tmp_path):
    """An imported .vdb (a VdbGrid feature) bent like any FRep solid: no gaps, printable."""
    import FRepImport
    path = str(tmp_path / "bar.vdb")
    frepcore.box((4, 1, 1), corner=(-2, -0.5, -0.5)).to_vdb(path, cells=48)
    volume = FRepImport.import_vdb(path, doc)
    lattice = FRepLattice.make_lattice(doc, target=volume, divisions=(2, 1, 1))
    for j in (0, 1):
        for k in (0, 1):
            FRepLattice.move_point(lattice, (1, j, k), (0, 0, 1.0))
    bent = FRepLattice.make_deform(doc, volume, lattice)
    doc.recompute()
    assert bent.isValid(), bent.getStatusString()
    shape = FRepTree.shape_of(bent)
    assert shape(0, 0, 0.45) > 0 > shape(0, 0, -0.45)  # the middle rose by about half of 1
    report = shape.export(str(tmp_path / "bent.stl"), cells=64)
    assert report["printable"], report["text"]


def test_an_exposed_control_point_is_driven_by_an_expression(doc):
    bar = F.make("box", doc, corner=(-10, -2, -2), size=(20, 4, 4))
    lattice = FRepLattice.make_lattice(doc, target=bar, divisions=(2, 1, 1))
    bent = FRepLattice.make_deform(doc, bar, lattice)
    doc.recompute()
    top = FRepTree.shape_of(bent).bounds()["box"][1][2]
    names = [FRepLattice.expose_point(lattice, (1, j, 1)) for j in (0, 1)]
    assert names == ["Point_1_0_1", "Point_1_1_1"]
    sheet = doc.addObject("Spreadsheet::Sheet", "Controls")
    sheet.set("A1", "6")
    sheet.setAlias("A1", "lift")
    for name in names:
        lattice.setExpression(name + ".z", "Controls.lift")
    doc.recompute()
    assert lattice.Point_1_0_1.z == pytest.approx(6)
    lifted = FRepTree.shape_of(bent).bounds()["box"][1][2]
    assert lifted > top + 1
    sheet.set("A1", "0")
    doc.recompute()
    assert FRepTree.shape_of(bent).bounds()["box"][1][2] == pytest.approx(top, abs=1e-6)
    # move_point on an exposed point sets its property
    lattice.setExpression("Point_1_0_1.z", None)
    FRepLattice.move_point(lattice, (1, 0, 1), (0, 0, 2))
    assert lattice.Point_1_0_1.z == 2


def test_straight_struts_follow_the_lattice_and_export_one_beam_a_strut(doc, tmp_path):
    """A beam of octet struts bent by a Lattice: Struts 'straight' keeps each strut straight
    from one end's image to the other's (the field is the radius at the middle of that chord;
    curved, the strut bows away from it), writes one beam a strut into a beam 3MF (fewer than
    the curved struts' chains) and saves and reopens."""
    import FRepExport
    cells = F.make("strut_lattice", doc, cell_type="octet", cell=(2.0, 2.0, 2.0), radius=0.1)
    block = F.make("box", doc, corner=(-10, -2, -2), size=(20, 4, 4))
    part = F.make("intersection", doc, inputs=[cells, block])
    lattice = FRepLattice.make_lattice(doc, target=part, divisions=(2, 1, 1))
    bent = FRepLattice.make_deform(doc, part, lattice)
    for j in (0, 1):
        for k in (0, 1):
            FRepLattice.move_point(lattice, (1, j, k), (0, 0, 6))
    doc.recompute()
    assert bent.isValid(), bent.getStatusString()
    assert bent.Struts == "curved"
    curved_facets = bent.Mesh.CountFacets
    # a strut across the cells' faces near the middle: from node (0, 0, 0) to (2, 0, 2)
    bend = lattice.Proxy.lattice(lattice)
    a, b = bend.deform((0.0, 0.0, 0.0)), bend.deform((2.0, 0.0, 2.0))
    middle = [(a[i] + b[i]) / 2 for i in range(3)]
    assert FRepTree.shape_of(bent)(*middle) < 0.1 - 0.01  # curved: the chord misses its axis
    bent.Struts = "straight"
    doc.recompute()
    assert bent.isValid(), bent.getStatusString()
    assert bent.Mesh.CountFacets != curved_facets
    assert FRepTree.shape_of(bent)(*middle) == pytest.approx(0.1, abs=1e-9)
    straight = FRepExport.export_objects([bent], str(tmp_path / "straight.3mf"), cells=96,
                                         fmt="3mf-beams")
    assert straight["written"], straight["text"]
    assert frepcore.read_3mf_beams(str(tmp_path / "straight.3mf"))["beams"] == straight["beams"]
    bent.Struts = "curved"
    doc.recompute()
    curved = FRepExport.export_objects([bent], str(tmp_path / "curved.3mf"), cells=96,
                                       fmt="3mf-beams")
    assert 100 < straight["beams"] < curved["beams"]
    bent.Struts = "straight"
    doc.recompute()
    _reopens_straight(doc, bent, tmp_path / "straight.FCStd", middle, 0.1)


def _reopens_straight(doc, obj, path, middle, radius):
    """Saved and reopened, obj keeps Struts straight: the field at a chord's middle is
    still the radius."""
    name = obj.Name
    doc.saveAs(str(path))
    again = FreeCAD.openDocument(str(path))
    try:
        again.recompute()
        reopened = again.getObject(name)
        assert reopened.Struts == "straight" and reopened.isValid()
        assert FRepTree.shape_of(reopened)(*middle) == pytest.approx(radius, abs=1e-9)
    finally:
        FreeCAD.closeDocument(again.Name)


def test_cells_round_a_cylinder_take_straight_struts(doc, tmp_path):
    """Octet cells round a tube's axis: Struts 'straight' makes each strut the chord between
    its ends round the axis (the field is the radius at the chord's middle; curved, the strut
    bows away from it), one beam a strut in a beam 3MF, and the choice saves and reopens."""
    import math
    import FRepExport
    cells = F.make("strut_lattice", doc, cell_type="simple_cubic", cell=(2.0, 2.0, 2.0),
                   radius=0.2, conform="cylinder", around=16)
    tube = F.make("difference", doc, inputs=[
        F.make("cylinder", doc, radius=9.0, length=8.0),
        F.make("cylinder", doc, radius=5.0, length=10.0)])
    part = F.make("intersection", doc, inputs=[cells, tube])
    doc.recompute()
    assert part.isValid(), part.getStatusString()
    assert cells.Struts == "curved"
    # a strut round the axis at 6 from it, from one cell's corner to the next
    turn = 2.0 * math.pi / 16
    a, b = (6.0, 0.0, 0.0), (6.0 * math.cos(turn), 6.0 * math.sin(turn), 0.0)
    middle = [(a[i] + b[i]) / 2 for i in range(3)]
    assert FRepTree.shape_of(cells)(*middle) < 0.2 - 0.02  # curved: the chord misses it
    curved = FRepExport.export_objects([part], str(tmp_path / "curved.3mf"), cells=96,
                                       fmt="3mf-beams")
    assert curved["written"], curved["text"]
    cells.Struts = "straight"
    doc.recompute()
    assert part.isValid(), part.getStatusString()
    assert FRepTree.shape_of(cells)(*middle) == pytest.approx(0.2, abs=1e-9)
    straight = FRepExport.export_objects([part], str(tmp_path / "straight.3mf"), cells=96,
                                         fmt="3mf-beams")
    assert straight["written"], straight["text"]
    assert frepcore.read_3mf_beams(str(tmp_path / "straight.3mf"))["beams"] == straight["beams"]
    assert 100 < straight["beams"] < curved["beams"]
    _reopens_straight(doc, cells, tmp_path / "round.FCStd", middle, 0.2)
