"""Task panels: the parameters of an FRep feature, edited with a live preview.

Opened by double-clicking a feature (its view provider's setEdit). Every change is applied to
the property at once and the document recomputed, so the 3D view follows. The whole edit is
one undo step ("Edit <label>"): OK commits it, Cancel aborts it and every value is as it was.
Parameters the panel cannot show as a field (matrices, point lists) are left to the property
view, and the panel says so.
"""

import FreeCAD
import FreeCADGui

import FRepProperties as props
from FRepGuiHelpers import narrow, panel_title

try:
    translate = FreeCAD.Qt.translate
except AttributeError:  # FreeCAD without its Qt helpers (headless tests)
    def translate(context, text):
        return text

# A field's range: the registry's allowed range where finite, else this.
UNBOUNDED = 1e9
UNIT_SUFFIX = {"length": " mm", "angle": " \u00b0", "": ""}


def _limits(param):
    lo = param["min"] if param["min"] is not None else -UNBOUNDED
    hi = param["max"] if param["max"] is not None else UNBOUNDED
    return lo, hi


def decimals_for(*values):
    """The decimals a field shows: three, or as many (up to six) as its value needs so that
    opening the panel does not round it."""
    for places in range(3, 7):
        if all(abs(round(v, places) - v) <= 1e-9 * max(1.0, abs(v)) for v in values):
            return places
    return 6


def compact(box, param):
    """A parameter's spin box, narrow, with the parameter's unit."""
    box.setSuffix(UNIT_SUFFIX.get(param["unit"], ""))
    return narrow(box)


