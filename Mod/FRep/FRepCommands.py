"""The workbench's GUI commands: one per registry node type, Polygonize, Export and the
preview quality. Registered by InitGui; every command works on the active document inside
one undo transaction.

Operations take their inputs from the selection in the order it was made (the first
selected is the base of a difference) and hide them, as Part's booleans do. A selection that
does not fit gets a message naming the command and what it needs, never an exception.
"""

import FreeCAD
import FreeCADGui

import FRepFeatures
import FRepHSplineCommands
import FRepMeshing
import FRepPaths
import FRepPolygonize
import FRepProperties as props
import FRepTree
from FRepGuiHelpers import (QT_TRANSLATE_NOOP, Transaction, add_to_active_container, report,
                            report_if_failed, translate)

MENU = "FRep"
# The toolbars as a user sees them at FreeCAD's default width: the commonest commands as
# buttons, the rest of a family behind a drop-down (a group command, as Part's primitives).
# An entry is a node type, another command's name (FRep_...), or a group: (its command name,
# its title, its tooltip, its members). A node type placed nowhere goes to "FRep more".
LAYOUT = (
    ("FRep primitives", (
        "sphere", "box", "cylinder", "cone", "torus",
        ("FRep_MorePrimitives", "More primitives", "Ellipsoid, superellipsoid, half-space",
         ("ellipsoid", "superellipsoid", "halfspace")),
        ("FRep_SoftSolids", "Blobs and convolution",
         "Solids around points and skeletons: blobby, soft objects, metaballs, convolution, "
         "sweep", ("blobby", "soft_objects", "metaballs", "convolution", "convolution_segments",
                   "sweep")),
        ("FRep_FieldSources", "Formula and files",
         "A solid written as a formula, or read from a mesh or an OpenVDB grid",
         ("formula", "mesh_sdf", "vdb_grid")))),
    ("FRep operations", (
        "union", "intersection", "difference",
        ("FRep_Blends", "Blends", "Set operations with a smooth fillet",
         ("blend_union", "blend_intersection", "bounded_blend")),
        ("FRep_FieldOperations", "Offset and shell", "Grow, hollow, invert or morph a solid",
         ("offset", "shell", "complement", "metamorphosis")))),
    ("FRep transforms", (
        ("FRep_Placements", "Move", "Translate, rotate, scale or transform a solid",
         ("translate", "rotate", "scale", "transform")),
        ("FRep_Deformations", "Deform", "Twist, bend, taper, stretch or push a solid",
         ("twist", "bend", "taper", "stretch", "deform_point")),
        ("FRep_Arrays", "Arrays", "Copies of a solid in a row, round an axis or at points",
         ("linear_array", "polar_array", "instancer")))),
    ("FRep microstructures", (
        ("FRep_Surfaces", "Lattice surfaces",
         "Triply periodic surfaces as sheets or networks: gyroid, Schwarz P and D, diamond, "
         "Neovius, lidinoid", ("gyroid", "schwarz_p", "schwarz_d", "diamond", "neovius",
                               "lidinoid")),
        ("FRep_Struts", "Strut lattices", "Beams between the nodes of a unit cell, or a random "
         "Voronoi foam", ("strut_lattice", "voronoi_foam")),
        "infill")),
    ("FRep lattice", ("FRep_Lattice", "FRep_Deform", "ffd")),
    ("FRep hspline", (
        ("FRep_HSplineNew", "New hspline", "A new hspline: a plane, a cylinder, a torus or "
         "from a selected face", ("FRep_HSplinePlane", "FRep_HSplineCylinder",
                                  "FRep_HSplineTorus", "FRep_HSplineFromFace")),
        "FRep_HSplineRefine", "FRep_HSplineZeroOffsets", "FRep_HSplineUnrefine",
        "FRep_HSplineToSolid",
        ("FRep_HSplineCompose", "Attach, envelope, struts", "Join a cylinder to an hspline "
         "through a seam; bind an hspline to skeleton segments that bend it; fill a shell along "
         "it with struts", ("FRep_HSplineAttach", "FRep_HSplineEnvelope", "FRep_HSplineStruts")),
        ("FRep_HSplineFiles", "Hspline files", "Import or export .hs, STEP or a checked STL",
         ("FRep_HSplineImport", "FRep_HSplineExport")))),
    ("FRep mesh", (
        "FRep_Polygonize", ("FRep_Geometry", "Section and points", "FreeCAD geometry from a "
                            "solid: a plane section as wires, surface points as a Points "
                            "object", ("FRep_Section", "FRep_PointSample")),
        "FRep_Export", "FRep_Repair", "FRep_Printability",
        ("FRep_Settings", "Meshing settings", "The preview's quality and the tolerance solids "
         "are tessellated at", ("FRep_PreviewQuality", "FRep_SolidTolerance")))),
)


