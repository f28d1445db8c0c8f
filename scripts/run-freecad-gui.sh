#!/usr/bin/env bash
# Runs a macro in the real FreeCAD GUI under Xvfb (software OpenGL) with a private FreeCAD
# home under the build folder whose Mod folder links the workbench. FreeCAD's output goes to
# LOG; the exit status is the macro's (macros end with os._exit). Extra environment for the
# macro is passed through. Used by the GUI test, the node gallery, the GUI benchmark and
# `make examples`.
# Usage: run-freecad-gui.sh BUILD_DIR MACRO LOG [TIMEOUT_SECONDS]
set -euo pipefail
build="$(realpath "$1")"; macro="$(realpath "$2")"; log="$3"; limit="${4:-600}"
here="$(dirname "$(realpath "$0")")"
home="$build/freecad-gui-home"
mkdir -p "$home"
bash "$here/install-workbench.sh" "$home" >/dev/null
export FREECAD_USER_HOME="$home" FREPCORE_PATH="${FREPCORE_PATH:-$build/python}"
export FREP_SOURCE_DIR="${FREP_SOURCE_DIR:-$(dirname "$here")}"
export QTWEBENGINE_DISABLE_SANDBOX=1 PYTHONDONTWRITEBYTECODE=1 LIBGL_ALWAYS_SOFTWARE=1
exec timeout "$limit" xvfb-run -a -s "-screen 0 1280x1024x24" freecad "$macro" >"$log" 2>&1
