"""Run by freecadcmd against an installed FRepCAD (no source tree, no build folder on any
path): the workbench and frepcore load from under INSTALL_ROOT, the csg example is built
with the workbench's features, exported with its checked export and the document saved.
Exits 0 when all holds; prints "FAIL: ..." lines otherwise.

Environment: INSTALL_ROOT (where the workbench and frepcore must come from), OUT_DIR (where
to write csg.stl and csg.FCStd)."""

import os
import sys

import FreeCAD

root = os.path.realpath(os.environ["INSTALL_ROOT"])
out = os.environ["OUT_DIR"]
failures = []
try:
    import FRepFeatures
    import FRepExamples
    import FRepExport
    import frepcore
    for module in (FRepFeatures, frepcore):
        where = os.path.realpath(module.__file__)
        if not where.startswith(root + os.sep):
            failures.append("%s loaded from %s, not from the install in %s"
                            % (module.__name__, where, root))
    # .vdb files are read first by the installed frepcad (a damaged one cannot crash FreeCAD)
    reader = frepcore.vdb_reader()
    if not reader or os.path.realpath(reader) != os.path.join(root, "bin", "frepcad"):
        failures.append("frepcore reads .vdb files with %r, not the installed frepcad"
                        % (reader,))
    doc = FreeCAD.newDocument("installed")
    part = FRepExamples.build_csg(doc)
    doc.recompute()
    stl = os.path.join(out, "csg.stl")
    report = FRepExport.export_objects([part], stl, cells=48)
    if not (report.get("printable") and os.path.getsize(stl) > 0):
        failures.append("the checked export of the csg example: %r" % (report,))
    doc.saveAs(os.path.join(out, "csg.FCStd"))
    print("FreeCAD %s, Python %d.%d, frepcore from %s"
          % (".".join(FreeCAD.Version()[:3]), sys.version_info[0], sys.version_info[1],
             os.path.dirname(frepcore.__file__)))
except Exception as e:  # reported as a failure line, not a traceback, and exit 1
    import traceback
    traceback.print_exc()
    failures.append("%s: %s" % (type(e).__name__, e))
for f in failures:
    print("FAIL: " + f)
print("installed workbench: %s" % ("ok" if not failures else "FAILED"))
sys.stdout.flush()
os._exit(0 if not failures else 1)
