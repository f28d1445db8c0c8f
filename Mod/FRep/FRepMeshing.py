"""Meshing for the workbench: document-wide preview settings, the automatic box, handing a
frepcore mesh to FreeCAD, and progress with cancel through FreeCAD's progress indicator.
"""

import os
import tempfile

import FreeCAD

from FRepPaths import frepcore

PREFERENCES = "User parameter:BaseApp/Preferences/Mod/FRep"
PREVIEW_KEY = "FRepPreviewCells"
DEFAULT_PREVIEW_CELLS = 48
DEFAULT_EXPORT_CELLS = frepcore.DEFAULT_CELLS  # the export pipeline's default (libcore)
MIN_CELLS, MAX_CELLS = 4, 4096


def preview_cells(doc):
    """Grid cells along the longest side of each preview: one setting per document."""
    value = doc.Meta.get(PREVIEW_KEY)
    if value is None:
        params = FreeCAD.ParamGet(PREFERENCES)
        return params.GetInt("PreviewCells", DEFAULT_PREVIEW_CELLS) or DEFAULT_PREVIEW_CELLS
    return int(value)


def set_preview_cells(doc, cells):
    """Sets the document's preview resolution and recomputes every FRep preview."""
    cells = int(cells)
    if not MIN_CELLS <= cells <= MAX_CELLS:
        raise ValueError("%s: preview cells %d is out of range; allowed: %d to %d"
                         % (doc.Label, cells, MIN_CELLS, MAX_CELLS))
    meta = dict(doc.Meta)
    meta[PREVIEW_KEY] = str(cells)
    doc.Meta = meta
    import FRepTree
    for obj in doc.Objects:
        if FRepTree.is_frep_feature(obj):
            obj.touch()
    doc.recompute()


def require_not_empty(label, bounds):
    if bounds["empty"]:
        raise ValueError("%s: the result is empty (no point is inside); check that the inputs "
                         "overlap and the operation is the intended one" % label)


def display_box(label, shape, cells, bounds):
    """Meshing box and cell size for a preview, from shape.bounds(). An unbounded solid is
    shown clipped (with a warning) rather than failing: half-spaces and complements are
    normal modelling steps."""
    b = bounds
    require_not_empty(label, b)
    if b["bounded"]:
        return frepcore.automatic_box(shape, cells=cells, bounds=b)
    lo, hi = [list(v) for v in b["box"]]
    finite = [abs(v) for v in lo + hi if abs(v) < 1e5]
    reach = max([10.0] + [2 * v for v in finite])
    for a in range(3):
        lo[a] = max(lo[a], -reach)
        hi[a] = min(hi[a], reach)
    FreeCAD.Console.PrintWarning(
        "%s: the solid is unbounded towards %s; the preview shows it clipped to +-%g mm. "
        "Intersect it with a bounded solid before exporting.\n"
        % (label, ", ".join(b["unbounded_sides"]), reach))
    if any(h <= l for l, h in zip(lo, hi)):
        raise ValueError("%s: the solid lies outside the preview box" % label)
    return frepcore.automatic_box(shape, cells=cells, bbox=(lo, hi))


def warn_thin_parts(label, thin):
    """Says in the report view where parts thinner than a cell passed between the grid's
    points with no surface near (frepcore's Mesh.thin_parts): the mesh is printable, but
    those parts are missing from it (solid) or closed in it (gaps). Crease tips cut short
    are not warned of: every crease off the grid has them. Where they were meshed again at
    half a cell (Refine), it says so instead, with the smaller cubes of deeper
    levels (RefineLevels)."""
    if thin and thin.get("refinement_skipped"):
        FreeCAD.Console.PrintWarning("%s: the thin parts were not refined: %s\n"
                                     % (label, thin["refinement_skipped"]))
    if thin and thin.get("refinement_deeper_skipped"):
        FreeCAD.Console.PrintWarning("%s: the thin parts were refined %d level(s) deep only: %s\n"
                                     % (label, thin.get("refined_levels", 1),
                                        thin["refinement_deeper_skipped"]))
    if thin and thin.get("refined_cubes"):
        deeper = ""
        if thin.get("refined_deeper_cubes"):
            deeper = (", and %d smaller cubes below that, down to a cell / %d"
                      % (thin["refined_deeper_cubes"], 2 ** thin["refined_levels"]))
        FreeCAD.Console.PrintMessage("%s: %d cubes round parts thinner than a cell meshed again "
                                     "at half a cell%s.\n"
                                     % (label, thin["refined_cubes"], deeper))
        return
    if not thin or not (thin["solid"] or thin["gaps"]):
        return
    parts = []
    if thin["solid"]:
        parts.append("solid thinner than a cell passes between the grid's points at %d grid "
                     "edges and is left out" % thin["solid"])
    if thin["gaps"]:
        parts.append("gaps narrower than a cell pass between the grid's points at %d grid "
                     "edges and are closed" % thin["gaps"])
    FreeCAD.Console.PrintWarning(
        "%s: %s, for example at (%.4g, %.4g, %.4g); more Cells or a smaller Resolution keep "
        "more of the model.\n" % ((label, "; ".join(parts)) + tuple(thin["example"])))


