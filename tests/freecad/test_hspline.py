"""Hspline features in FreeCAD: the exact surface as a Part face or solid, seed
003's tutorial steps, the hierarchy saved in properties (reopen, undo), tags refusing fixed
CVs, B-spline faces as level 0, and .hs, STEP and checked STL exports."""

import FreeCAD
import Part
import pytest

import FRepExamples
import FRepHSpline as H
import FRepHSplineStruts as S
from FRepPaths import frepcore


def _points(obj, n=7):
    surface = obj.Shape.Faces[0].Surface
    u0, u1, v0, v1 = surface.bounds()
    return [surface.value(u0 + (u1 - u0) * (a + 0.3) / n, v0 + (v1 - v0) * (b + 0.6) / n)
            for a in range(n) for b in range(n)]


def _reopened(doc, path):
    """The document saved to path, closed and opened again (the caller closes it)."""
    doc.saveAs(path)
    FreeCAD.closeDocument(doc.Name)
    return FreeCAD.openDocument(path)


def test_the_tutorial_refines_edits_zeroes_and_unrefines(doc):
    obj = FRepExamples.hspline_tutorial(doc)
    assert obj.isValid(), obj.getStatusString()
    # After the whole tutorial: level 3's detail zeroed and unrefined away, level 1's kept.
    h = H.hspline_of(obj)
    assert h.level_count == 2 and obj.Levels == 2
    assert h.select_non_zero() == [(1, 5, 5)]
    face = obj.Shape.Faces[0]
    assert isinstance(face.Surface, Part.BSplineSurface)
    # The Part face is the hierarchy: sample both.
    s = face.Surface
    for u, v in ((0.3, 0.4), (1.7, 2.2), (2.5, 1.1)):
        p = s.value(u, v)
        assert (p - FreeCAD.Vector(*h.evaluate(u, v)["point"])).Length < 1e-9


def test_each_tutorial_step_is_one_undo_step_and_level3_follows_level1(doc):
    doc.UndoMode = 1
    obj = FRepExamples.hspline_tutorial(doc, step=3)
    h = H.hspline_of(obj)
    assert h.level_count == 4
    dent = h.evaluate(*h.reference(3, 17, 16))["point"]
    base = h.evaluate(*h.reference(3, 17, 16), level=2)["point"]
    assert base[2] - dent[2] > 1.0  # the level-3 edit dents the surface
    doc.openTransaction("lift")
    H.nudge_cvs(obj, [(1, 5, 5)], (0, 0, 10.0))
    doc.commitTransaction()
    doc.recompute()
    h2 = H.hspline_of(obj)
    moved_dent = h2.evaluate(*h2.reference(3, 17, 16))["point"]
    moved_base = h2.evaluate(*h2.reference(3, 17, 16), level=2)["point"]
    assert moved_base[2] > base[2] + 1.0            # level 1's move lifted the region...
    assert moved_base[2] - moved_dent[2] > 1.0       # ...and the dent came along
    doc.undo()
    doc.recompute()
    assert H.hspline_of(obj).to_text() == h.to_text()
    doc.undo()  # step 3 as a whole
    doc.recompute()
    assert H.hspline_of(obj).level_count == 2


def test_the_hierarchy_saves_and_reopens(doc, tmp_path):
    obj = H.make_torus(doc, 10, 8, 30, 10)
    doc.recompute()
    H.set_tags(obj, [(0, 3, 3), (0, 4, 3)])
    H.refine(obj)
    H.nudge_cvs(obj, H.tags(obj)[:1], (0, 0, 0), along_normal=3.0)
    doc.recompute()
    assert obj.Shape.ShapeType == "Solid" and obj.Shape.isValid()
    volume, text, name = obj.Shape.Volume, H.hspline_of(obj).to_text(), obj.Name
    again = _reopened(doc, str(tmp_path / "hspline.FCStd"))
    try:
        restored = again.getObject(name)
        again.recompute()
        assert H.hspline_of(restored).to_text() == text
        assert restored.Shape.Volume == pytest.approx(volume, rel=1e-9)
        assert H.tags(restored)
    finally:
        FreeCAD.closeDocument(again.Name)


