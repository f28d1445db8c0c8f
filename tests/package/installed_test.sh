#!/usr/bin/env bash
# Inside a root where the frepcad package was installed: the workbench from FreeCAD's system
# Mod folder builds and exports the csg example (check_installed.py), the installed frepcad
# exports the saved document and the mesh is printable. Ends with the test's summary line.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
out="$(mktemp -d)"
cd /
test -x /usr/bin/frepcad
workbench=$(dpkg -L frepcad | grep '/Mod/FRep/InitGui.py$' | head -1)
test -n "$workbench" || { echo "FAIL: the package has no workbench"; exit 1; }
echo "workbench installed at $(dirname "$workbench")"
# A user's own FreeCAD home, empty: only the system Mod folder holds the workbench.
export HOME="$out/home"; mkdir -p "$HOME"
INSTALL_ROOT=/usr OUT_DIR="$out" freecadcmd "$here/check_installed.py" >"$out/freecad.log" 2>&1 || true
grep -E "^(FreeCAD [0-9]|FAIL|installed workbench)" "$out/freecad.log" || true
grep -q "installed workbench: ok" "$out/freecad.log" \
  || { echo "FAIL: FreeCAD's run:"; tail -30 "$out/freecad.log"; exit 1; }
frepcad export "$out/csg.FCStd" -o "$out/from-document.stl" --cells 48 --quiet
frepcad check "$out/from-document.stl" | tee "$out/check.txt"
grep -q "verdict: printable" "$out/check.txt"
python3 -c "import frepcore; print('frepcore for the system python3:', frepcore.__file__)"
echo "1 passed, 0 failed"