def command_name(entry):
    """A layout entry's command: a node type's (sphere -> FRep_Sphere) or the name given."""
    if entry.startswith("FRep_"):
        return entry
    return "FRep_" + props.type_class_name(entry)


def toolbars():
    """[(toolbar title, [command names])], groups as their own command names, and the groups
    as {group command name: (title, tooltip, [member command names])}."""
    bars, groups, placed = [], {}, set()
    for title, entries in LAYOUT:
        names = []
        for entry in entries:
            if isinstance(entry, tuple):
                name, text, tip, members = entry
                groups[name] = (text, tip, [command_name(m) for m in members])
                placed.update(members)
                names.append(name)
            else:
                placed.add(entry)
                names.append(command_name(entry))
        bars.append((title, names))
    rest = [command_name(t) for t in FRepFeatures.NODE_TYPES if t not in placed]
    if rest:
        bars.insert(len(bars) - 3, ("FRep more", rest))
    return bars, groups


def menus():
    """[(submenu title, [command names])]: the toolbars with their groups spelled out."""
    bars, groups = toolbars()
    return [(title.replace("FRep ", "").capitalize(),
             [m for n in names for m in (groups[n][2] if n in groups else [n])])
            for title, names in bars]


def place_toolbars():
    """Puts the workbench's toolbars on a row of their own (or as many rows as they need)
    where they would share one with FreeCAD's own: Qt squeezes a crowded row, and most
    buttons went behind ». Toolbars the user has moved, or that fit, stay where they are."""
    from PySide import QtCore, QtGui
    mw = FreeCADGui.getMainWindow()
    bars = [mw.findChild(QtGui.QToolBar, title) for title, _ in toolbars()[0]]
    bars = [b for b in bars if b is not None and b.isVisible() and
            mw.toolBarArea(b) == QtCore.Qt.TopToolBarArea]
    if not bars or all(b.width() >= b.sizeHint().width() for b in bars):
        return
    room = mw.width() - 20
    row = 0
    for k, bar in enumerate(bars):
        wants = bar.sizeHint().width()
        if k == 0 or row + wants > room:
            mw.insertToolBarBreak(bar)
            row = 0
        row += wants


class GroupCommand:
    """A drop-down of commands on a toolbar (FreeCAD's group command)."""

    def __init__(self, title, tip, members):
        self.title, self.tip, self.members = title, tip, members

    def GetCommands(self):
        return tuple(self.members)

    def GetDefaultCommand(self):
        return 0

    def GetResources(self):
        return {"MenuText": translate("FRep", self.title), "ToolTip": translate("FRep", self.tip)}

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None


