#!/usr/bin/python3
"""Writes the example FreeCAD documents with the workbench's own features:

    examples/csg.FCStd              the csg reference model (examples/csg.json) as features
    examples/csg_spreadsheet.FCStd  the same part driven by a spreadsheet, with a Polygonize
    examples/showcase.FCStd         seed 000's showcase shapes, from examples/showcase/*.json
    examples/twist.FCStd, helix.FCStd, gyroid.FCStd
                                    the reference models of the same names, imported from
                                    their .json files (File > Open does the same)
    examples/lattice.FCStd          lattices bending an FRep bar with holes and a mesh block
    examples/hspline.FCStd          seed 003's hspline tutorial after its editing steps
    examples/bracket.FCStd          a PartDesign bracket filled with the gyroid infill
    examples/attachment.FCStd       an hspline limb attached to an hspline torus, closed
    examples/envelope.FCStd         an hspline ring folded by two enveloping bones

FREP_EXAMPLES=lattice,csg (names, comma-separated) writes only those documents.

Run with `make examples` (after `make`). It starts the FreeCAD GUI under Xvfb and runs itself
there: a document saved headless has no GuiDocument.xml, and FreeCAD then opens it with
every object shown, the consumed inputs included. The documents hold their preview meshes
at a modest preview resolution so that they stay small in the repository; a recompute in
FreeCAD or `frepcad export` rebuilds everything from the exact tree.
"""

import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

# Saved previews and the saved Polygonize mesh: coarse, to keep the files small.
PREVIEW_CELLS = 48
POLYGONIZE_CELLS = 48


def launch():
    """Outside FreeCAD: start the GUI under Xvfb with this file as its macro."""
    build = os.path.abspath(os.environ.get("BUILD_DIR", os.path.join(ROOT, "build")))
    log = os.path.join(build, "make_documents.log")
    rc = subprocess.run(["bash", os.path.join(ROOT, "scripts", "run-freecad-gui.sh"), build,
                         os.path.abspath(__file__), log, "300"],
                        env=dict(os.environ, FREP_MAKE_DOCUMENTS="1")).returncode
    with open(log) as f:
        lines = [line for line in f if line.startswith(("wrote ", "error"))]
    sys.stdout.write("".join(lines))
    if rc != 0:
        sys.stdout.write("make_documents failed (exit %d); see %s\n" % (rc, log))
    return rc


