"""The hspline commands (FRep > HSpline): new hsplines from a plane, a cylinder, a torus or a
selected B-spline face; Refine, Zero Offsets and Unrefine on the tagged CVs; To Solid; import
and export of .hs files, and export as STEP or as a checked mesh; struts in a shell along one.
Each works inside one undo transaction and reports a refusal in a dialog with the reason."""

import FreeCAD
import FreeCADGui

import FRepPaths
from FRepGuiHelpers import (QT_TRANSLATE_NOOP, Transaction, add_to_active_container, report,
                             report_if_failed)


def _selected_hsplines():
    import FRepHSpline
    return [o for o in FreeCADGui.Selection.getSelection() if FRepHSpline.is_hspline(o)]


def _select(obj):
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(obj)


def _add_in_one_step(doc, title, make):
    """Runs make() in one undo transaction: it returns the new feature (or the feature and
    more), which goes into the active container, is recomputed and selected. A refusal goes to
    a dialog and None is returned; otherwise make()'s result."""
    try:
        with Transaction(doc, title):
            result = make()
            obj = result[0] if isinstance(result, tuple) else result
            add_to_active_container(obj)
            doc.recompute()
    except ValueError as e:
        report("FRep hspline", str(e))
        return None
    _select(obj)
    return result


class NewHSplineCommand:
    SHAPES = {
        "plane": ("New hspline plane", "An hspline from a plane of 8 x 8 CVs, 100 mm square."),
        "cylinder": ("New hspline cylinder",
                     "An hspline cylinder (periodic around): 8 x 8 CVs, radius 20 mm, 60 mm high."),
        "torus": ("New hspline torus", "A closed hspline torus (a solid): 10 x 8 CVs, radii 30 "
                                       "and 10 mm."),
    }

    def __init__(self, shape):
        self.shape = shape

    def GetResources(self):
        text, tip = self.SHAPES[self.shape]
        return {"Pixmap": FRepPaths.icon("hspline_" + self.shape), "MenuText": text,
                "ToolTip": tip}

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None

    def Activated(self):
        import FRepHSpline
        doc = FreeCAD.ActiveDocument
        make = {"plane": FRepHSpline.make_plane, "cylinder": FRepHSpline.make_cylinder,
                "torus": FRepHSpline.make_torus}[self.shape]
        with Transaction(doc, "Create hspline"):
            obj = make(doc)
            add_to_active_container(obj)
            doc.recompute()
        _select(obj)


class FromFaceCommand:
    def GetResources(self):
        return {"Pixmap": FRepPaths.icon("hspline_from_face"),
                "MenuText": QT_TRANSLATE_NOOP("FRep_HSplineFromFace", "Hspline from face"),
                "ToolTip": QT_TRANSLATE_NOOP(
                    "FRep_HSplineFromFace",
                    "An hspline whose level 0 is the selected face's B-spline surface, exactly "
                    "(untrimmed; degree raised to 3 where lower).")}

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None and bool(FreeCADGui.Selection.getSelectionEx())

    def Activated(self):
        import FRepHSpline
        doc = FreeCAD.ActiveDocument
        faces = [(s.Object, f) for s in FreeCADGui.Selection.getSelectionEx()
                 for f in (s.SubObjects or getattr(s.Object.Shape, "Faces", [])[:1])
                 if f.ShapeType == "Face"]
        if not faces:
            report("FRep hspline", "Hspline from face needs a face selected (a B-spline face: "
                   "Part > Convert to NURBS makes one of most faces)")
            return
        source, face = faces[0]
        _add_in_one_step(doc, "Hspline from face", lambda: FRepHSpline.make_from_face(
            doc, face, label="%s's face" % source.Label))