def report_straightened(label, straightened):
    """Says in the report view what straightening the creases did (frepcore's
    'straightened': vertices merged onto creases, edges flipped along them)."""
    if straightened:
        FreeCAD.Console.PrintMessage(
            "%s: creases straightened: %d vertices merged onto them, %d edges flipped along "
            "them.\n" % (label, straightened["merged"], straightened["flipped"]))


# A memory file system where there is one: the hand-over file lives for milliseconds, and
# frepcore syncs what it writes to disk (it is built for exports that must survive a crash).
_HAND_OVER_DIR = "/dev/shm" if os.access("/dev/shm", os.W_OK) else None


def to_freecad_mesh(mesh):
    """A frepcore mesh as a Mesh.Mesh, through FreeCAD's own binary mesh file: frepcore writes
    the facet neighbours too, so FreeCAD adopts the topology instead of rebuilding it (four
    times faster than a PLY, ten times faster than Python lists)."""
    import Mesh
    if mesh.triangle_count == 0:
        return Mesh.Mesh()
    fd, path = tempfile.mkstemp(prefix="frep-", suffix=".bms", dir=_HAND_OVER_DIR)
    os.close(fd)
    try:
        mesh.write(path, "bms")
        return Mesh.Mesh(path)
    finally:
        if os.path.exists(path):
            os.remove(path)


def set_mesh(obj, mesh):
    """Assigns a Mesh.Mesh to a Mesh feature keeping its Placement (Mesh::Feature would take
    the new mesh's identity transform as the object's placement)."""
    mesh.Placement = obj.Placement
    obj.Mesh = mesh


class Progress:
    """FreeCAD's progress indicator as a frepcore progress callback (no GUI: the console).
    progress(fraction) returns False once the user cancels."""

    STEPS = 100

    def __init__(self, text):
        self.indicator = FreeCAD.Base.ProgressIndicator()
        self.indicator.start(text, self.STEPS)
        self.done = 0
        self.cancelled = False

    def __call__(self, fraction):
        target = min(self.STEPS, int(fraction * self.STEPS))
        try:
            while self.done < target:
                self.indicator.next(True)  # True: the user may abort here
                self.done += 1
        except Exception:  # FreeCAD raises when the user pressed cancel
            self.cancelled = True
        return not self.cancelled

    def close(self):
        self.indicator.stop()


class GuiProgress:
    """A modal progress dialog with a Cancel button (Esc cancels too), shown when work lasts
    longer than SHOW_AFTER_MS.

    Why not FreeCAD's status-bar indicator: in FreeCAD 0.20 an indicator started inside a
    recompute (where Polygonize and every preview mesh) is nested in the recompute's own, and
    nested indicators are ignored: no progress, no cancel, and no event processing, so the
    window froze. The dialog is modal, so while it processes events (to draw itself and see the
    Cancel) the user cannot edit the document underneath."""

    STEPS = 1000
    SHOW_AFTER_MS = 800  # counted from the first report, which comes after 50 ms of work

    def __init__(self, text):
        self.text = text
        self.dialog = None  # made at the first report: quick work (most previews) has none
        self.cancelled = False

    def _make_dialog(self):
        import FreeCADGui
        from PySide import QtCore, QtGui
        self.QtCore = QtCore
        self.dialog = QtGui.QProgressDialog(self.text + "...", "Cancel", 0, self.STEPS,
                                            FreeCADGui.getMainWindow())
        self.dialog.setWindowTitle("FRep")
        self.dialog.setWindowModality(QtCore.Qt.ApplicationModal)
        self.dialog.setMinimumDuration(self.SHOW_AFTER_MS)
        self.dialog.setAutoClose(False)
        self.dialog.setAutoReset(False)
        self.dialog.setValue(0)

    def __call__(self, fraction):
        if self.dialog is None:
            self._make_dialog()
        self.dialog.setValue(min(self.STEPS, int(fraction * self.STEPS)))
        if self.dialog.isVisible():
            # setValue only processes events when the value changes; a slow stretch must
            # still see the Cancel button.
            self.QtCore.QCoreApplication.processEvents()
        self.cancelled = self.cancelled or self.dialog.wasCanceled()
        return not self.cancelled

    def close(self):
        if self.dialog is not None:
            self.dialog.close()
            self.dialog.deleteLater()


def default_progress(text):
    return GuiProgress(text) if FreeCAD.GuiUp else Progress(text)


# Tests (and scripts) can replace this to drive cancel without a GUI.
progress_factory = default_progress


def run_with_progress(text, work):
    """Runs work(progress) under a progress indicator; always stops the indicator."""
    progress = progress_factory(text)
    try:
        return work(progress)
    finally:
        progress.close()
