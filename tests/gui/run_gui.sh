#!/usr/bin/env bash
# Runs the GUI smoke test in the real FreeCAD GUI under Xvfb, with a private FreeCAD home.
# Usage: run_gui.sh BUILD_DIR SOURCE_DIR [OUT_DIR]   (screenshots and result.txt go to OUT_DIR,
# default BUILD_DIR/gui; `make screenshots` copies the screenshots into docs/images).
set -euo pipefail
build="$(realpath "$1")"; source="$(realpath "$2")"; out="$(realpath -m "${3:-$build/gui}")"
rm -rf "$out"; mkdir -p "$out"
rc=0
FREP_SOURCE_DIR="$source" FREP_GUI_OUT="$out" bash "$source/scripts/run-freecad-gui.sh" \
  "$build" "$source/tests/gui/gui_smoke.FCMacro" "$out/freecad.log" 300 || rc=$?
cat "$out/result.txt" 2>/dev/null || echo "no result.txt: FreeCAD did not run the macro"
if [ "$rc" -ne 0 ]; then
  echo "FreeCAD exited with $rc; its output:"; tail -40 "$out/freecad.log"
fi
exit "$rc"