class EditCommand:
    """Refine, Zero Offsets, Unrefine, To Solid on the selected hsplines."""
    ACTIONS = {
        "refine": ("hspline_refine", "Refine",
                   "Adds a finer level around the tagged CVs (7 x 7 new CVs about each, with zero "
                   "offsets: the surface does not change). Tag CVs in edit mode first."),
        "zero": ("hspline_zero", "Zero offsets",
                 "Puts the tagged CVs of refined levels back on their parent surface."),
        "unrefine": ("hspline_unrefine", "Unrefine",
                     "Removes the CVs with zero offset that no detail needs, and empty levels; "
                     "the surface does not change."),
        "solid": ("hspline_solid", "To solid",
                  "Makes the selected closed hspline (periodic both ways, like a torus) a solid."),
    }

    def __init__(self, action):
        self.action = action

    def GetResources(self):
        icon, text, tip = self.ACTIONS[self.action]
        return {"Pixmap": FRepPaths.icon(icon), "MenuText": text, "ToolTip": tip}

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None and bool(_selected_hsplines())

    def Activated(self):
        import FRepHSpline as H
        doc = FreeCAD.ActiveDocument
        run = {"refine": H.refine, "zero": H.zero_offsets, "unrefine": H.unrefine,
               "solid": H.set_make_solid}[self.action]
        for obj in _selected_hsplines():
            try:
                with Transaction(doc, "%s %s" % (self.ACTIONS[self.action][1], obj.Label)):
                    result = run(obj)
                    doc.recompute()
            except ValueError as e:
                report("FRep hspline", str(e))
                continue
            if self.action == "unrefine":
                FreeCAD.Console.PrintMessage("%s: unrefine removed %d CVs\n" % (obj.Label, result))


class AttachCommand:
    def GetResources(self):
        return {"Pixmap": FRepPaths.icon("hspline_attach"),
                "MenuText": QT_TRANSLATE_NOOP("FRep_HSplineAttach", "Attach cylinder"),
                "ToolTip": QT_TRANSLATE_NOOP(
                    "FRep_HSplineAttach",
                    "Stands a cylinder on the selected hspline, joined through a Catmull-Clark "
                    "seam around a rectangle of its level-0 CVs (the tagged ones, or one at its "
                    "middle); a second selected hspline cylinder is used instead of a new one. "
                    "The panel sets the rectangle, the height and the seam's subdivisions.")}

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None and 1 <= len(_selected_hsplines()) <= 2

    def Activated(self):
        from PySide import QtCore
        doc, chosen = FreeCAD.ActiveDocument, _selected_hsplines()
        # After the command has returned: FreeCAD closes a transaction still open when a
        # command ends, and this one must stay open until the panel's OK or Cancel.
        QtCore.QTimer.singleShot(0, lambda: self.attach(doc, chosen))

    def attach(self, doc, chosen):
        import FRepHSplineAttach as A
        parent = chosen[0]
        doc.openTransaction("Attach to %s" % parent.Label)
        try:
            # the rectangle the tagged CVs of the level shown in the view span
            shown = parent.ViewObject.ShowLevel if parent.ViewObject else 0
            level, rect = A.default_placement(parent, shown)
            if len(chosen) == 2:
                joint = A.make_attachment(doc, parent, chosen[1], rect)
                joint.SeamLevel = level
            else:
                _, joint = A.attach_new_cylinder(doc, parent, rect,
                                                 height=A.default_height(parent), level=level)
            add_to_active_container(joint)
            doc.recompute()
        except ValueError as e:
            doc.abortTransaction()
            report("FRep hspline", str(e))
            return
        _select(joint)
        import FRepHSplineAttachPanel
        # (the panel, not edit mode: FreeCAD's setEdit commits the open transaction, and OK
        # or Cancel must decide about the new objects too)
        FreeCADGui.Control.showDialog(FRepHSplineAttachPanel.AttachPanel(joint, True))


class EnvelopeCommand:
    def GetResources(self):
        return {"Pixmap": FRepPaths.icon("hspline_envelope"),
                "MenuText": QT_TRANSLATE_NOOP("FRep_HSplineEnvelope", "Envelope"),
                "ToolTip": QT_TRANSLATE_NOOP(
                    "FRep_HSplineEnvelope",
                    "Binds the selected hspline's CVs to skeleton segments (the selected lines "
                    "or coordinate systems, in order; none: two lines along its longest side, "
                    "jointed at the middle). Move a segment to bend the surface; the joint stays "
                    "round (level 0 refined there, its level 1 blending the two frames).")}

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None and len(_selected_hsplines()) == 1

    def Activated(self):
        import FRepHSplineEnvelope as E
        doc = FreeCAD.ActiveDocument
        base = _selected_hsplines()[0]
        segments = [o for o in FreeCADGui.Selection.getSelection() if o != base]
        try:
            with Transaction(doc, "Envelope %s" % base.Label):
                if not segments:
                    segments = E.make_skeleton(doc, base)
                obj = E.make_envelope(doc, base, segments)
                add_to_active_container(obj)
                doc.recompute()
        except ValueError as e:
            report("FRep hspline", str(e))
            return
        report_if_failed("FRep hspline", obj)
        _select(obj)