def test_tags_refuse_fixed_cvs_and_the_rules_select(doc):
    obj = H.make_plane(doc, 12, 12, 100, 100)
    doc.recompute()
    H.set_tags(obj, [(0, 5, 5)])
    fresh = H.refine(obj)
    assert fresh == [(1, 9, 9)]  # the one movable CV of a 7 x 7 block
    with pytest.raises(ValueError, match=r"CV \(level 1, i 8, j 9\) is fixed"):
        H.tag_cv(obj, (1, 8, 9))
    with pytest.raises(ValueError, match="is fixed"):
        H.move_cv(obj, (1, 6, 6), (0, 0, 5))
    assert H.tag(obj, "along_u") == [(1, i, 9) for i in range(6, 13)]
    assert H.tag(obj, "untag_fixed") == [(1, 9, 9)]
    with pytest.raises(ValueError, match="Zero Offsets acts on CVs of level 1"):
        H.zero_offsets(obj, [(0, 1, 1)])
    with pytest.raises(ValueError, match="only a closed hspline"):
        H.set_make_solid(obj)


def test_a_bspline_face_becomes_level_zero_exactly(doc):
    plane = Part.makePlane(40, 30).toNurbs().Faces[0]
    s = plane.Surface
    s.increaseDegree(3, 3)
    s.insertUKnot(0.4, 1, 1e-9)  # an uneven knot: level 0 need not be uniform
    s.setPole(2, 2, s.getPole(2, 2) + FreeCAD.Vector(0, 0, 5))
    obj = H.make_from_face(doc, s.toShape(), label="test face")
    doc.recompute()
    mine = obj.Shape.Faces[0].Surface
    u0, u1, v0, v1 = s.bounds()
    assert mine.bounds() == pytest.approx((u0, u1, v0, v1))
    for a, b in ((0.1, 0.2), (0.45, 0.7), (0.9, 0.35), (1.0, 1.0)):
        u, v = u0 + a * (u1 - u0), v0 + b * (v1 - v0)
        assert (s.value(u, v) - mine.value(u, v)).Length < 1e-9
    # A periodic face (an hspline torus's own) comes back as the same surface.
    torus = H.make_torus(doc, 9, 7, 20, 6)
    doc.recompute()
    again = H.make_from_face(doc, torus.Shape.Faces[0], label="the torus")
    doc.recompute()
    a, b = torus.Shape.Faces[0].Surface, again.Shape.Faces[0].Surface
    assert again.PeriodU > 0 and again.PeriodV > 0
    for u, v in ((0.3, 0.2), (4.5, 3.3), (8.9, 6.9)):
        assert (a.value(u, v) - b.value(u, v)).Length < 1e-9
    sphere = Part.makeSphere(5).Faces[0]
    with pytest.raises(ValueError, match="not a B-spline surface"):
        H.make_from_face(doc, sphere, label="the sphere")
    with pytest.raises(ValueError, match="is rational"):
        H.make_from_face(doc, Part.makeSphere(5).toNurbs().Faces[0], label="the sphere")


def test_exports_hs_step_and_a_checked_stl(doc, tmp_path):
    obj = H.make_torus(doc, 10, 8, 30, 10)
    doc.recompute()
    H.set_tags(obj, [(0, 2, 2)])
    H.refine(obj)
    H.nudge_cvs(obj, H.tags(obj), (0, 0, 0), along_normal=2.0)
    doc.recompute()
    hs = str(tmp_path / "t.hs")
    H.export_hs(obj, hs, optimised=True)
    copy = H.import_hs(doc, hs)
    doc.recompute()
    assert copy.Shape.Volume == pytest.approx(obj.Shape.Volume, rel=1e-9)
    assert copy.CvCount <= obj.CvCount
    step = str(tmp_path / "t.step")
    H.export_step(obj, step)
    back = Part.read(step)
    assert back.Solids and back.isValid()
    assert back.Volume == pytest.approx(obj.Shape.Volume, rel=1e-6)
    stl = str(tmp_path / "t.stl")
    report = H.export_mesh(obj, stl, tolerance=0.02)
    assert report["printable"]
    assert frepcore.read_mesh(stl).check()["printable"]


