"""The reference models as FreeCAD documents, built with the workbench's own features.

Used by examples/make_documents.py (examples/*.FCStd), the tests and the benchmarks, so the
documents, the tests and the JSON references describe the same exact solids.
"""

import FreeCAD

import FRepFeatures as F
import FRepPolygonize


def build_csg(doc):
    """examples/csg.json: (cube [-1,1]^3 & sphere r 1.3) minus three infinite cylinders r 0.5
    along x, y, z. Returns the top feature (the Difference)."""
    box = F.make("box", doc, name="Cube", corner=(-1, -1, -1), size=(2, 2, 2))
    ball = F.make("sphere", doc, name="Ball", radius=1.3)
    core = F.make("intersection", doc, name="Core", inputs=[box, ball])
    holes = []
    for axis, name in (((1, 0, 0), "HoleX"), ((0, 1, 0), "HoleY"), ((0, 0, 1), "HoleZ")):
        holes.append(F.make("cylinder", doc, name=name, axis=axis, radius=0.5, length=0))
    return F.make("difference", doc, name="Part", inputs=[core] + holes)


def build_csg_spreadsheet(doc):
    """The csg part driven by a spreadsheet: cells Size (cube edge), Ball (sphere radius) and
    Hole (hole radius), with a Polygonize feature for export. Returns the Polygonize."""
    sheet = doc.addObject("Spreadsheet::Sheet", "Parameters")
    for row, (alias, value, text) in enumerate((("Size", 2, "cube edge"),
                                                ("Ball", 1.3, "sphere radius"),
                                                ("Hole", 0.5, "hole radius")), start=1):
        sheet.set("A%d" % row, text)
        sheet.set("B%d" % row, str(value))
        sheet.setAlias("B%d" % row, alias)
    doc.recompute()
    part = build_csg(doc)
    cube, ball = doc.getObject("Cube"), doc.getObject("Ball")
    for axis in ("x", "y", "z"):
        cube.setExpression("Size.%s" % axis, "Parameters.Size")
        cube.setExpression("Corner.%s" % axis, "-Parameters.Size / 2")
    ball.setExpression("Radius", "Parameters.Ball")
    for name in ("HoleX", "HoleY", "HoleZ"):
        doc.getObject(name).setExpression("Radius", "Parameters.Hole")
    mesh = FRepPolygonize.make(part, doc, name="PartMesh", Cells=160)
    return mesh


def _attach_flat(sketch, plane):
    """Puts a sketch flat on a datum plane. FreeCAD 1.0 renamed the attachment's Support to
    AttachmentSupport (0.20 has only Support)."""
    support = "AttachmentSupport" if "AttachmentSupport" in sketch.PropertiesList else "Support"
    setattr(sketch, support, (plane, [""]))
    sketch.MapMode = "FlatFace"