class NodeCommand:
    """Creates one FRep feature type; operations take the selection as inputs."""

    def __init__(self, type_id):
        self.type_id = type_id
        self.info = FRepFeatures.NODE_TYPES[type_id]
        self.title = props.type_class_name(type_id)
        self.inputs = self.info["inputs"]

    def GetResources(self):
        tip = self.info["doc"]
        if self.inputs["min"] > 0:
            tip += "\n\nSelect its input%s first (%s), in order." % (
                "s" if self.inputs["max"] != 1 else "", self.input_rule())
        # The registry's texts are translated at run time (context "FRep"); they are not
        # literals a translation tool could collect.
        return {"Pixmap": FRepPaths.icon(self.type_id, self.info["category"]),
                "MenuText": translate("FRep", self.info["title"]),
                "ToolTip": translate("FRep", tip)}

    def input_rule(self):
        least, most = self.inputs["min"], self.inputs["max"]
        if most == least:
            return "exactly %d" % least
        return "at least %d" % least if most is None else "%d to %d" % (least, most)

    def IsActive(self):
        if FreeCAD.ActiveDocument is None:
            return False
        if self.inputs["min"] == 0:  # optional inputs are linked in the property view
            return True
        return len(FreeCADGui.Selection.getSelection()) >= self.inputs["min"]

    def selected_inputs(self):
        """The selection as inputs, or a message saying what is wrong with it."""
        selection = FreeCADGui.Selection.getSelection()
        least, most = self.inputs["min"], self.inputs["max"]
        if len(selection) < least or (most is not None and len(selection) > most):
            return None, ("%s needs %s input%s selected (FRep features, Part primitives, solids "
                          "or meshes); "
                          "%d %s selected" % (self.title, self.input_rule(),
                                              "" if most == 1 else "s", len(selection),
                                              "is" if len(selection) == 1 else "are"))
        wrong = [o for o in selection if not FRepTree.is_frep_input(o)]
        if wrong:
            return None, ("%s: %s %s not an FRep input; accepted: %s"
                          % (self.title, ", ".join(FRepTree.describe(o) for o in wrong),
                             "is" if len(wrong) == 1 else "are", FRepTree.ACCEPTED))
        return selection, None

    def Activated(self):
        doc = FreeCAD.ActiveDocument
        inputs = []
        if self.inputs["min"] > 0:
            inputs, problem = self.selected_inputs()
            if problem:
                report("FRep " + self.title, problem)
                return
        try:
            with Transaction(doc, "Create " + self.title):
                obj = FRepFeatures.make(self.type_id, doc, inputs=inputs, sized=True)
                add_to_active_container(obj)
                doc.recompute()
        except ValueError as e:
            report("FRep " + self.title, str(e))
            return
        # (a failed feature is kept: the user changes what the dialog's line says)
        report_if_failed("FRep " + self.title, obj)
        FreeCADGui.Selection.clearSelection()
        FreeCADGui.Selection.addSelection(obj)
        if not inputs and len(doc.Objects) == 1:
            FreeCADGui.SendMsgToActiveView("ViewFit")


class FromSolidCommand:
    """A command that makes a feature from the one selected FRep solid: Polygonize, Section,
    Point sample. `make(source, doc)` makes it (a ValueError: the solid cannot have one)."""

    def __init__(self, name, title, icon, tooltip, make):
        self.name, self.title, self.icon, self.tooltip, self.make = (name, title, icon,
                                                                      tooltip, make)

    def GetResources(self):
        return {"Pixmap": FRepPaths.icon(self.icon),
                "MenuText": QT_TRANSLATE_NOOP(self.name, self.title),
                "ToolTip": QT_TRANSLATE_NOOP(self.name, self.tooltip)}

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None and \
            len(FreeCADGui.Selection.getSelection()) == 1

    def Activated(self):
        where = "FRep " + self.title
        selection = FreeCADGui.Selection.getSelection()
        if len(selection) != 1 or not FRepTree.is_frep_input(selection[0]):
            report(where, "%s needs exactly one FRep feature, Part primitive or solid "
                   "selected" % self.title)
            return
        doc = selection[0].Document
        try:
            with Transaction(doc, self.title):
                obj = self.make(selection[0], doc)
                add_to_active_container(obj)
        except ValueError as e:  # (an empty or unbounded solid, for a box-centred plane)
            report(where, str(e))
            return
        # Recompute outside the transaction: a cancel or an error marks the feature, the user
        # sees why in the tree and can change its settings, and undo still removes it.
        doc.recompute()
        report_if_failed(where, obj)