def test_a_cv_of_its_own_is_driven_by_its_property_and_an_expression(doc, tmp_path):
    obj = H.make_plane(doc, 12, 12, 100, 100)
    doc.recompute()
    H.set_tags(obj, [(0, 5, 5)])
    H.refine(obj)
    doc.recompute()
    with pytest.raises(ValueError, match="is fixed, so it gets no property"):
        H.expose_cv(obj, (1, 8, 9))
    name = H.expose_cv(obj, (1, 9, 9))
    assert name == "Cv_1_9_9" and obj.getGroupOfProperty(name) == "CVs"
    u, v = H.hspline_of(obj).reference(1, 9, 9)
    flat = H.hspline_of(obj).evaluate(u, v)["point"][2]
    sheet = doc.addObject("Spreadsheet::Sheet", "Controls")
    sheet.set("A1", "7")
    sheet.setAlias("A1", "lift")
    doc.recompute()
    obj.setExpression(name + ".z", "Controls.lift")
    doc.recompute()
    lifted = H.hspline_of(obj).evaluate(u, v)["point"][2]
    assert lifted > flat + 1.0  # the offset along the normal, driven by the spreadsheet
    assert obj.Shape.BoundBox.ZMax > 1.0
    # A move of the CV (a drag) lands in its property.
    obj.setExpression(name + ".z", None)
    H.nudge_cvs(obj, [(1, 9, 9)], (0, 0, 0), along_normal=2.0)
    assert getattr(obj, name).z == pytest.approx(9.0)
    feature = obj.Name
    again = _reopened(doc, str(tmp_path / "exposed.FCStd"))
    try:
        restored = again.getObject(feature)
        again.recompute()
        assert getattr(restored, name).z == pytest.approx(9.0)
        assert H.hspline_of(restored).value(1, 9, 9)[2] == pytest.approx(9.0)
    finally:
        FreeCAD.closeDocument(again.Name)


def test_a_closed_hspline_is_an_frep_input(doc, tmp_path, monkeypatch):
    """A closed hspline is a Part solid, so FRep operations take it (as the signed distance
    to its own tessellation, not MeshPart's) and the result exports printable."""
    import FRepFeatures as F
    import FRepTree
    import MeshPart

    def refuse(**_):
        raise AssertionError("MeshPart was asked to tessellate the hspline")
    monkeypatch.setattr(MeshPart, "meshFromShape", refuse)
    torus = H.make_torus(doc, 10, 8, 30, 10)
    doc.recompute()
    H.set_tags(torus, [(0, 2, 2)])
    H.refine(torus)
    H.nudge_cvs(torus, H.tags(torus), (0, 0, 0), along_normal=4.0)
    ball = F.make("sphere", doc, radius=12, center=(-30, 0, 0))
    union = F.make("union", doc, inputs=[torus, ball])
    doc.recompute()
    assert union.isValid(), union.getStatusString()
    shape = FRepTree.shape_of(union)
    assert shape(-30, 0, 0) > 0 and shape(0, 0, 0) < 0  # inside the ball, in the torus's hole
    assert shape(0, 30, 0) > 0 and shape(0, 30, 12) < 0  # on the tube's centre circle; above it
    report = shape.export(str(tmp_path / "union.stl"), cells=80)
    assert report["printable"], report["text"]


def test_an_attachment_joins_a_cylinder_and_follows_its_edits(doc):
    import FRepHSplineAttach as A
    body = H.make_plane(doc, 10, 10, 90, 90)
    doc.recompute()
    limb, joint = A.attach_new_cylinder(doc, body, (3, 6, 3, 6), rows=5, height=30)
    joint.CloseEnd = False  # the open rim keeps its row's height (the boundary rule)
    doc.recompute()
    assert joint.isValid(), joint.getStatusString()
    assert joint.Mesh.CountFacets > 4000 and joint.Mesh.BoundBox.ZMax == pytest.approx(30, abs=1e-3)
    # Raising the cylinder's top row raises the joined surface.
    top = [(0, k, 4) for k in range(12)]
    H.nudge_cvs(limb, top, (0, 0, 10.0))
    doc.recompute()
    assert joint.Mesh.BoundBox.ZMax == pytest.approx(40, abs=1e-3)
    joint.I1 = 7  # the ring no longer has the cylinder's 12 CVs
    doc.recompute()
    assert "Invalid" in joint.State


