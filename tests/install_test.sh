#!/usr/bin/env bash
# The installed layout works without the source tree: cmake --install into a temporary prefix,
# then FreeCAD (headless, its user home pointing at the prefix's Mod folder) loads the
# workbench and frepcore from there, builds and exports the csg example
# (tests/package/check_installed.py), and the installed frepcad exports a model, the saved
# document and an example document. Usage: install_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build="$(cd "$1" && pwd)"; src="$(cd "$2" && pwd)"
prefix="$(mktemp -d)"
trap 'rm -rf "$prefix"' EXIT
cmake --install "$build" --prefix "$prefix" >/dev/null
mods="$prefix/share/FreeCAD/Mod"
test -f "$mods/FRep/InitGui.py" && ls "$mods/FRep/frepcore/"_frepcore*.so >/dev/null
test -x "$prefix/bin/frepcad"

# No source tree on any path: run from /, without FREPCORE_PATH, with a home that has only the
# installed Mod folder.
(cd / && env -u FREPCORE_PATH -u FREPCAD_WORKBENCH_DIR INSTALL_ROOT="$prefix" OUT_DIR="$prefix" \
   FREECAD_USER_HOME="$prefix/share/FreeCAD" freecadcmd "$src/tests/package/check_installed.py" 2>&1) \
   | tee "$prefix/log" | grep -E "installed workbench|FAIL"
grep -q "installed workbench: ok" "$prefix/log"

(cd / && env -u FREPCORE_PATH -u FREPCAD_WORKBENCH_DIR "$prefix/bin/frepcad" export \
   "$src/examples/sphere.json" -o "$prefix/s.stl" --cells 16 --quiet)
(cd / && env -u FREPCORE_PATH -u FREPCAD_WORKBENCH_DIR "$prefix/bin/frepcad" export \
   "$src/examples/csg.FCStd" -o "$prefix/example.stl" --cells 24 --quiet)
(cd / && env -u FREPCORE_PATH -u FREPCAD_WORKBENCH_DIR "$prefix/bin/frepcad" export \
   "$prefix/csg.FCStd" -o "$prefix/saved.stl" --cells 24 --quiet)
test -s "$prefix/s.stl" && test -s "$prefix/example.stl" && test -s "$prefix/saved.stl"
echo "1 passed, 0 failed"
