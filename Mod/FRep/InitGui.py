# FRep workbench, GUI part. FreeCAD execs this file without __file__ and with separate global
# and local namespaces, so module-level names are not visible inside the class: everything
# the class needs is computed or imported in its own body.
import FreeCADGui


class FRepWorkbench(FreeCADGui.Workbench):
    MenuText = "FRep"
    ToolTip = ("Function-representation solids: exact primitives, set operations, blends and "
               "transforms, meshed watertight for 3D printing")
    # The icon path comes from FRepPaths' location without importing it: the import loads
    # frepcore, and a missing build should be explained when the workbench is activated,
    # not hide the workbench from the list.
    import importlib.util as _util
    import os as _os
    _spec = _util.find_spec("FRepPaths")
    Icon = _os.path.join(_os.path.dirname(_os.path.realpath(_spec.origin)) if _spec else "",
                         "resources", "icons", "frep.svg")

    def Initialize(self):
        import FRepBlendGuideView
        import FRepCommands
        FRepBlendGuideView.install()  # a selected blend shows where it acts
        bars, menus = FRepCommands.register()
        for title, names in bars:
            self.appendToolbar(title, names)
        for title, names in menus:
            if title == "Mesh":  # meshing and printing: at the menu's top level
                self.appendMenu(FRepCommands.MENU, names)
            else:
                self.appendMenu([FRepCommands.MENU, title], names)

    def Activated(self):
        # (once FreeCAD has laid its toolbars out: after the activation's events)
        from PySide import QtCore
        import FRepCommands
        QtCore.QTimer.singleShot(0, FRepCommands.place_toolbars)

    def GetClassName(self):
        return "Gui::PythonWorkbench"


FreeCADGui.addWorkbench(FRepWorkbench())