def build_bracket(doc, length=40.0, width=24.0, thickness=10.0, hole=3.5, fillet=4.0):
    """A PartDesign bracket, made as a user would: a sketched plate with corners rounded to
    `fillet` mm, padded to `thickness` mm, two holes pocketed through it. Returns the Body
    (its Tip is the pocket)."""
    import math
    import Part
    import Sketcher  # noqa: F401  (registers the sketch type)
    import FreeCAD
    body = doc.addObject("PartDesign::Body", "Bracket")
    plate = body.newObject("Sketcher::SketchObject", "PlateSketch")
    xy = [f for f in body.Origin.OriginFeatures if f.Role == "XY_Plane"][0]
    _attach_flat(plate, xy)
    # The corners are rounded in the sketch rather than by a Fillet on the pad's edges: a
    # fillet names its edges, and FreeCAD 1.0 renames a scripted pad's edges when its length
    # changes, so the fillet (and the body) would fail on the first edit.
    f, z = fillet, FreeCAD.Vector(0, 0, 1)
    centres = [(length - f, f), (length - f, width - f), (f, width - f), (f, f)]
    for i, (cx, cy) in enumerate(centres):
        start = math.radians(90 * i - 90)
        circle = Part.Circle(FreeCAD.Vector(cx, cy, 0), z, f)
        plate.addGeometry(Part.ArcOfCircle(circle, start, start + math.pi / 2))
        nx, ny = centres[(i + 1) % 4]
        end = FreeCAD.Vector(cx + f * math.cos(start + math.pi / 2),
                             cy + f * math.sin(start + math.pi / 2), 0)
        plate.addGeometry(Part.LineSegment(
            end, FreeCAD.Vector(nx + f * math.cos(start + math.pi / 2),
                                ny + f * math.sin(start + math.pi / 2), 0)))
    pad = body.newObject("PartDesign::Pad", "Pad")
    pad.Profile = plate
    pad.Length = thickness
    holes = body.newObject("Sketcher::SketchObject", "HoleSketch")
    _attach_flat(holes, xy)
    for x in (length * 0.25, length * 0.75):
        holes.addGeometry(Part.Circle(FreeCAD.Vector(x, width / 2, 0), z, hole))
    pocket = body.newObject("PartDesign::Pocket", "Holes")
    pocket.Profile = holes
    pocket.Type = 1  # through all,
    pocket.Midplane = True  # both ways from the sketch (which lies on the plate's bottom)
    doc.recompute()
    return body


def build_bracket_infill(doc, wall=1.5, cell=5.0):
    """The bracket (build_bracket) as a printable lightweight part: a gyroid infill inside a
    skin of `wall` mm. Returns (body, infill feature)."""
    body = build_bracket(doc)
    infill = F.make("infill", doc, name="BracketInfill", inputs=[body], lattice="gyroid",
                    wall=wall, cell=cell, level=0.25)
    return body, infill


def build_lattice_bend(doc, lift=12.0):
    """Seed 002's lattice, on an FRep part and on a mesh: a bar with three holes (FRep) and a
    FreeCAD mesh block beside it, each bent by lifting the two middle planes of control points
    of a 3 x 1 x 1 lattice fitted around it. Returns (part deform, mesh deform, lattices)."""
    import FRepLattice
    bar = F.make("box", doc, name="Bar", corner=(-30, -5, -4), size=(60, 10, 8))
    holes = [F.make("cylinder", doc, name="Hole%d" % n, center=(x, 0, 0), axis=(0, 0, 1),
                    radius=2.5, length=0) for n, x in enumerate((-15, 0, 15))]
    part = F.make("difference", doc, name="HoledBar", inputs=[bar] + holes)
    # The mesh: a block as fine triangles (a box of twelve would bend as twelve flat facets).
    import FRepMeshing
    from FRepPaths import frepcore
    block = doc.addObject("Mesh::Feature", "Block")
    block.Mesh = FRepMeshing.to_freecad_mesh(
        frepcore.box((60, 10, 8), corner=(-30, 25, -4)).mesh(cells=60))
    deforms, lattices = [], []
    for base in (part, block):
        lattice = FRepLattice.make_lattice(doc, target=base, divisions=(3, 1, 1), margin=0.05,
                                           name="Lattice" + base.Name)
        for i in (1, 2):
            for j in (0, 1):
                for k in (0, 1):
                    FRepLattice.move_point(lattice, (i, j, k), (0, 0, lift))
        deforms.append(FRepLattice.make_deform(doc, base, lattice, name="Bent" + base.Name))
        lattices.append(lattice)
    return deforms[0], deforms[1], lattices