class ImportCommand:
    def GetResources(self):
        return {"Pixmap": FRepPaths.icon("hspline_import"), "MenuText": "Import .hs...",
                "ToolTip": "Reads an hspline file (.hs, docs/file-formats.md) into a new HSpline."}

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None

    def Activated(self):
        from PySide import QtGui
        import FRepHSpline
        path, _ = QtGui.QFileDialog.getOpenFileName(FreeCADGui.getMainWindow(), "Import hspline",
                                                    "", "Hspline (*.hs)")
        if not path:
            return
        doc = FreeCAD.ActiveDocument
        try:
            with Transaction(doc, "Import hspline"):
                obj = FRepHSpline.import_hs(doc, path)
                add_to_active_container(obj)
                doc.recompute()
        except (ValueError, OSError) as e:
            report("FRep hspline", str(e))
            return
        _select(obj)


class ExportCommand:
    FILTERS = ("Hspline (*.hs);;Hspline, unrefined (*.hs);;STEP (*.step *.stp);;"
               "STL mesh, checked (*.stl)")

    def GetResources(self):
        return {"Pixmap": FRepPaths.icon("hspline_export"), "MenuText": "Export hspline...",
                "ToolTip": "Writes the selected hspline as .hs (optionally unrefined), as STEP "
                           "(a solid when closed) or as an STL mesh checked printable."}

    def IsActive(self):
        return len(_selected_hsplines()) == 1

    def Activated(self):
        import os
        from PySide import QtGui
        import FRepHSpline
        obj = _selected_hsplines()[0]
        path, chosen = QtGui.QFileDialog.getSaveFileName(
            FreeCADGui.getMainWindow(), "Export hspline", obj.Label + ".hs", self.FILTERS)
        if not path:
            return
        ext = os.path.splitext(path)[1].lower()
        try:
            if ext == ".hs":
                FRepHSpline.export_hs(obj, path, optimised="unrefined" in chosen)
            elif ext in (".step", ".stp"):
                FRepHSpline.export_step(obj, path)
            elif ext == ".stl":
                FRepHSpline.export_mesh(obj, path, tolerance=0.01)
            else:
                raise ValueError("%s: export as .hs, .step or .stl, not '%s'" % (obj.Label, ext))
        except (ValueError, OSError) as e:
            report("FRep hspline", str(e))
            return
        FreeCADGui.getMainWindow().statusBar().showMessage("Wrote %s" % path, 10000)


class StrutsCommand:
    def GetResources(self):
        return {"Pixmap": FRepPaths.icon("hspline_struts"), "MenuText": "Struts along hspline...",
                "ToolTip": "Fills a shell along the selected hspline with a strut lattice whose "
                           "cells follow the surface's parameters (octet cells of half the "
                           "thickness; edit the lattice's cell type, cell and radius after)."}

    def IsActive(self):
        return len(_selected_hsplines()) == 1

    def Activated(self):
        from PySide import QtGui
        import FRepHSplineStruts
        obj = _selected_hsplines()[0]
        doc = obj.Document
        try:
            default = FRepHSplineStruts.default_shell_thickness(obj)
        except ValueError as e:
            report("FRep hspline", str(e))
            return
        thickness, ok = QtGui.QInputDialog.getDouble(
            FreeCADGui.getMainWindow(), "Struts along hspline",
            "Shell thickness (mm) along %s:" % obj.Label, default, 0.001, 1e6, 3)
        if not ok:
            return
        made = _add_in_one_step(doc, "Struts along %s" % obj.Label,
                                lambda: FRepHSplineStruts.struts_along(obj, thickness))
        if made is None:
            return
        top, result = made
        FreeCAD.Console.PrintMessage(
            "%s: the FFD lattice of %d x %d divisions follows %s within %.3g mm\n" % (
                top.Label, result["divisions"][0], result["divisions"][1], obj.Label,
                result["deviation"]))


def commands():
    """The hspline commands by name (FRepCommands registers them)."""
    made = {"FRep_HSpline" + shape.capitalize(): NewHSplineCommand(shape)
            for shape in ("plane", "cylinder", "torus")}
    made["FRep_HSplineFromFace"] = FromFaceCommand()
    for action, name in (("refine", "Refine"), ("zero", "ZeroOffsets"), ("unrefine", "Unrefine"),
                         ("solid", "ToSolid")):
        made["FRep_HSpline" + name] = EditCommand(action)
    made["FRep_HSplineAttach"] = AttachCommand()
    made["FRep_HSplineEnvelope"] = EnvelopeCommand()
    made["FRep_HSplineImport"] = ImportCommand()
    made["FRep_HSplineExport"] = ExportCommand()
    made["FRep_HSplineStruts"] = StrutsCommand()
    return made
