"""frepcore from the build folder (FREPCORE_PATH, set by tests/freecad/run_pytest.sh)."""

import os
import sys

sys.path.insert(0, os.environ["FREPCORE_PATH"])