def hspline_tutorial_steps(doc):
    """Seed 003's tutorial (appendix A) as FreeCAD steps on one HSpline feature, each its own
    undo step: a plane refined (A.2), a CV edited at level 1, two levels more and two CVs
    edited at level 3 (A.3), the level-1 CV moved again so the level-3 detail follows it, then
    Zero Offsets on level 3 and Unrefine (A.6). Yields (title, feature) after each step."""
    import FRepHSpline as H
    obj = H.make_plane(doc, 6, 6, 60.0, 60.0, name="Tutorial")
    doc.recompute()

    def refine_all():
        H.tag(obj, "level", level=0)
        H.refine(obj)
        H.set_tags(obj, [])

    def edit_level1():
        H.move_cv(obj, (1, 5, 5), tuple(H.hspline_of(obj).position(1, 5, 5))[:2] + (15.0,))
        H.set_tags(obj, [(1, 5, 5)])

    def refine_twice_and_edit_level3():
        for level in (1, 2):
            H.tag(obj, "level", level=level)
            H.refine(obj)
        for cv in ((3, 17, 16), (3, 20, 20)):
            H.nudge_cvs(obj, [cv], (0, 0, 0), along_normal=-8.0)
        H.set_tags(obj, [(3, 17, 16), (3, 20, 20)])

    def move_level1_again():
        H.nudge_cvs(obj, [(1, 5, 5)], (0, 0, 10.0))
        H.set_tags(obj, [(1, 5, 5)])

    def zero_level3():
        H.set_tags(obj, H.hspline_of(obj).select_non_zero(3))
        H.zero_offsets(obj)

    for title, action in (("Refine the plane", refine_all), ("Edit a CV at level 1", edit_level1),
                          ("Refine twice, edit at level 3", refine_twice_and_edit_level3),
                          ("Move the level-1 CV again", move_level1_again),
                          ("Zero the level-3 offsets", zero_level3),
                          ("Unrefine", lambda: H.unrefine(obj))):
        doc.openTransaction(title)
        action()
        doc.commitTransaction()
        doc.recompute()
        yield title, obj


def hspline_tutorial(doc, step=None):
    """The tutorial's feature after `step` steps (1 to 6; all by default)."""
    obj = None
    for done, (_, obj) in enumerate(hspline_tutorial_steps(doc), start=1):
        if step is not None and done >= step:
            break
    return obj


def build_attachment(doc, height=36.0):
    """Seed 003's attachment on a closed body: a limb (a tapered hspline cylinder of 6 rows)
    standing on a 2 x 2 rectangle of CVs on the outside of an hspline torus, joined through a
    Catmull-Clark seam and closed at its tip: one closed, printable surface. Returns (torus,
    limb, attachment)."""
    import FRepHSpline as H
    import FRepHSplineAttach as A
    torus = H.make_torus(doc, 12, 8, 30.0, 10.0, name="Body")
    doc.recompute()
    rect = (3, 5, 1, 3)  # (the rectangle may not wrap round the tube's seam, at j = 0)
    limb, joint = A.attach_new_cylinder(doc, torus, rect, rows=6, height=height)
    limb.Label, joint.Label = "Limb", "BodyWithLimb"
    joint.CloseEnd = True
    return torus, limb, joint


def build_envelope(doc, fold=60.0):
    """Seed 003's enveloping on a closed surface: an hspline ring (a torus) bound to two bones
    along its diameter; the second bone turned `fold` degrees about the joint folds the ring
    there. Level 0 is refined around the joint and level 1 there blends the two bones' frames,
    so the fold stays round. Returns (ring, bones, envelope)."""
    import FRepHSpline as H
    import FRepHSplineEnvelope as E
    ring = H.make_torus(doc, 16, 8, 30.0, 8.0, name="Ring")
    bones = [E.make_line(doc, (-40, 0, 0), (0, 0, 0), "Bone"),
             E.make_line(doc, (0, 0, 0), (40, 0, 0), "Bone")]
    env = E.make_envelope(doc, ring, bones)
    env.Label = "FoldedRing"
    doc.recompute()
    bones[1].Placement = FreeCAD.Placement(FreeCAD.Vector(), FreeCAD.Rotation(
        FreeCAD.Vector(0, 1, 0), -fold), FreeCAD.Vector(0, 0, 0))
    return ring, bones, env
