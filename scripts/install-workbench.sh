#!/usr/bin/env bash
# Links Mod/FRep into a FreeCAD user Mod folder (FreeCAD only loads FeaturePython classes from
# modules in its Mod folders). Usage: install-workbench.sh [FREECAD_USER_HOME]
#   no argument: the user's own folder ($FREECAD_USER_HOME/Mod or ~/.local/share/FreeCAD/Mod)
#   an argument: a private FreeCAD home for tests and the CLI (created with its Mod folder)
set -euo pipefail
repo="$(cd "$(dirname "$0")/.." && pwd)"
if [ $# -ge 1 ]; then
  mods="$1/Mod"
elif [ -n "${FREECAD_USER_HOME:-}" ]; then
  mods="$FREECAD_USER_HOME/Mod"
else
  mods="${XDG_DATA_HOME:-$HOME/.local/share}/FreeCAD/Mod"
fi
mkdir -p "$mods"
ln -sfn "$repo/Mod/FRep" "$mods/FRep"
echo "FRep workbench linked: $mods/FRep -> $repo/Mod/FRep"
