"""Where the workbench's parts live, and how it finds the frepcore module.

Two layouts: in the repository the workbench folder is symlinked into FreeCAD's user Mod
folder by the set-up and frepcore is built into <repository>/build/python; installed
(`make install`, `cmake --install`) frepcore sits inside the workbench folder itself, so no
source tree is needed. FREPCORE_PATH overrides both.
"""

import os
import sys

WORKBENCH_DIR = os.path.dirname(os.path.realpath(__file__))
ICON_DIR = os.path.join(WORKBENCH_DIR, "resources", "icons")
REPOSITORY_DIR = os.path.dirname(os.path.dirname(WORKBENCH_DIR))


def icon(name, category=None):
    """Path of an SVG icon of the workbench by base name ("sphere" -> .../sphere.svg); a
    node type without its own icon gets its registry category's, then the workbench's."""
    for base in (name, "category-%s" % category if category else None, "frep"):
        if base:
            path = os.path.join(ICON_DIR, base + ".svg")
            if os.path.exists(path):
                return path
    return os.path.join(ICON_DIR, "frep.svg")


def frepcore_dirs():
    dirs = []
    if os.environ.get("FREPCORE_PATH"):
        dirs.append(os.environ["FREPCORE_PATH"])
    dirs.append(WORKBENCH_DIR)  # installed: Mod/FRep/frepcore
    dirs.append(os.path.join(REPOSITORY_DIR, "build", "python"))
    return dirs


def import_frepcore():
    """Imports frepcore, adding its build folder to sys.path when needed."""
    try:
        import frepcore  # noqa: F401  (already importable)
    except ImportError:
        for d in frepcore_dirs():
            if os.path.isdir(os.path.join(d, "frepcore")) and d not in sys.path:
                sys.path.insert(0, d)
        try:
            import frepcore  # noqa: F401
        except ImportError as e:
            raise ImportError(
                "FRep workbench: the frepcore module was not found in %s; build it with "
                "`make` in %s (or set FREPCORE_PATH)" % (", ".join(frepcore_dirs()),
                                                         REPOSITORY_DIR)) from e
    return sys.modules["frepcore"]


frepcore = import_frepcore()