class ParametersPanel:
    """The Qt form of one feature's parameters (FreeCAD task panel protocol)."""

    def __init__(self, obj):
        from PySide import QtGui
        self.obj = obj
        self.doc = obj.Document
        self.fields = {}  # property name -> (getter, setter of the widget)
        self.doc.openTransaction(translate("FRep", "Edit %s") % obj.Label)
        self.form = QtGui.QWidget()
        self.form.setObjectName("FRepParametersPanel")
        self.form.setWindowTitle(panel_title(obj.Label))
        layout = QtGui.QFormLayout(self.form)
        # a label above its field where the two do not fit side by side
        layout.setRowWrapPolicy(QtGui.QFormLayout.WrapLongRows)
        layout.setFieldGrowthPolicy(QtGui.QFormLayout.AllNonFixedFieldsGrow)
        skipped = []
        for param in obj.Proxy.parameters():
            name = props.property_name(param["name"])
            widget = self._field(param, name)
            if widget is None:
                skipped.append(name)
                continue
            widget.setToolTip(props.tooltip(param))
            # (a formula's letter gets the registry's words: "Strength (a0)")
            layout.addRow(translate("FRep", param.get("title") or name), widget)
        if skipped:
            note = QtGui.QLabel(translate("FRep", "Edit in the property view: %s")
                                % ", ".join(skipped))
            note.setWordWrap(True)
            layout.addRow(note)
        self.status = QtGui.QLabel("")
        self.status.setObjectName("FRepPanelStatus")
        self.status.setWordWrap(True)
        layout.addRow(self.status)

    # -- fields -------------------------------------------------------------------------
    def _field(self, param, name):
        from PySide import QtGui
        t = param["type"]
        value = getattr(self.obj, name)
        if t in ("real", "integer"):
            box = QtGui.QDoubleSpinBox() if t == "real" else QtGui.QSpinBox()
            lo, hi = _limits(param)
            if t == "real":
                box.setDecimals(decimals_for(float(value)))
                box.setSingleStep(0.1)
            else:
                lo, hi = int(max(lo, -2 ** 31 + 1)), int(min(hi, 2 ** 31 - 1))
            box.setRange(lo, hi)
            box.setValue(float(value) if t == "real" else int(value))
            compact(box, param)
            box.setObjectName(name)
            box.valueChanged.connect(lambda v, n=name: self._apply(n, v))
            self.fields[name] = box
            return box
        if t == "boolean":
            box = QtGui.QCheckBox()
            box.setChecked(bool(value))
            box.setObjectName(name)
            box.toggled.connect(lambda v, n=name: self._apply(n, v))
            self.fields[name] = box
            return box
        if t == "choice":
            box = QtGui.QComboBox()
            # (as narrow as eight characters; the list opens as wide as its longest choice)
            box.setSizeAdjustPolicy(QtGui.QComboBox.AdjustToMinimumContentsLengthWithIcon)
            box.setMinimumContentsLength(8)
            box.addItems(list(param["choices"]))
            box.setCurrentIndex(list(param["choices"]).index(value))
            box.setObjectName(name)
            box.currentIndexChanged.connect(
                lambda i, n=name, c=list(param["choices"]): self._apply(n, c[i]))
            self.fields[name] = box
            return box
        if t == "vector3":
            # x, y and z one under the other: three fields side by side do not fit the
            # Combo View
            row = QtGui.QWidget()
            row.setObjectName(name)
            grid = QtGui.QGridLayout(row)
            grid.setContentsMargins(0, 0, 0, 0)
            grid.setVerticalSpacing(2)
            grid.setColumnStretch(1, 1)  # (the fields take the width, not the axis letters)
            boxes = []
            places = decimals_for(*value)
            for axis in range(3):
                b = QtGui.QDoubleSpinBox()
                b.setDecimals(places)
                b.setRange(-UNBOUNDED, UNBOUNDED)
                b.setValue(value[axis])
                b.setObjectName("%s.%s" % (name, "xyz"[axis]))
                compact(b, param)
                grid.addWidget(QtGui.QLabel("xyz"[axis]), axis, 0)
                grid.addWidget(b, axis, 1)
                boxes.append(b)
            for b in boxes:
                b.valueChanged.connect(lambda _v, n=name, bs=boxes: self._apply(
                    n, FreeCAD.Vector(*[x.value() for x in bs])))
            self.fields[name] = row
            return row
        if t == "text":
            line = QtGui.QLineEdit(value)
            line.setObjectName(name)
            line.editingFinished.connect(lambda n=name, w=line: self._apply(n, w.text()))
            self.fields[name] = line
            return line
        return None

    def _apply(self, name, value):
        """Live preview: the property takes the value and the document recomputes."""
        try:
            setattr(self.obj, name, value)
        except Exception as e:  # a value the property refuses: say so, keep editing
            self.status.setText(str(e))
            return
        self.doc.recompute()
        self.status.setText(self.obj.getStatusString() if "Invalid" in self.obj.State else "")

    # -- FreeCAD task panel protocol ------------------------------------------------------
    def getStandardButtons(self):
        from PySide import QtGui
        return int(QtGui.QDialogButtonBox.Ok | QtGui.QDialogButtonBox.Cancel)

    def accept(self):
        self.doc.commitTransaction()
        self.doc.recompute()
        FreeCADGui.ActiveDocument.resetEdit()
        return True

    def reject(self):
        self.doc.abortTransaction()  # every value as it was before the panel opened
        self.doc.recompute()
        FreeCADGui.ActiveDocument.resetEdit()
        return True


class LatticeEditPanel:
    """While a lattice is edited: what to do, and Close to leave edit mode (each drag is
    already its own undo step)."""

    def __init__(self, obj):
        from PySide import QtGui
        self.obj = obj
        self.form = QtGui.QWidget()
        self.form.setObjectName("FRepLatticeEditPanel")
        self.form.setWindowTitle(panel_title(translate("FRep", "Edit %s") % obj.Label))
        layout = QtGui.QVBoxLayout(self.form)
        text = QtGui.QLabel(translate(
            "FRep", "Drag a control point's handle to move it: the cube moves it freely, the "
                    "arrows along an axis. Every drag is one undo step. Offsets in the "
                    "property view hold the exact values; Amount scales them all."))
        text.setWordWrap(True)
        layout.addWidget(text)
        # A point of its own: a vector property that expressions and spreadsheets can drive.
        row = QtGui.QHBoxLayout()
        self.index = []
        for axis, name in enumerate(("DivisionsX", "DivisionsY", "DivisionsZ")):
            box = QtGui.QSpinBox()
            box.setRange(0, getattr(obj, name))
            box.setObjectName("PointIndex" + "ijk"[axis])
            box.setToolTip(translate("FRep", "Control point index %s (0 to %d)")
                           % ("ijk"[axis], getattr(obj, name)))
            row.addWidget(box)
            self.index.append(box)
        expose = QtGui.QPushButton(translate("FRep", "Own property"))
        expose.setObjectName("ExposePoint")
        expose.setToolTip(translate(
            "FRep", "Gives control point (i, j, k) a vector property of its own, "
                    "Point_i_j_k, that expressions and spreadsheets can drive"))
        expose.clicked.connect(self.expose)
        row.addWidget(expose)
        layout.addLayout(row)
        self.status = QtGui.QLabel("")
        self.status.setWordWrap(True)
        layout.addWidget(self.status)

    def expose(self):
        """One undo step: the chosen point's own property, starting at its current offset."""
        ijk = tuple(b.value() for b in self.index)
        doc = self.obj.Document
        doc.openTransaction(translate("FRep", "Expose lattice point"))
        try:
            name = self.obj.Proxy.expose_point(self.obj, ijk)
            doc.commitTransaction()
            self.status.setText(translate("FRep", "%s added (group Control points): bind its "
                                                  "x, y or z to an expression") % name)
        except ValueError as e:
            doc.abortTransaction()
            self.status.setText(str(e))

    def getStandardButtons(self):
        from PySide import QtGui
        return int(QtGui.QDialogButtonBox.Close)

    def reject(self):
        import FreeCADGui
        FreeCADGui.ActiveDocument.resetEdit()
        return True