def _make_section(source, doc):
    import FRepSection
    return FRepSection.make(source, doc)


def _make_point_sample(source, doc):
    import FRepPointSample
    return FRepPointSample.make(source, doc)


FROM_SOLID = {
    "FRep_Polygonize": (
        "Polygonize", "polygonize",
        "Mesh the selected FRep solid at full resolution into a Polygonize feature (automatic "
        "bounding box, resolution and method in its properties). Shows progress; Esc or the "
        "cancel button stops it.", FRepPolygonize.make),
    "FRep_Section": (
        "Section", "section",
        "Cut the selected FRep solid by a plane (through the middle of its box, across z; "
        "Origin and Normal in its properties) into closed wires that Sketcher, Part and "
        "PartDesign use like any edges.", _make_section),
    "FRep_PointSample": (
        "Point sample", "point_sample",
        "Points on the selected FRep solid's surface, about a cell apart (Cells in its "
        "properties), as a FreeCAD Points object.", _make_point_sample),
}


class ExportCommand:
    ASCII_STL = "STL mesh, ASCII (*.stl)"
    BEAMS = "3MF beam lattice, a strut lattice's struts as beams (*.3mf)"
    FILTERS = ("STL mesh (*.stl);;" + ASCII_STL + ";;3MF, each selected object its own (*.3mf);;"
               + BEAMS + ";;Wavefront OBJ (*.obj);;Stanford PLY (*.ply)")

    def GetResources(self):
        return {"Pixmap": FRepPaths.icon("export"),
                "MenuText": QT_TRANSLATE_NOOP("FRep_Export", "Export printable mesh..."),
                "ToolTip": QT_TRANSLATE_NOOP(
                    "FRep_Export",
                    "Mesh the selected FRep solids (or Polygonize features, with their "
                    "settings), check the mesh with CGAL and write it only when it is "
                    "printable: closed, manifold, outward, no self-intersections.")}

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None and bool(FreeCADGui.Selection.getSelection())

    def Activated(self):
        import os
        from PySide import QtGui
        import FRepExport
        objects = FreeCADGui.Selection.getSelection()
        start = os.path.join(os.path.dirname(FreeCAD.ActiveDocument.FileName or "") or
                             os.path.expanduser("~"), objects[0].Label + ".stl")
        filename, chosen = QtGui.QFileDialog.getSaveFileName(
            FreeCADGui.getMainWindow(), "Export printable mesh", start, self.FILTERS)
        if not filename:
            return
        options = export_options(objects, filename)
        if options is None:
            return
        if chosen == self.ASCII_STL:
            options["fmt"] = "stl-ascii"
        if chosen == self.BEAMS:
            options["fmt"] = "3mf-beams"
        try:
            result = FRepExport.export_objects(objects, filename, **options)
        except (ValueError, RuntimeError, OSError) as e:
            report("FRep export", str(e))
            return
        FreeCAD.Console.PrintMessage("%s\n" % result["text"])
        # (after the warnings the export printed, which FreeCAD's status bar shows as well)
        from PySide import QtCore
        written = ("Wrote %s: %d triangles, watertight (closed, manifold, outward, no "
                   "self-intersections); walls and overhangs: FRep > Printability"
                   % (filename, result["triangles"]))
        if "beams" in result:
            written = "Wrote %s: %s" % (filename, result["summary"])
        QtCore.QTimer.singleShot(200, lambda: FreeCADGui.getMainWindow().statusBar()
                                 .showMessage(written, 15000))


