#!/usr/bin/env bash
# Runs workbench tests headless inside FreeCAD (imported into FreeCAD's Python 3.11) with a
# private FreeCAD home under the build folder. Usage: run_pytest.sh BUILD_DIR SOURCE_DIR ARGS...
set -euo pipefail
build="$1"; source="$2"; shift 2
home="$build/freecad-home"
bash "$source/scripts/install-workbench.sh" "$home" >/dev/null
export FREECAD_USER_HOME="$home" FREP_SOURCE_DIR="$source" FREPCORE_PATH="$build/python"
export FREPCAD_BIN="$build/bin/frepcad"
export PYTHONDONTWRITEBYTECODE=1
cd "$source/tests/freecad"
exec /usr/bin/python3.11 -m pytest -q -p no:cacheprovider "$@"