def watertight(report):
    """What Export checks of a mesh (its CGAL check): closed, manifold, outward, no
    self-intersection, no degenerate triangle."""
    return (report["closed"] and report["outward"] and not report["non_manifold_edges"] and
            not report["non_manifold_vertices"] and not report["self_intersections"] and
            not report["degenerate_triangles"])


def verdict_lines(report, wall):
    """The panel's verdict in the words Export uses: watertight or not (Export's check), then
    the walls this panel adds."""
    lines = ["%s%s" % ("PRINTABLE" if report["printable"] else "NOT printable",
                       " with walls of at least %g mm" % wall if wall else "")]
    lines.append("Watertight (what Export checks): %s" % (
        "yes" if watertight(report) else "no"))
    if wall:
        lines.append("Triangles where the wall is thinner than %g mm: %d (in red)"
                     % (wall, report["print"]["thin_triangles"]))
    cavities = report["print"].get("cavities")
    if cavities:
        lines.append("Enclosed cavities, which trap resin or powder: %d, volume %.4g mm\u00b3 "
                     "(in blue)" % (cavities, report["print"]["cavity_volume"]))
    return "\n".join(lines)


class PrintabilityPanel:
    """The printability report of a mesh: minimum wall, material, build direction and
    overhang angle in, the report out, the triangles thinner than the wall in red and the
    walls of enclosed cavities in blue (the mesh drawn see-through while the panel is open);
    for an infill's mesh, a button that drains the cavities."""

    # The mesh's transparency while its cavities are shown.
    SEE_THROUGH = 60

    DIRECTIONS = (("z", (0, 0, 1)), ("y", (0, 1, 0)), ("x", (1, 0, 0)),
                  ("-z", (0, 0, -1)), ("-y", (0, -1, 0)), ("-x", (-1, 0, 0)))

    def __init__(self, obj):
        from PySide import QtGui
        from FRepPaths import frepcore
        self.obj = obj
        self.report = None
        self.form = QtGui.QWidget()
        self.form.setObjectName("FRepPrintabilityPanel")
        self.form.setWindowTitle(panel_title(translate("FRep", "Printability of %s")
                                             % obj.Label))
        layout = QtGui.QFormLayout(self.form)
        layout.setRowWrapPolicy(QtGui.QFormLayout.WrapLongRows)
        layout.setFieldGrowthPolicy(QtGui.QFormLayout.AllNonFixedFieldsGrow)
        self.min_wall = QtGui.QDoubleSpinBox()
        self.min_wall.setObjectName("MinWall")
        self.min_wall.setDecimals(3)
        self.min_wall.setRange(0.0, 1000.0)
        self.min_wall.setValue(0.8)
        self.min_wall.setSuffix(" mm")
        narrow(self.min_wall)
        self.min_wall.setToolTip(translate("FRep", "Walls thinner than this are shown in red "
                                                   "and make the part not printable (0: none)"))
        layout.addRow(translate("FRep", "Minimum wall"), self.min_wall)
        self.material = QtGui.QComboBox()
        self.material.setObjectName("Material")
        self.material.addItems(sorted(frepcore.materials()))
        narrow(self.material)
        self.material.setCurrentIndex(self.material.findText("pla"))
        layout.addRow(translate("FRep", "Material"), self.material)
        self.up = QtGui.QComboBox()
        self.up.setObjectName("BuildDirection")
        self.up.addItems([name for name, _ in self.DIRECTIONS])
        narrow(self.up)
        layout.addRow(translate("FRep", "Build direction"), self.up)
        self.overhang = QtGui.QDoubleSpinBox()
        self.overhang.setObjectName("Overhang")
        self.overhang.setRange(0.0, 90.0)
        self.overhang.setValue(45.0)
        self.overhang.setSuffix(" \u00b0")
        narrow(self.overhang)
        layout.addRow(translate("FRep", "Overhang from vertical"), self.overhang)
        run = QtGui.QPushButton(translate("FRep", "Check"))
        run.setObjectName("RunPrintability")
        run.clicked.connect(self.run)
        layout.addRow(run)
        self.drain = QtGui.QPushButton(translate("FRep", "Drain the cavities"))
        self.drain.setObjectName("DrainCavities")
        self.drain.setEnabled(False)
        self.drain.clicked.connect(self.drain_cavities)
        layout.addRow(self.drain)
        self.transparency = None  # the mesh's own, while it is drawn see-through
        self.text = QtGui.QPlainTextEdit()
        self.text.setObjectName("PrintabilityReport")
        self.text.setReadOnly(True)
        self.text.setMinimumHeight(260)
        layout.addRow(self.text)

    def run(self):
        import FRepManufacturing
        wall = self.min_wall.value() or None
        try:
            self.report = FRepManufacturing.printability(
                self.obj, min_wall=wall, material=self.material.currentText(),
                up=dict(self.DIRECTIONS)[self.up.currentText()], overhang=self.overhang.value())
        except (ValueError, OSError) as e:
            self.text.setPlainText(str(e))
            return None
        self.text.setPlainText("%s\n\n%s" % (verdict_lines(self.report, wall),
                                               self.report["text"]))
        walls = self.report["cavity_triangles"]
        FRepManufacturing.show_regions(self.obj, self.report["thin"], walls)
        self.see_through(bool(walls))
        infill = FRepManufacturing.infill_of(self.obj)
        self.drain.setEnabled(bool(walls) and infill is not None)
        self.drain.setToolTip(
            translate("FRep", "Adds a drain hole on each cavity's floor to %s's Drain holes "
                              "(one undo step), then checks again") % infill.Label
            if infill is not None else
            translate("FRep", "Drain holes are made by an Infill; this mesh is not one's"))
        return self.report

    def see_through(self, on):
        """Draws the mesh see-through while cavities are shown, so that their walls show."""
        view = getattr(self.obj, "ViewObject", None)
        if view is None or not hasattr(view, "Transparency"):
            return
        if on and self.transparency is None:
            self.transparency = view.Transparency
            view.Transparency = max(view.Transparency, self.SEE_THROUGH)
        elif not on and self.transparency is not None:
            view.Transparency = self.transparency
            self.transparency = None

    def drain_cavities(self):
        """Adds drain holes on the cavities' floors to the infill, recomputes and checks
        again."""
        import FRepManufacturing
        infill = FRepManufacturing.infill_of(self.obj)
        if infill is None or not self.report:
            return 0
        doc = infill.Document
        doc.openTransaction(translate("FRep", "Drain the cavities"))
        try:
            added = FRepManufacturing.drain_cavities(
                infill, self.report, dict(self.DIRECTIONS)[self.up.currentText()])
        except ValueError as e:
            doc.abortTransaction()
            self.text.setPlainText(str(e))
            return 0
        doc.commitTransaction()
        doc.recompute()
        self.run()
        if added:
            self.text.setPlainText(translate("FRep", "Added %d drain holes to %s.") % (
                added, infill.Label) + "\n" + self.text.toPlainText())
        return added

    def accept(self):
        self.see_through(False)
        FreeCADGui.Control.closeDialog()
        return True

    def reject(self):
        self.see_through(False)
        FreeCADGui.Control.closeDialog()
        return True

    def getStandardButtons(self):
        from PySide import QtGui
        return int(QtGui.QDialogButtonBox.Close)