def export_options(objects, filename):
    """The export's options, asked where the objects do not carry them: cells and tolerance
    for FRep features (a Polygonize feature has its own), the unit of a 3MF. {} when there is
    nothing to ask, None when the user cancels."""
    import FRepPolygonize
    from PySide import QtGui
    unmeshed = [o for o in objects
                if not isinstance(getattr(o, "Proxy", None), FRepPolygonize.Polygonize)]
    three_mf = filename.lower().endswith(".3mf")
    if not unmeshed and not three_mf:
        return {}
    dialog = QtGui.QDialog(FreeCADGui.getMainWindow())
    dialog.setObjectName("FRepExportOptions")
    dialog.setWindowTitle(translate("FRep", "Export options"))
    form = QtGui.QFormLayout(dialog)
    cells = tolerance = unit = None
    if unmeshed:
        cells = QtGui.QSpinBox()
        cells.setObjectName("Cells")
        cells.setRange(8, 4096)
        cells.setValue(FRepPaths.frepcore.DEFAULT_CELLS)
        cells.setToolTip(translate("FRep", "Grid cells along the longest side of each solid's "
                                           "box (Polygonize features keep their own)"))
        form.addRow(translate("FRep", "Cells"), cells)
        tolerance = QtGui.QDoubleSpinBox()
        tolerance.setObjectName("Tolerance")
        tolerance.setDecimals(4)
        tolerance.setRange(0.0, 1000.0)
        tolerance.setToolTip(translate("FRep", "Simplify within this distance of the surface "
                                               "(0: off; a tenth of a cell is a good start)"))
        form.addRow(translate("FRep", "Tolerance"), tolerance)
    if three_mf:
        unit = QtGui.QComboBox()
        unit.setObjectName("Unit")
        unit.addItems(["mm", "micron", "cm", "m", "inch", "ft"])
        form.addRow(translate("FRep", "3MF unit"), unit)
    buttons = QtGui.QDialogButtonBox(QtGui.QDialogButtonBox.Ok | QtGui.QDialogButtonBox.Cancel)
    buttons.accepted.connect(dialog.accept)
    buttons.rejected.connect(dialog.reject)
    form.addRow(buttons)
    if not dialog.exec_():
        return None
    options = {}
    if cells is not None:
        options["cells"] = cells.value()
        if tolerance.value():
            options["settings"] = {"tolerance": tolerance.value()}
    if unit is not None:
        options["unit"] = unit.currentText()
    return options


class PreviewQualityCommand:
    def GetResources(self):
        return {"Pixmap": FRepPaths.icon("preview"),
                "MenuText": QT_TRANSLATE_NOOP("FRep_PreviewQuality", "Preview quality..."),
                "ToolTip": translate(
                    "FRep_PreviewQuality",
                    "Grid cells along the longest side of every FRep preview in this "
                    "document (default %d). Lower is faster to recompute; exports are "
                    "not affected.") % FRepMeshing.DEFAULT_PREVIEW_CELLS}

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None

    def Activated(self):
        from PySide import QtGui
        doc = FreeCAD.ActiveDocument
        cells, ok = QtGui.QInputDialog.getInt(
            FreeCADGui.getMainWindow(), "FRep preview quality",
            "Grid cells along the longest side of each preview (%d to %d):"
            % (FRepMeshing.MIN_CELLS, FRepMeshing.MAX_CELLS),
            FRepMeshing.preview_cells(doc), FRepMeshing.MIN_CELLS, FRepMeshing.MAX_CELLS)
        if ok:  # a view setting, like FreeCAD's mesh deviation: not an undo step
            FRepMeshing.set_preview_cells(doc, cells)


class SolidToleranceCommand:
    def GetResources(self):
        return {"Pixmap": FRepPaths.icon("solid_tolerance"),
                "MenuText": QT_TRANSLATE_NOOP("FRep_SolidTolerance", "Solid input tolerance..."),
                "ToolTip": translate(
                    "FRep_SolidTolerance",
                    "How closely solids used as FRep inputs (PartDesign bodies, Part features, "
                    "imported STEP) are tessellated: the largest distance between the facets "
                    "and the exact surface, in mm. 0: automatic (0.1 % of each solid's size).")}

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None

    def Activated(self):
        from PySide import QtGui
        import FRepSolids
        doc = FreeCAD.ActiveDocument
        current = float(doc.Meta.get(FRepSolids.TOLERANCE_KEY) or 0.0)
        mm, ok = QtGui.QInputDialog.getDouble(
            FreeCADGui.getMainWindow(), "FRep solid input tolerance",
            "Largest distance between a solid and its facets, mm (0: automatic):",
            current, 0.0, 100.0, 4)
        if ok:
            FRepSolids.set_solid_tolerance(doc, mm if mm > 0 else None)
            doc.recompute()


