#!/usr/bin/env bash
# Takes the node gallery (docs/gallery.md, docs/images/nodes/*.png) in the real FreeCAD GUI
# under Xvfb. Usage: run_gallery.sh BUILD_DIR SOURCE_DIR [DOCS_DIR] (default SOURCE_DIR/docs).
set -euo pipefail
build="$(realpath "$1")"; source="$(realpath "$2")"; docs="$(realpath -m "${3:-$source/docs}")"
home="$build/freecad-gui-home"
mkdir -p "$home" "$docs"
bash "$source/scripts/install-workbench.sh" "$home" >/dev/null
export FREECAD_USER_HOME="$home" FREPCORE_PATH="$build/python" FREP_GALLERY_OUT="$docs"
export QTWEBENGINE_DISABLE_SANDBOX=1 PYTHONDONTWRITEBYTECODE=1
log="$build/gallery.log"
if ! timeout 600 xvfb-run -a -s "-screen 0 1280x1024x24" \
    freecad "$source/tests/gui/gallery.FCMacro" >"$log" 2>&1; then
  echo "gallery failed; FreeCAD's output:"; tail -30 "$log"; exit 1
fi
echo "node gallery written to $docs/gallery.md ($(ls "$docs/images/nodes" | wc -l) pictures)"
