#!/usr/bin/env bash
# Runs workbench tests headless inside FreeCAD (imported into the Python FreeCAD runs) with a
# private FreeCAD home under the build folder. Usage: run_pytest.sh BUILD_DIR SOURCE_DIR ARGS...
set -euo pipefail
build="$1"; source="$2"; shift 2
home="$build/freecad-home"
bash "$source/scripts/install-workbench.sh" "$home" >/dev/null
export FREECAD_USER_HOME="$home" FREP_SOURCE_DIR="$source" FREPCORE_PATH="$build/python"
export FREPCAD_BIN="$build/bin/frepcad"
export PYTHONDONTWRITEBYTECODE=1
# FREP_PYTHON and FREECAD_LIB_DIR, as the configure step found them
set -a; . "$build/frep-env.sh"; set +a
cd "$source/tests/freecad"
exec "$FREP_PYTHON" -m pytest -q -p no:cacheprovider "$@"