def _tube_volume(obj, n=64):
    """The volume of an open tube's surface closed by flat fans at its two end rings."""
    surface = obj.Shape.Faces[0].Surface
    u0, u1, v0, v1 = surface.bounds()
    rows = [[surface.value(u0 + (u1 - u0) * a / n, v0 + (v1 - v0) * b / (3 * n))
             for a in range(n)] for b in range(3 * n + 1)]
    tet = lambda a, b, c: a.dot(b.cross(c)) / 6.0
    volume = 0.0
    for b in range(3 * n):
        for a in range(n):
            p, q = rows[b], rows[b + 1]
            volume += tet(p[a], p[(a + 1) % n], q[(a + 1) % n]) + tet(p[a], q[(a + 1) % n], q[a])
    for row, sign in ((rows[0], -1), (rows[-1], 1)):
        c = sum(row, FreeCAD.Vector()) * (1.0 / n)
        volume += sum(sign * tet(c, row[a], row[(a + 1) % n]) for a in range(n))
    return abs(volume)


def test_an_envelope_bends_a_joint_without_collapsing_and_reopens(doc, tmp_path):
    import FRepHSplineEnvelope as E
    arm = H.make_cylinder(doc, 8, 12, 10, 80, name="Arm")
    upper = E.make_line(doc, (0, 0, 0), (0, 0, 40), "Upper")
    fore = E.make_line(doc, (0, 0, 40), (0, 0, 80), "Fore")
    env = E.make_envelope(doc, arm, [upper, fore])
    doc.recompute()
    assert env.isValid(), env.getStatusString()
    rest = _tube_volume(env)
    assert env.Levels == 2 and "blended across 1 joint" in env.Binding
    # The forearm turned 90 degrees about the elbow, as the Transform tool would do it.
    fore.Placement = FreeCAD.Placement(FreeCAD.Vector(), FreeCAD.Rotation(FreeCAD.Vector(1, 0, 0), 90),
                                       FreeCAD.Vector(0, 0, 40))
    doc.recompute()
    assert env.isValid(), env.getStatusString()
    box = env.Shape.BoundBox
    assert box.ZMax < 55 and box.YMin == pytest.approx(-80 + 40, abs=0.5)
    assert _tube_volume(env) == pytest.approx(rest, rel=0.025)
    # Its CVs are the segments' to move; the Base's edits come through.
    with pytest.raises(ValueError, match="edit the CVs of its Base 'Arm'"):
        H.refine(env, [(0, 1, 1)])
    H.nudge_cvs(arm, [(0, k, 0) for k in range(8)], (0, 0, -5))
    doc.recompute()
    assert env.Shape.BoundBox.ZMin == pytest.approx(-5, abs=1e-6)
    # Set rest pose: the bent pose becomes the rest, the surface its Base's.
    path, name = str(tmp_path / "envelope.FCStd"), env.Name
    again = _reopened(doc, path)
    try:
        env2 = again.getObject(name)
        again.recompute()
        assert env2.isValid() and env2.Shape.BoundBox.ZMax < 55
        E.set_rest_pose(env2)
        again.recompute()
        assert env2.Shape.BoundBox.ZMax == pytest.approx(80, abs=1e-6)
    finally:
        FreeCAD.closeDocument(again.Name)


def test_an_envelope_names_what_is_wrong(doc):
    import FRepHSplineEnvelope as E
    arm = H.make_cylinder(doc, 8, 12, 10, 80, name="Arm")
    box = doc.addObject("Part::Box", "Box")
    env = E.make_envelope(doc, arm, [E.make_line(doc, (0, 0, 0), (0, 0, 80))])
    doc.recompute()
    assert env.isValid()
    env.Segments = [box]
    doc.recompute()
    assert "Invalid" in env.State
    assert "neither a straight line" in env.getStatusString()


def test_an_attachment_s_rectangle_rebuilds_the_limb_and_bad_ones_are_named(doc):
    import FRepHSplineAttach as A
    body = H.make_plane(doc, 10, 10, 90, 90)
    doc.recompute()
    H.set_tags(body, [(0, 2, 2), (0, 4, 5)])
    rect = A.default_rectangle(body)
    assert rect == (2, 4, 2, 5)
    limb, joint = A.attach_new_cylinder(doc, body, rect, height=A.default_height(body))
    doc.recompute()
    assert joint.isValid(), joint.getStatusString()
    assert H._shared(limb).grid_size(0)[0] == 2 * 2 + 2 * 3
    A.set_rectangle(joint, (3, 6, 3, 6))  # a bigger ring: the limb gets 12 CVs around
    doc.recompute()
    assert joint.isValid(), joint.getStatusString()
    assert H._shared(limb).grid_size(0)[0] == 12
    for bad, says in (((6, 3, 3, 6), "0 <= I0 < I1 <= 9"), ((3, 6, 3, 10), "0 <= J0 < J1 <= 9")):
        with pytest.raises(ValueError, match=says):
            A.set_rectangle(joint, bad)
    assert (joint.I0, joint.I1, joint.J0, joint.J1) == (3, 6, 3, 6)