def save(doc, name):
    """Saves atomically: a temporary file in examples/, then a rename."""
    import FreeCAD
    import FreeCADGui
    broken = [o.Label for o in doc.Objects if "Invalid" in o.State]
    if broken:
        raise RuntimeError("%s: recompute failed for %s" % (name, ", ".join(broken)))
    view = FreeCADGui.getDocument(doc.Name).ActiveView
    view.viewIsometric()
    view.fitAll()
    path = os.path.join(HERE, name + ".FCStd")
    tmp = os.path.join(HERE, ".%s.tmp.FCStd" % name)
    doc.saveAs(tmp)
    FreeCAD.closeDocument(doc.Name)
    os.replace(tmp, path)
    print("wrote %s (%d kB)" % (os.path.relpath(path, ROOT), os.path.getsize(path) // 1024))


def new_document(name, comment, preview_cells=PREVIEW_CELLS):
    import FreeCAD
    import FRepMeshing
    doc = FreeCAD.newDocument(name)
    doc.Comment = comment
    doc.Meta = dict(doc.Meta, **{FRepMeshing.PREVIEW_KEY: str(preview_cells)})
    return doc


def wanted(name):
    only = os.environ.get("FREP_EXAMPLES", "")
    return not only or name in only.split(",")


def build():
    """Inside the FreeCAD GUI."""
    import FreeCAD
    import FRepExamples

    if wanted("lattice"):
        doc = new_document("lattice", "Seed 002's lattice deformation: a 3 x 1 x 1 lattice "
                           "lifts the middle of an FRep bar with three holes (pulled back "
                           "through the lattice's inverse: exact), another bends a mesh block "
                           "(vertices moved). Double-click a lattice to drag its points.")
        FRepExamples.build_lattice_bend(doc)
        doc.recompute()
        save(doc, "lattice")

    if wanted("bracket"):
        doc = new_document("bracket", "A 40 x 24 x 10 mm PartDesign bracket (a Body) filled "
                           "by the FRep Infill: a 1.5 mm skin round a gyroid of 5 mm cells. "
                           "Try: frepcad export examples/bracket.FCStd -o bracket.3mf")
        FRepExamples.build_bracket_infill(doc)
        doc.recompute()
        save(doc, "bracket")

    if wanted("attachment"):
        doc = new_document("attachment", "Seed 003's attachment: a limb (an hspline cylinder) "
                           "joined to an hspline torus through a Catmull-Clark seam around a "
                           "2 x 2 rectangle of its CVs, closed at its tip: one closed surface. "
                           "Edit the Limb's CVs and the joint follows; double-click the "
                           "attachment for its panel. Try: frepcad export "
                           "examples/attachment.FCStd -o limb.stl")
        FRepExamples.build_attachment(doc)
        doc.recompute()
        save(doc, "attachment")

    if wanted("envelope"):
        doc = new_document("envelope", "Seed 003's enveloping: an hspline ring bound to two "
                           "bones across it; the second bone is turned 60 degrees about the "
                           "joint and folds the ring, which keeps 98 % of its volume (level 0 "
                           "refined at the joint, level 1 blending the bones' frames). Turn "
                           "the Bone001 line (Placement) to fold it further.")
        FRepExamples.build_envelope(doc)
        doc.recompute()
        save(doc, "envelope")

    if wanted("hspline"):
        doc = new_document("hspline", "Seed 003's hspline tutorial (docs/hsplines.md) after "
                           "step 4: a plane refined to level 3, a CV lifted at level 1 and "
                           "two pushed in at level 3, which followed when level 1 moved "
                           "again. Double-click the Tutorial to edit it; try Zero offsets on "
                           "level 3, then Unrefine.")
        FRepExamples.hspline_tutorial(doc, step=4)
        save(doc, "hspline")

    if wanted("csg"):
        doc = new_document("csg", "Reference model csg (examples/csg.json): cube [-1,1]^3 "
                           "intersected with a sphere of radius 1.3, minus three infinite "
                           "cylinders of radius 0.5 along x, y and z.")
        FRepExamples.build_csg(doc)
        doc.recompute()
        save(doc, "csg")

    if wanted("csg_spreadsheet"):
        doc = new_document("csg_spreadsheet", "The csg part driven by the spreadsheet "
                           "'Parameters' (aliases Size, Ball, Hole). Try: frepcad export "
                           "examples/csg_spreadsheet.FCStd --set Parameters.Hole=0.3 -o "
                           "part.stl")
        mesh = FRepExamples.build_csg_spreadsheet(doc)
        mesh.Cells = POLYGONIZE_CELLS
        doc.recompute()
        save(doc, "csg_spreadsheet")

    import FRepImport
    for name in ("twist", "helix", "gyroid"):
        if not wanted(name):
            continue
        doc = new_document(name, "")
        FRepImport.import_model(os.path.join(HERE, name + ".json"), doc)
        doc.recompute()
        save(doc, name)

    # Seed 000's showcase shapes side by side, one feature tree each (examples/showcase).
    if not wanted("showcase"):
        return
    doc = new_document("showcase", "Seed 000's showcase shapes (figures 4.9 to 4.17), from "
                       "examples/showcase/*.json; each exports as a printable STL.",
                       preview_cells=32)  # twelve previews: coarser, to keep the file small
    folder = os.path.join(HERE, "showcase")
    names = sorted(n[:-5] for n in os.listdir(folder) if n.endswith(".json"))
    for i, name in enumerate(names):
        top = FRepImport.import_model(os.path.join(folder, name + ".json"), doc)
        top.Placement.Base = FreeCAD.Vector(3.0 * (i % 4), -3.0 * (i // 4), 0)
    doc.recompute()
    import FreeCADGui
    view = FreeCADGui.getDocument(doc.Name).ActiveView
    view.viewIsometric()
    view.fitAll()
    FreeCADGui.updateGui()
    view.saveImage(os.path.join(ROOT, "docs", "images", "showcase.png"), 1000, 620, "White")
    save(doc, "showcase")


if os.environ.get("FREP_MAKE_DOCUMENTS") == "1" and "FreeCADGui" in sys.modules:
    rc = 1
    try:
        build()
        rc = 0
    except Exception as e:
        import traceback
        traceback.print_exc()
        print("error: %s" % e)
    sys.stdout.flush()
    os._exit(rc)
elif __name__ == "__main__":
    sys.exit(launch())
