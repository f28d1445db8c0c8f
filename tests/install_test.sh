#!/usr/bin/env bash
# The installed layout works without the source tree: cmake --install into a temporary prefix,
# then FreeCAD (headless, its user home pointing at the prefix's Mod folder) loads the
# workbench and frepcore from there, builds and exports a solid, and the installed frepcad
# exports a model and a FreeCAD document. Usage: install_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build="$(cd "$1" && pwd)"; src="$(cd "$2" && pwd)"
prefix="$(mktemp -d)"
trap 'rm -rf "$prefix"' EXIT
cmake --install "$build" --prefix "$prefix" >/dev/null
mods="$prefix/share/FreeCAD/Mod"
test -f "$mods/FRep/InitGui.py" && ls "$mods/FRep/frepcore/"_frepcore*.so >/dev/null
test -x "$prefix/bin/frepcad"

cat >"$prefix/check.py" <<'PY'
import os, sys
import FreeCAD
prefix = os.environ["PREFIX"]
import FRepPaths
import FRepFeatures
import frepcore
ok = True
for name, mod in (("FRepPaths", FRepPaths), ("frepcore", frepcore)):
    where = os.path.realpath(mod.__file__)
    if not where.startswith(os.path.realpath(prefix)):
        print("FAIL: %s loaded from %s, not from the install" % (name, where))
        ok = False
doc = FreeCAD.newDocument("installed")
ball = FRepFeatures.make("sphere", doc, radius=2.0)
doc.recompute()
import FRepTree
solid = FRepTree.shape_of(ball)
r = solid.export(os.path.join(prefix, "ball.stl"), cells=24)
if not (r["printable"] and os.path.exists(os.path.join(prefix, "ball.stl"))):
    print("FAIL: export from the installed workbench")
    ok = False
print("installed workbench: %s" % ("ok" if ok else "FAILED"))
os._exit(0 if ok else 1)
PY
# No source tree on any path: run from /, without FREPCORE_PATH, with a home that has only the
# installed Mod folder.
(cd / && env -u FREPCORE_PATH -u FREPCAD_WORKBENCH_DIR PREFIX="$prefix" \
   FREECAD_USER_HOME="$prefix/share/FreeCAD" freecadcmd "$prefix/check.py" 2>&1) | tee "$prefix/log" \
   | grep -E "installed workbench|FAIL"
grep -q "installed workbench: ok" "$prefix/log"

(cd / && env -u FREPCORE_PATH -u FREPCAD_WORKBENCH_DIR "$prefix/bin/frepcad" export \
   "$src/examples/sphere.json" -o "$prefix/s.stl" --cells 16 --quiet)
(cd / && env -u FREPCORE_PATH -u FREPCAD_WORKBENCH_DIR "$prefix/bin/frepcad" export \
   "$src/examples/csg.FCStd" -o "$prefix/csg.stl" --cells 24 --quiet)
test -s "$prefix/s.stl" && test -s "$prefix/csg.stl"
echo "1 passed, 0 failed"
