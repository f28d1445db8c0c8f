"""Helpers every command and panel of the workbench shares: FreeCAD's translation hooks, a
message the user acknowledges, the active container and one undo step. Of the workbench they
import only FRepErrors (which imports none of it), so any GUI module may import them."""

import FreeCAD
import FreeCADGui

import FRepErrors

try:  # FreeCAD's translation hooks (menu texts and tooltips go through them)
    from FreeCAD import Qt
    translate, QT_TRANSLATE_NOOP = Qt.translate, Qt.QT_TRANSLATE_NOOP
except ImportError:
    def translate(context, text):
        return text

    def QT_TRANSLATE_NOOP(context, text):
        return text


# The widest a task box's title gets (px): the box is never narrower than its title, and the
# Combo View is 264 px wide by default (the box's icon and margins take the rest).
TITLE_MAX_WIDTH = 150


def panel_title(text):
    """A task panel's title, elided in the middle to fit the Combo View."""
    from PySide import QtCore, QtGui
    metrics = QtGui.QFontMetrics(QtGui.QApplication.font())
    return metrics.elidedText(text, QtCore.Qt.ElideMiddle, TITLE_MAX_WIDTH)


# The narrowest a number field gets (px): the Combo View is 264 px wide by default, and a spin
# box would otherwise ask for the width of its range's longest number (-1000000000.000000).
FIELD_MIN_WIDTH = 64


def narrow(field):
    """A field that fits the Combo View: as narrow as FIELD_MIN_WIDTH, as wide as the row
    allows."""
    from PySide import QtGui
    field.setMinimumWidth(FIELD_MIN_WIDTH)
    field.setSizePolicy(QtGui.QSizePolicy.Ignored, QtGui.QSizePolicy.Fixed)
    return field


def report(title, message, error=True):
    """A message on the console and, in the GUI, in a dialog the user has to acknowledge."""
    (FreeCAD.Console.PrintError if error else FreeCAD.Console.PrintMessage)(message + "\n")
    from PySide import QtGui
    box = QtGui.QMessageBox.warning if error else QtGui.QMessageBox.information
    box(FreeCADGui.getMainWindow(), title, message)


def report_if_failed(title, obj):
    """After a command's recompute: a feature it made or changed that failed, or that waits
    for a failed input, gets a dialog saying why (the report view has FreeCAD's line for a
    failure; a wait is printed there too). Returns whether it did."""
    why = FRepErrors.why_failed(obj)
    if why is None:
        return False
    if "Invalid" not in obj.State:
        FreeCAD.Console.PrintError(why + "\n")
    from PySide import QtGui
    QtGui.QMessageBox.warning(FreeCADGui.getMainWindow(), title, why)
    return True


def add_to_active_container(obj):
    """A new object goes into the active App::Part, as the Part workbench's own commands put
    theirs (Part's CommandShapes); with none active it stays at the document's top level."""
    try:
        part = FreeCADGui.ActiveDocument.ActiveView.getActiveObject("part")
    except Exception:  # no 3D view (a macro, a test without one)
        part = None
    if part is not None and part.Document == obj.Document and obj not in part.Group:
        part.addObject(obj)


class Transaction:
    """One undo step; aborted (the document left as it was) when the body raises."""

    def __init__(self, doc, title):
        self.doc, self.title = doc, title

    def __enter__(self):
        self.doc.openTransaction(self.title)
        return self

    def __exit__(self, kind, value, trace):
        if kind is None:
            self.doc.commitTransaction()
        else:
            self.doc.abortTransaction()
        return False
