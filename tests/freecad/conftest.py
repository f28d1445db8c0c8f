"""Runs the workbench tests inside FreeCAD, headless: FreeCAD imported as a module into
the Python FreeCAD runs, with a private FreeCAD home whose Mod folder links Mod/FRep
(FREECAD_USER_HOME is set by CTest; see tests/CMakeLists.txt)."""

import os
import sys

# FreeCAD's module folder as the configure step found it (FreeCAD 0.20 on bookworm:
# /usr/lib/freecad-python3/lib; 1.0 on trixie: /usr/lib/freecad/lib)
sys.path += [d for d in (os.environ.get("FREECAD_LIB_DIR"), "/usr/lib/freecad-python3/lib",
                         "/usr/lib/freecad/lib") if d]
# Python workbenches (Draft), the PySide shim they import and Part's Python modules (FreeCAD
# 1.0's Draft arrays import PartEnums), as FreeCAD's own start-up adds them
sys.path += ["/usr/share/freecad/Mod/Draft", "/usr/share/freecad/Ext",
             "/usr/share/freecad/Mod/Part"]
# FreeCAD 1.0's Draft arrays import the BIM workbench's resources (Arch_rc)
sys.path += [d for d in ["/usr/share/freecad/Mod/BIM"] if os.path.isdir(d)]
# Compiled workbenches with a Python package of their own (PartDesign), last so that they
# never shadow a module found above.
sys.path.append("/usr/lib/freecad/Mod")

import FreeCAD  # noqa: E402  (after the path set-up)
import pytest  # noqa: E402

assert FreeCAD.getUserAppDataDir().rstrip("/") == os.environ["FREECAD_USER_HOME"].rstrip("/"), \
    "tests must run with the private FreeCAD home"

import FRepFeatures  # noqa: E402,F401  (found through the Mod folder)


@pytest.fixture
def doc():
    d = FreeCAD.newDocument("FRepTest")
    name = d.Name
    yield d
    if name in FreeCAD.listDocuments():
        FreeCAD.closeDocument(name)


def ball_mesh(tmp_path, cells):
    """A FreeCAD mesh of the unit ball, meshed by frepcore at `cells` and read back."""
    import Mesh
    from FRepPaths import frepcore
    path = str(tmp_path / ("ball-%d.stl" % cells))
    frepcore.sphere(1.0).mesh(cells=cells).write(path)
    return Mesh.Mesh(path)