def _deformable(obj):
    import FRepLattice
    return not FRepLattice.is_lattice(obj) and (
        FRepTree.is_frep_input(obj) or obj.isDerivedFrom("Mesh::Feature"))


class LatticeCommand:
    """A lattice fitted to the selected object (FRep feature, solid or mesh)."""

    def GetResources(self):
        return {"Pixmap": FRepPaths.icon("lattice", "deformation"),
                "MenuText": QT_TRANSLATE_NOOP("FRep_Lattice", "Lattice"),
                "ToolTip": translate(
                    "FRep_Lattice",
                    "A free-form deformation lattice (Sederberg-Parry, as in Houdini or "
                    "Blender) fitted around the selected object: 2 x 2 x 2 cells to start "
                    "with. Double-click it to drag its control points; apply it with Deform.")}

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None and \
            len(FreeCADGui.Selection.getSelection()) == 1

    def Activated(self):
        import FRepLattice
        doc = FreeCAD.ActiveDocument
        target = FreeCADGui.Selection.getSelection()[0]
        if not _deformable(target):
            report("FRep Lattice", "Lattice: %s cannot be deformed; select an FRep feature, a "
                   "solid or a mesh" % FRepTree.describe(target))
            return
        try:
            with Transaction(doc, "Create Lattice"):
                obj = FRepLattice.make_lattice(doc, target=target)
                add_to_active_container(obj)
                doc.recompute()
        except ValueError as e:
            report("FRep Lattice", str(e))
            return
        report_if_failed("FRep Lattice", obj)


class DeformCommand:
    """The selected object deformed by the selected lattice (or by a new one fitted to it)."""

    def GetResources(self):
        return {"Pixmap": FRepPaths.icon("deform"),
                "MenuText": QT_TRANSLATE_NOOP("FRep_Deform", "Deform"),
                "ToolTip": translate(
                    "FRep_Deform",
                    "Deforms the selected object by the selected lattice: FRep features, "
                    "solids and volumes exactly (through the lattice's inverse, no gaps), "
                    "meshes vertex by vertex. Select the object, then its lattice; without a "
                    "lattice one is fitted to the object.")}

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None and \
            1 <= len(FreeCADGui.Selection.getSelection()) <= 2

    def Activated(self):
        import FRepLattice
        doc = FreeCAD.ActiveDocument
        selection = FreeCADGui.Selection.getSelection()
        lattices = [o for o in selection if FRepLattice.is_lattice(o)]
        bases = [o for o in selection if not FRepLattice.is_lattice(o)]
        if len(bases) != 1 or len(lattices) > 1 or not _deformable(bases[0]):
            report("FRep Deform", "Deform needs one FRep feature, solid or mesh selected, and "
                   "optionally one Lattice; the selection is %s"
                   % (", ".join(FRepTree.describe(o) for o in selection) or "empty"))
            return
        try:
            with Transaction(doc, "Create Deform"):
                lattice = lattices[0] if lattices else FRepLattice.make_lattice(doc, target=bases[0])
                obj = FRepLattice.make_deform(doc, bases[0], lattice)
                add_to_active_container(obj)
                doc.recompute()
        except ValueError as e:
            report("FRep Deform", str(e))
            return
        report_if_failed("FRep Deform", obj)
        FreeCADGui.Selection.clearSelection()
        FreeCADGui.Selection.addSelection(obj)


def _selected_meshes():
    import FRepManufacturing
    return [o for o in FreeCADGui.Selection.getSelection() if FRepManufacturing.is_mesh_object(o)]