def test_a_refined_seam_doubles_the_ring_and_keeps_the_rectangle_where_it_was(doc):
    import FRepHSplineAttach as A
    body = H.make_plane(doc, 10, 10, 90, 90)
    doc.recompute()
    limb, joint = A.attach_new_cylinder(doc, body, (3, 6, 3, 6), height=10)
    doc.recompute()
    coarse = joint.Mesh.CountFacets
    box = joint.Mesh.BoundBox
    rect = joint.Proxy.set_seam_level(joint, 1)
    doc.recompute()
    assert joint.isValid(), joint.getStatusString()
    i0, i1, j0, j1 = rect
    assert H._shared(limb).grid_size(0)[0] == 2 * (i1 - i0) + 2 * (j1 - j0) == 24
    assert joint.Mesh.CountFacets > 2 * coarse
    # the ring lies where it was: the joined surface spans about the same box
    fine = joint.Mesh.BoundBox
    assert abs(fine.XLength - box.XLength) < 1 and abs(fine.ZMax - box.ZMax) < 2
    nu, nv = joint.Proxy.parent_grid(joint)
    assert nu > 10 and nv > 10 and H._shared(body).level_count == 1  # (the body unchanged)
    with pytest.raises(ValueError, match="0 <= I0 < I1 <= %d" % (nu - 1)):
        A.set_rectangle(joint, (0, 30, 0, 30))


def test_placements_are_segments_too_and_a_new_segment_keeps_the_others_rest_pose(doc):
    import FRepHSplineEnvelope as E
    arm = H.make_cylinder(doc, 8, 12, 10, 80, name="Arm")
    upper = doc.addObject("App::Placement", "Shoulder")  # runs to the next segment's origin
    elbow = doc.addObject("App::Placement", "Elbow")
    elbow.Placement.Base = FreeCAD.Vector(0, 0, 40)
    env = E.make_envelope(doc, arm, [upper, elbow])
    doc.recompute()
    assert env.isValid(), env.getStatusString()
    assert "blended across 1 joint" in env.Binding
    # the elbow turned about its own origin: the forearm (the last segment, along its local Z
    # as long as the one before it) goes with it
    elbow.Placement = FreeCAD.Placement(FreeCAD.Vector(0, 0, 40),
                                        FreeCAD.Rotation(FreeCAD.Vector(1, 0, 0), 90))
    doc.recompute()
    bent = env.Shape.BoundBox
    assert bent.ZMax < 55 and bent.YMin == pytest.approx(-40, abs=0.5)
    # a third segment added later takes its rest pose where it is; the others keep theirs
    wrist = E.make_line(doc, (0, -40, 40), (0, -50, 40), "Wrist")
    env.Segments = [upper, elbow, wrist]
    doc.recompute()
    assert env.isValid(), env.getStatusString()
    assert env.Shape.BoundBox.ZMax < 55


def test_the_rectangle_comes_from_the_tagged_cvs_of_the_shown_level(doc):
    import FRepHSplineAttach as A
    body = H.make_plane(doc, 10, 10, 90, 90)
    doc.recompute()
    assert A.default_placement(body, -1) == (0, (4, 6, 4, 6))  # nothing tagged: the middle
    H.refine(body, [(0, i, j) for i in range(2, 8) for j in range(2, 8)])
    H.set_tags(body, [(0, 3, 3), (0, 6, 6), (1, 6, 6), (1, 11, 12)])
    assert A.default_placement(body, 0) == (0, (3, 6, 3, 6))
    assert A.default_placement(body, -1) == (1, (6, 11, 6, 12))  # the finest shown
    level, rect = A.default_placement(body, 1)
    limb, joint = A.attach_new_cylinder(doc, body, rect, height=10, level=level)
    doc.recompute()
    assert joint.isValid(), joint.getStatusString()
    assert joint.SeamLevel == 1 and H._shared(limb).grid_size(0)[0] == 2 * 5 + 2 * 6


