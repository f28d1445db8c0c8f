# FRep workbench, application part (runs in freecadcmd too). Exec'd by FreeCAD without
# __file__: everything that needs paths lives in FRepPaths.
import FreeCAD

FreeCAD.addExportType("FRep mesh (*.stl *.obj *.ply)", "FRepExport")
FreeCAD.addExportType("FRep level set (*.vdb)", "FRepExport")
FreeCAD.addExportType("FRep 3MF (*.3mf)", "FRepExport")
FreeCAD.addImportType("FRep model (*.json)", "FRepImport")
FreeCAD.addImportType("HyperFun model (*.hf)", "FRepImport")
FreeCAD.addImportType("OpenVDB volume (*.vdb)", "FRepImport")
