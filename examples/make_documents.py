#!/usr/bin/python3.11
"""Writes the example FreeCAD documents with the workbench's own features:

    examples/csg.FCStd              the csg reference model (examples/csg.json) as features
    examples/csg_spreadsheet.FCStd  the same part driven by a spreadsheet, with a Polygonize

Run with `make examples` (after `make`). The documents hold their preview meshes at a modest
preview resolution so that they stay small in the repository; a recompute in FreeCAD or
`frepcad export` rebuilds everything from the exact tree.
"""

import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
BUILD = os.environ.get("BUILD_DIR", os.path.join(ROOT, "build"))
HOME = os.path.join(BUILD, "freecad-home")

# Saved previews and the saved Polygonize mesh: coarse, to keep the files small.
PREVIEW_CELLS = 48
POLYGONIZE_CELLS = 48


def setup_freecad():
    """FreeCAD with a private home whose Mod folder links the workbench (set before import)."""
    subprocess.run(["bash", os.path.join(ROOT, "scripts", "install-workbench.sh"), HOME],
                   check=True, stdout=subprocess.DEVNULL)
    os.environ["FREECAD_USER_HOME"] = HOME
    os.environ.setdefault("FREPCORE_PATH", os.path.join(BUILD, "python"))
    sys.path.append("/usr/lib/freecad-python3/lib")
    import FreeCAD
    return FreeCAD


def save(FreeCAD, doc, name):
    """Saves atomically: a temporary file in examples/, then a rename."""
    broken = [o.Label for o in doc.Objects if "Invalid" in o.State]
    if broken:
        raise RuntimeError("%s: recompute failed for %s" % (name, ", ".join(broken)))
    path = os.path.join(HERE, name + ".FCStd")
    tmp = os.path.join(HERE, ".%s.tmp.FCStd" % name)
    doc.saveAs(tmp)
    FreeCAD.closeDocument(doc.Name)
    os.replace(tmp, path)
    print("wrote %s (%d kB)" % (os.path.relpath(path, ROOT), os.path.getsize(path) // 1024))


def new_document(FreeCAD, name, comment):
    import FRepMeshing
    doc = FreeCAD.newDocument(name)
    doc.Comment = comment
    doc.Meta = dict(doc.Meta, **{FRepMeshing.PREVIEW_KEY: str(PREVIEW_CELLS)})
    return doc


def main():
    FreeCAD = setup_freecad()
    import FRepExamples

    doc = new_document(FreeCAD, "csg", "Reference model csg (examples/csg.json): cube [-1,1]^3 "
                       "intersected with a sphere of radius 1.3, minus three infinite "
                       "cylinders of radius 0.5 along x, y and z.")
    FRepExamples.build_csg(doc)
    doc.recompute()
    save(FreeCAD, doc, "csg")

    doc = new_document(FreeCAD, "csg_spreadsheet", "The csg part driven by the spreadsheet "
                       "'Parameters' (aliases Size, Ball, Hole). Try: frepcad export "
                       "examples/csg_spreadsheet.FCStd --set Parameters.Hole=0.3 -o part.stl")
    mesh = FRepExamples.build_csg_spreadsheet(doc)
    mesh.Cells = POLYGONIZE_CELLS
    doc.recompute()
    save(FreeCAD, doc, "csg_spreadsheet")
    return 0


if __name__ == "__main__":
    sys.exit(main())
