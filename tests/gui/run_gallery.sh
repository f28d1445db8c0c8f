#!/usr/bin/env bash
# Takes the node gallery (docs/gallery.md, docs/images/nodes/*.png) in the real FreeCAD GUI
# under Xvfb. Usage: run_gallery.sh BUILD_DIR SOURCE_DIR [DOCS_DIR] (default SOURCE_DIR/docs).
set -euo pipefail
build="$(realpath "$1")"; source="$(realpath "$2")"; docs="$(realpath -m "${3:-$source/docs}")"
mkdir -p "$docs"
log="$build/gallery.log"
if ! FREP_SOURCE_DIR="$source" FREP_GALLERY_OUT="$docs" bash "$source/scripts/run-freecad-gui.sh" \
    "$build" "$source/tests/gui/gallery.FCMacro" "$log"; then
  echo "gallery failed; FreeCAD's output:"; tail -30 "$log"; exit 1
fi
echo "node gallery written to $docs/gallery.md ($(ls "$docs/images/nodes" | wc -l) pictures)"