def test_struts_along_an_arched_hspline_follow_it(doc):
    import FRepMeshing
    obj = H.make_plane(doc, 6, 5, 30.0, 20.0)
    doc.recompute()
    for i, dz in ((1, 5.0), (2, 9.0), (3, 9.0), (4, 5.0)):  # an arch along u
        H.nudge_cvs(obj, [(0, i, j) for j in range(5)], delta=(0, 0, dz))
    doc.recompute()
    assert S.default_shell_thickness(obj) == pytest.approx(1.5)  # a twentieth of 30
    FRepMeshing.set_preview_cells(doc, 160)
    top, result = S.struts_along(obj, 3.0, cell=1.5)
    doc.recompute()
    assert top.isValid(), top.getStatusString()
    assert top.Label == "Struts along " + obj.Label
    assert result["divisions"] == (5, 4)
    assert result["deviation"] < 0.05 * 3.0
    assert result["size"][0] > 31.0  # the arch is longer than the plane it was
    assert top.Mesh.CountFacets > 10000
    # every vertex lies in the shell: within half the thickness of the surface (and the fit's
    # deviation and a preview cell)
    face = obj.Shape.Faces[0]
    cell = 36.0 / 160
    points = top.Mesh.Points
    for p in points[::max(1, len(points) // 150)]:
        d = face.distToShape(Part.Vertex(p.Vector))[0]
        assert d < 1.5 + result["deviation"] + cell, (p.Vector, d)
    # the arch's top: the shell reaches above the surface's highest point
    assert top.Mesh.BoundBox.ZMax > obj.Shape.BoundBox.ZMax + 0.5
    assert float(top.Deviation) == pytest.approx(result["deviation"])
    names = [o.Name for o in doc.Objects]
    with pytest.raises(ValueError, match="property 'Thickness' = 0 mm is out of range"):
        S.struts_along(obj, 0.0)
    assert [o.Name for o in doc.Objects] == names  # (none left behind)


def test_struts_along_follow_the_surface_when_it_changes(doc, tmp_path):
    """The Struts along feature is fitted again when its surface's CVs move or a setting
    changes: the cells rise with a raised arch; a wrong setting is one line naming the
    property; Struts straight and the settings save and reopen."""
    obj = H.make_plane(doc, 6, 5, 30.0, 20.0)
    doc.recompute()
    struts = S.make_struts_along(doc, obj, thickness=3.0, cell=1.5)
    doc.recompute()
    assert struts.isValid(), struts.getStatusString()
    flat_top = struts.Mesh.BoundBox.ZMax
    assert flat_top < 1.5 + 0.5
    H.nudge_cvs(obj, [(0, i, j) for i in (2, 3) for j in range(5)], delta=(0, 0, 8.0))
    doc.recompute()
    assert struts.isValid(), struts.getStatusString()
    assert struts.Mesh.BoundBox.ZMax > flat_top + 4.0  # the cells rose with the surface
    assert 0 < float(struts.Deviation) < 0.05 * 3.0
    raised = struts.Mesh.CountFacets
    struts.CellType = "bcc"
    doc.recompute()
    assert struts.isValid() and struts.Mesh.CountFacets != raised
    struts.Thickness = 0.0
    doc.recompute()
    assert not struts.isValid()
    message = struts.getStatusString()
    assert "property 'Thickness' = 0 mm is out of range; allowed: (0, inf) mm" in message
    assert "\n" not in message.strip()
    struts.Thickness = 3.0
    struts.Struts = "straight"
    doc.recompute()
    assert struts.isValid(), struts.getStatusString()
    path = str(tmp_path / "struts-along.FCStd")
    name, facets = struts.Name, struts.Mesh.CountFacets
    doc.saveAs(path)
    again = FreeCAD.openDocument(path)
    try:
        reopened = again.getObject(name)
        reopened.touch()
        again.recompute()
        assert reopened.isValid(), reopened.getStatusString()
        assert reopened.Struts == "straight" and reopened.CellType == "bcc"
        assert reopened.Surface.Name == obj.Name
        assert reopened.Mesh.CountFacets == facets
    finally:
        FreeCAD.closeDocument(again.Name)
