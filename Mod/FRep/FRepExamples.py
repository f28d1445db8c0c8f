"""The reference models as FreeCAD documents, built with the workbench's own features.

Used by examples/make_documents.py (examples/*.FCStd), the tests and the benchmarks, so the
documents, the tests and the JSON references describe the same exact solids.
"""

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
