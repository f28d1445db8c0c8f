#!/usr/bin/env bash
# Runs the GUI smoke test in the real FreeCAD GUI under Xvfb, with a private FreeCAD home.
# Usage: run_gui.sh BUILD_DIR SOURCE_DIR [OUT_DIR]   (screenshots and result.txt go to OUT_DIR,
# default BUILD_DIR/gui; `make screenshots` copies the screenshots into docs/images).
set -euo pipefail
build="$(realpath "$1")"; source="$(realpath "$2")"; out="$(realpath -m "${3:-$build/gui}")"
home="$build/freecad-gui-home"
rm -rf "$out"; mkdir -p "$out" "$home"
bash "$source/scripts/install-workbench.sh" "$home" >/dev/null
export FREECAD_USER_HOME="$home" FREP_SOURCE_DIR="$source" FREPCORE_PATH="$build/python"
export FREP_GUI_OUT="$out" QTWEBENGINE_DISABLE_SANDBOX=1 PYTHONDONTWRITEBYTECODE=1
export LIBGL_ALWAYS_SOFTWARE=1
rc=0
timeout 300 xvfb-run -a -s "-screen 0 1280x1024x24" \
  freecad "$source/tests/gui/gui_smoke.FCMacro" >"$out/freecad.log" 2>&1 || rc=$?
cat "$out/result.txt" 2>/dev/null || echo "no result.txt: FreeCAD did not run the macro"
if [ "$rc" -ne 0 ]; then
  echo "FreeCAD exited with $rc; its output:"; tail -40 "$out/freecad.log"
fi
exit "$rc"
