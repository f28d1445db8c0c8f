"""The Attach panel (edit mode of an hspline Attachment): the rectangle of the parent's level-0
CVs the cylinder stands on (typed, or taken from the CVs tagged by Ctrl+click in the parent's
edit mode), the limb's height and the seam's subdivisions, with a live preview. OK is one undo
step with whatever made the attachment; Cancel leaves the document as it was."""

import FreeCAD
import FreeCADGui

from FRepGuiHelpers import narrow, panel_title, translate

FIELDS = (("I0", "First CV along u"), ("I1", "Last CV along u"),
          ("J0", "First CV along v"), ("J1", "Last CV along v"))


class AttachPanel:
    def __init__(self, obj, transaction_open=False):
        from PySide import QtGui
        self.obj, self.doc = obj, obj.Document
        if not transaction_open:  # the Attach command opened it with the new objects
            self.doc.openTransaction(translate("FRep", "Edit %s") % obj.Label)
        self.form = QtGui.QWidget()
        self.form.setObjectName("FRepAttachPanel")
        self.form.setWindowTitle(panel_title(translate("FRep", "Attach to %s") % obj.Parent.Label))
        layout = QtGui.QFormLayout(self.form)
        layout.setRowWrapPolicy(QtGui.QFormLayout.WrapLongRows)
        layout.setFieldGrowthPolicy(QtGui.QFormLayout.AllNonFixedFieldsGrow)
        text = QtGui.QLabel(translate(
            "FRep", "The cylinder stands on the ring of the parent's CVs around this "
                    "rectangle (CVs of the seam level). Ctrl+click CVs in the parent's edit "
                    "mode and take them with From tagged CVs."))
        text.setWordWrap(True)
        layout.addRow(text)
        self.level = narrow(QtGui.QSpinBox())
        self.level.setObjectName("SeamLevel")
        self.level.setRange(0, 3)
        self.level.setValue(obj.SeamLevel)
        self.level.setToolTip(translate("FRep", "The parent's level the ring is taken on: each "
                                                "level doubles the CVs around the joint (the "
                                                "seam refined) and keeps the parent's detail "
                                                "up to it"))
        self.level.valueChanged.connect(self.level_changed)
        layout.addRow(translate("FRep", "Seam level"), self.level)
        self.boxes = {}
        for name, tip in FIELDS:
            box = narrow(QtGui.QSpinBox())
            box.setValue(getattr(obj, name))
            box.setObjectName(name)
            box.setToolTip(translate("FRep", tip))
            box.valueChanged.connect(self.rectangle_changed)
            layout.addRow(name, box)
            self.boxes[name] = box
        self.set_ranges()
        self.tagged = QtGui.QPushButton(translate("FRep", "From tagged CVs"))
        self.tagged.setObjectName("FromTagged")
        self.tagged.clicked.connect(self.from_tagged)
        layout.addRow(self.tagged)
        self.height = narrow(QtGui.QDoubleSpinBox())
        self.height.setObjectName("LimbHeight")
        self.height.setRange(0.001, 1e6)
        self.height.setDecimals(3)
        self.height.setSuffix(" mm")
        self.height.setValue(float(obj.LimbHeight) or 1.0)
        self.height.setEnabled(obj.LimbHeight > 0)
        self.height.setToolTip(translate("FRep", "How high the cylinder's top row stands above "
                                                 "the ring, along the parent's normal"))
        self.height.valueChanged.connect(self.height_changed)
        layout.addRow(translate("FRep", "Height"), self.height)
        self.steps = narrow(QtGui.QSpinBox())
        self.steps.setObjectName("Subdivisions")
        self.steps.setRange(0, 6)
        self.steps.setValue(obj.Subdivisions)
        self.steps.setToolTip(translate("FRep", "Catmull-Clark steps of the seam: each makes "
                                                "four times the faces"))
        self.steps.valueChanged.connect(self.steps_changed)
        layout.addRow(translate("FRep", "Subdivisions"), self.steps)
        self.status = QtGui.QLabel("")
        self.status.setObjectName("FRepPanelStatus")
        self.status.setWordWrap(True)
        layout.addRow(self.status)
        self.describe()

    def set_ranges(self):
        nu, nv = self.obj.Proxy.parent_grid(self.obj)
        for name, box in self.boxes.items():
            box.blockSignals(True)
            box.setRange(0, (nu if name[0] == "I" else nv) - 1)
            box.setValue(getattr(self.obj, name))
            box.blockSignals(False)

    def level_changed(self, value):
        def change():
            self.obj.Proxy.set_seam_level(self.obj, value)
            self.set_ranges()  # (the rectangle carried over to the new level's CVs)
        self._apply(change)

    def rectangle(self):
        return tuple(self.boxes[name].value() for name, _ in FIELDS)

    def describe(self, error=None):
        if error is None and "Invalid" in self.obj.State:
            error = self.obj.getStatusString()
        if error:
            self.status.setText(error)
            return
        i0, i1, j0, j1 = self.rectangle()
        self.status.setText(translate("FRep", "Ring of %d CVs; %d triangles")
                            % (2 * (i1 - i0) + 2 * (j1 - j0), self.obj.Mesh.CountFacets))

    def _apply(self, change):
        try:
            change()
        except ValueError as e:
            self.describe(str(e))
            return
        self.doc.recompute()
        self.describe()

    def rectangle_changed(self, _value=None):
        self._apply(lambda: self.obj.Proxy.set_rectangle(self.obj, self.rectangle()))

    def from_tagged(self):
        """The rectangle of the tagged CVs on the level the parent shows (the seam moves to
        that level), else on the seam's level."""
        view = self.obj.Parent.ViewObject
        shown = view.ShowLevel if view is not None and hasattr(view, "ShowLevel") else -2
        levels = self.obj.Proxy.parent_levels(self.obj)
        shown = levels - 1 if shown == -1 else shown
        if 0 <= shown <= 3 and shown < levels and shown != self.obj.SeamLevel and \
                self.obj.Proxy.tagged_rectangle(self.obj, shown) is not None:
            self.level.setValue(shown)  # (carries the rectangle over, rebuilds the limb)
        rect = self.obj.Proxy.tagged_rectangle(self.obj)
        if rect is None:
            self.describe(translate("FRep", "%s has no tagged CVs of level %d spanning a "
                                            "rectangle: double-click it, Ctrl+click two "
                                            "opposite corners")
                          % (self.obj.Parent.Label, self.obj.SeamLevel))
            return
        for (name, _), value in zip(FIELDS, rect):
            self.boxes[name].blockSignals(True)
            self.boxes[name].setValue(value)
            self.boxes[name].blockSignals(False)
        self.rectangle_changed()

    def height_changed(self, value):
        def change():
            self.obj.LimbHeight = value
            self.obj.Proxy.set_rectangle(self.obj, self.rectangle())
        self._apply(change)

    def steps_changed(self, value):
        def change():
            self.obj.Subdivisions = value
        self._apply(change)

    # -- FreeCAD task panel protocol ------------------------------------------------------
    def getStandardButtons(self):
        from PySide import QtGui
        return int(QtGui.QDialogButtonBox.Ok | QtGui.QDialogButtonBox.Cancel)

    def accept(self):
        if "Invalid" in self.obj.State:
            self.describe()
            return False  # stay open: the rectangle does not fit
        self.doc.commitTransaction()
        self.doc.recompute()
        FreeCADGui.ActiveDocument.resetEdit()
        return True

    def reject(self):
        FreeCADGui.ActiveDocument.resetEdit()  # before the abort, which may delete the object
        self.doc.abortTransaction()
        self.doc.recompute()
        return True
