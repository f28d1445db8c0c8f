"""The workbench's package.xml as FreeCAD's own metadata reader (and so the Addon Manager)
sees it, in the FreeCAD the tests run in: it parses, names the workbench class InitGui.py
registers, allows this FreeCAD version, points at icons that exist and carries the project's
one version number, which the build gives frepcore and frepcad too."""

import os
import re

import FreeCAD

from FRepPaths import frepcore

MOD = os.path.join(os.environ["FREP_SOURCE_DIR"], "Mod", "FRep")


def version_tuple(text):
    return tuple(int(p) for p in re.findall(r"\d+", text)[:3])


def test_package_xml_is_read_by_freecad():
    meta = FreeCAD.Metadata(os.path.join(MOD, "package.xml"))
    assert meta.Name == "FRep"
    assert meta.Version == frepcore.__version__
    assert os.path.isfile(os.path.join(MOD, meta.Icon))
    running = version_tuple(".".join(FreeCAD.Version()[:3]))
    assert version_tuple(meta.FreeCADMin) <= running
    workbenches = meta.Content["workbench"]
    assert len(workbenches) == 1
    wb = workbenches[0]
    init_gui = open(os.path.join(MOD, "InitGui.py")).read()
    assert re.search(r"^class %s\(" % wb.Classname, init_gui, re.M), wb.Classname
    assert os.path.isfile(os.path.join(MOD, wb.Subdirectory, wb.Icon))
    assert version_tuple(wb.FreeCADMin) <= running
