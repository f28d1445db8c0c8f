"""The HSpline edit panel (edit mode of an HSpline feature): the level shown, the tag tools
(seed 003's Tags menu, with Tag along U/V and Neighbours it wished for), Refine, Zero Offsets,
Unrefine and a move of the tagged CVs by a vector or along their normals. Every button is one
undo step; a refused request says why in the panel."""

import FreeCAD

from FRepGuiHelpers import narrow, panel_title, translate

TAG_TOOLS = (
    ("level", "Level", "Tag every CV of the shown level"),
    ("movable", "Movable", "Tag the CVs of the shown level that may move (Tag Movable)"),
    ("untag_fixed", "Untag fixed", "Keep only the tagged CVs that may move (Untag Fixed)"),
    ("along_u", "Along U", "Tag every CV on the u lines of the tagged CVs (Tag along U)"),
    ("along_v", "Along V", "Tag every CV on the v lines of the tagged CVs (Tag along V)"),
    ("neighbours", "Neighbours", "Add the up to 8 CVs around each tagged CV"),
    ("non_zero", "Non-zero", "Tag the CVs whose offset is not zero"),
    ("none", "Clear", "Untag everything"),
)


class HSplinePanel:
    def __init__(self, obj):
        from PySide import QtGui
        self.obj = obj
        self.form = QtGui.QWidget()
        self.form.setObjectName("FRepHSplinePanel")
        self.form.setWindowTitle(panel_title(translate("FRep", "Edit %s") % obj.Label))
        layout = QtGui.QVBoxLayout(self.form)
        text = QtGui.QLabel(translate(
            "FRep", "Ctrl+click a CV to tag it (fixed CVs, grey, cannot be tagged: they keep the "
                    "refined region joined to its parent). Drag a tagged CV's handle to move "
                    "it. Refine adds a finer level around the tagged CVs."))
        text.setWordWrap(True)
        layout.addWidget(text)
        row = QtGui.QHBoxLayout()
        row.addWidget(QtGui.QLabel(translate("FRep", "Level shown")))
        self.level = QtGui.QSpinBox()
        self.level.setObjectName("ShowLevel")
        self.level.setRange(-1, 11)
        self.level.setValue(obj.ViewObject.ShowLevel if obj.ViewObject else -1)
        self.level.setToolTip(translate("FRep", "-1: the finest level"))
        self.level.valueChanged.connect(self.show_level)
        row.addWidget(self.level)
        layout.addLayout(row)
        # Two buttons a row and one field a row: the panel fits the Combo View (264 px wide
        # by default).
        grid = QtGui.QGridLayout()
        for k, (how, label, tip) in enumerate(TAG_TOOLS):
            b = QtGui.QPushButton(translate("FRep", label))
            b.setObjectName("Tag_" + how)
            b.setToolTip(translate("FRep", tip))
            b.clicked.connect(lambda _=False, how=how: self.tag(how))
            grid.addWidget(b, k // 2, k % 2)
        layout.addLayout(grid)
        grid = QtGui.QGridLayout()
        for k, (name, label, slot) in enumerate((("Refine", "Refine", self.refine),
                                                 ("ZeroOffsets", "Zero offsets", self.zero),
                                                 ("Unrefine", "Unrefine", self.unrefine),
                                                 ("OwnProperty", "Own property", self.expose))):
            b = QtGui.QPushButton(translate("FRep", label))
            b.setObjectName(name)
            b.clicked.connect(slot)
            grid.addWidget(b, k // 2, k % 2)
        layout.addLayout(grid)
        form = QtGui.QFormLayout()
        self.move = []
        for axis, label in (("dx", "dx"), ("dy", "dy"), ("dz", "dz"), ("normal", "Along normal")):
            box = QtGui.QDoubleSpinBox()
            box.setRange(-1e6, 1e6)
            box.setDecimals(3)
            box.setSuffix(" mm")
            box.setObjectName("Move_" + axis)
            box.setToolTip(translate("FRep", "Move the tagged CVs by %s") % label.lower())
            form.addRow(translate("FRep", label), narrow(box))
            self.move.append(box)
        layout.addLayout(form)
        b = QtGui.QPushButton(translate("FRep", "Move tagged CVs"))
        b.setObjectName("MoveTagged")
        b.clicked.connect(self.move_tagged)
        layout.addWidget(b)
        self.status = QtGui.QLabel("")
        self.status.setObjectName("Status")
        self.status.setWordWrap(True)
        layout.addWidget(self.status)
        self.describe()

    def shown_level(self):
        h = self.obj.Proxy.hspline(self.obj)
        level = self.level.value()
        return h.level_count - 1 if level < 0 or level >= h.level_count else level

    def describe(self, message=""):
        h = self.obj.Proxy.hspline(self.obj)
        level = self.shown_level()
        text = translate("FRep", "%d levels, %d CVs. Level %d: %d CVs, %d movable. Tagged: %d.") % (
            h.level_count, h.cv_count, level, len(h.cvs(level)), len(h.select_movable(level)),
            len(self.obj.Proxy.tags(self.obj)))
        self.status.setText(message + ("\n" if message else "") + text)

    def show_level(self, value):
        if self.obj.ViewObject is not None:
            self.obj.ViewObject.ShowLevel = value
        self.describe()

    def run(self, title, action):
        """One undo step; a refusal leaves the document as it was and says why."""
        doc = self.obj.Document
        doc.openTransaction(title)
        try:
            result = action()
            doc.recompute()
            doc.commitTransaction()
        except ValueError as e:
            doc.abortTransaction()
            self.describe(str(e))
            return None
        self.describe()
        return result

    def tag(self, how):
        self.run("Tag hspline CVs", lambda: self.obj.Proxy.tag(self.obj, how, level=self.shown_level()))

    def refine(self):
        if self.run("Refine hspline", lambda: self.obj.Proxy.refine(self.obj)) is not None:
            self.level.setValue(-1)

    def zero(self):
        self.run("Zero hspline offsets", lambda: self.obj.Proxy.zero_offsets(self.obj))

    def unrefine(self):
        removed = self.run("Unrefine hspline", lambda: self.obj.Proxy.unrefine(self.obj))
        if removed is not None:
            self.describe(translate("FRep", "Unrefine removed %d CVs; the surface is unchanged")
                          % removed)

    def expose(self):
        """Each tagged CV that may move gets a vector property of its own (group CVs), for the
        property view, expressions and spreadsheets."""
        def action():
            cvs = [c for c in self.obj.Proxy.tags(self.obj) if self.obj.Proxy.hspline(self.obj).movable(*c)]
            if not cvs:
                raise ValueError(translate("FRep", "Tag CVs that may move first"))
            return [self.obj.Proxy.expose_cv(self.obj, c) for c in cvs]
        names = self.run("Expose hspline CVs", action)
        if names:
            self.describe(translate("FRep", "Added %s (group CVs): bind them to expressions")
                          % ", ".join(names))

    def move_tagged(self):
        dx, dy, dz, dn = (b.value() for b in self.move)
        cvs = [c for c in self.obj.Proxy.tags(self.obj)]
        if not cvs:
            self.describe(translate("FRep", "Tag the CVs to move first"))
            return
        self.run("Move hspline CVs", lambda: self.obj.Proxy.nudge(self.obj, cvs, (dx, dy, dz), dn))

    def getStandardButtons(self):
        from PySide import QtGui
        return int(QtGui.QDialogButtonBox.Close)

    def reject(self):
        import FreeCADGui
        FreeCADGui.ActiveDocument.resetEdit()
        FreeCAD.ActiveDocument.recompute()