class RepairCommand:
    """Each selected mesh repaired into a new Mesh feature beside it (the input untouched)."""

    def GetResources(self):
        return {"Pixmap": FRepPaths.icon("repair"),
                "MenuText": QT_TRANSLATE_NOOP("FRep_Repair", "Repair mesh"),
                "ToolTip": QT_TRANSLATE_NOOP(
                    "FRep_Repair",
                    "Makes the selected meshes printable: welds cracks, removes degenerate and "
                    "duplicate triangles, fills holes, orients outward and resolves "
                    "self-intersections (CGAL), rebuilding through a level set where that is "
                    "not enough. The result is a new mesh, checked; the input is kept.")}

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None and bool(_selected_meshes())

    def Activated(self):
        import FRepManufacturing
        doc = FreeCAD.ActiveDocument
        made, failed = [], []
        for obj in _selected_meshes():
            try:
                with Transaction(doc, "Repair %s" % obj.Label):
                    out, result = FRepManufacturing.repair(obj)
                    if out is not None:
                        add_to_active_container(out)
                        doc.recompute()
            except (ValueError, RuntimeError, OSError) as e:
                failed.append(str(e))
                continue
            FreeCAD.Console.PrintMessage(result["text"])
            if out is None:
                why = result["reasons"] + result["departures"]
                failed.append("%s could not be %s:\n%s"
                              % (obj.Label,
                                 "made printable" if not result["printable"]
                                 else "repaired without changing the part",
                                 "\n".join(" - " + r for r in why)))
            else:
                made.append(out)
        if failed:
            report("FRep Repair", "\n\n".join(failed))
        if made:
            FreeCADGui.Selection.clearSelection()
            for out in made:
                FreeCADGui.Selection.addSelection(out)


class PrintabilityCommand:
    """The printability report of the selected mesh, in a task panel."""

    def GetResources(self):
        return {"Pixmap": FRepPaths.icon("printability"),
                "MenuText": QT_TRANSLATE_NOOP("FRep_Printability", "Printability..."),
                "ToolTip": QT_TRANSLATE_NOOP(
                    "FRep_Printability",
                    "Checks the selected mesh with CGAL and reports its thinnest wall (walls "
                    "below the minimum in red), overhang area, volume and mass.")}

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None and len(_selected_meshes()) == 1 and \
            FreeCADGui.Control.activeDialog() is False

    def Activated(self):
        import FRepTaskPanels
        panel = FRepTaskPanels.PrintabilityPanel(_selected_meshes()[0])
        FreeCADGui.Control.showDialog(panel)
        panel.run()


# Every command of the workbench but the toolbars' groups, by name (filled by register()).
COMMANDS = {}


def register():
    """Adds every command to FreeCAD; returns the toolbars as (title, command names) and the
    menus as (submenu title, command names)."""
    COMMANDS.clear()
    for type_id in FRepFeatures.NODE_TYPES:
        COMMANDS[command_name(type_id)] = NodeCommand(type_id)
    for name, (title, icon, tooltip, make) in FROM_SOLID.items():
        COMMANDS[name] = FromSolidCommand(name, title, icon, tooltip, make)
    COMMANDS.update({"FRep_Export": ExportCommand(),
                     "FRep_PreviewQuality": PreviewQualityCommand(),
                     "FRep_SolidTolerance": SolidToleranceCommand(),
                     "FRep_Lattice": LatticeCommand(), "FRep_Deform": DeformCommand(),
                     "FRep_Repair": RepairCommand(), "FRep_Printability": PrintabilityCommand()})
    COMMANDS.update(FRepHSplineCommands.commands())
    for name, command in COMMANDS.items():
        FreeCADGui.addCommand(name, command)
    bars, groups = toolbars()
    for name, (title, tip, members) in groups.items():
        FreeCADGui.addCommand(name, GroupCommand(title, tip, members))
    return bars, menus()
