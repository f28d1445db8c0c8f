"""Blend guides in the 3D view: while a blend (Blend union, Blend intersection, Bounded blend)
is selected, the region where it acts is drawn see-through over it (where its added term
exceeds a tenth of its strength), with a handle for each reach (A1, A2) on the curve where its
inputs meet. Dragging a handle along its line sets that reach: one undo step. The object
computes the guide (obj.Proxy.blend_guide); this module only draws it and reports drags."""

import FreeCAD
import FreeCADGui

from FRepGuiHelpers import Transaction

GUIDE_COLOUR = (0.2, 0.55, 0.95)
HANDLE_COLOURS = {"A1": (0.9, 0.35, 0.1), "A2": (0.1, 0.6, 0.2)}

_guides = {}  # (document, object name) -> Guide
_observer = None


def _blend(doc_name, obj_name):
    doc = FreeCAD.getDocument(doc_name) if doc_name in FreeCAD.listDocuments() else None
    obj = doc.getObject(obj_name) if doc else None
    proxy = getattr(obj, "Proxy", None)
    if obj is None or not hasattr(proxy, "blend_guide") or obj.ViewObject is None:
        return None
    return obj if getattr(proxy, "FREP_TYPE", "") in ("blend_union", "blend_intersection",
                                                      "bounded_blend") else None


class Guide:
    """The guide of one blend: a see-through region and two line draggers, in the 3D view's
    scene beside the blend (not under it: the blend's selection highlight would paint the
    guide too, and a click on a handle would select the blend), moved by its Placement."""

    def __init__(self, obj):
        self.obj = obj
        self.root = None
        self.scene = None
        self.pending = False
        self.handles = {}  # name -> (dragger, start point, direction, size, lift)
        self.build()

    def build(self):
        from pivy import coin
        self.remove()
        obj = self.obj
        try:
            data = obj.Proxy.blend_guide(obj)
        except Exception as e:  # a failed input: say so once, draw nothing
            FreeCAD.Console.PrintWarning("%s: no blend guide: %s\n" % (obj.Label, e))
            return
        self.root = coin.SoSeparator()
        self.root.setName("FRepBlendGuide")
        place = coin.SoTransform()
        p = obj.Placement
        place.translation.setValue(p.Base.x, p.Base.y, p.Base.z)
        q = p.Rotation.Q
        place.rotation.setValue(q[0], q[1], q[2], q[3])
        self.root.addChild(place)
        mesh = data["mesh"]
        if mesh is not None and mesh.triangle_count:
            region = coin.SoSeparator()
            material = coin.SoMaterial()
            material.diffuseColor = GUIDE_COLOUR
            material.transparency = 0.45
            hints = coin.SoShapeHints()
            hints.vertexOrdering = coin.SoShapeHints.COUNTERCLOCKWISE
            coords = coin.SoCoordinate3()
            points = [tuple(p) for p in mesh.points]
            coords.point.setValues(0, len(points), points)
            faces = coin.SoIndexedFaceSet()
            index = []
            for a, b, c in mesh.triangles:
                index.extend((a, b, c, -1))
            faces.coordIndex.setValues(0, len(index), index)
            pick = coin.SoPickStyle()
            pick.style = coin.SoPickStyle.UNPICKABLE  # clicks go to the blend, not its guide
            for n in (pick, material, hints, coords, faces):
                region.addChild(n)
            self.root.addChild(region)
        size = self._handle_size(mesh)
        for name, point, direction, lift in data["handles"]:
            self._add_handle(name, point, direction, lift, size)
        try:
            self.scene = FreeCADGui.getDocument(obj.Document.Name).ActiveView.getSceneGraph()
        except Exception:  # no 3D view
            self.root, self.scene = None, None
            return
        self.scene.addChild(self.root)

    def _handle_size(self, mesh):
        box = self.obj.Mesh.BoundBox if self.obj.Mesh.CountPoints else None
        length = box.DiagonalLength if box is not None else 10.0
        return max(length, 1e-6) / 15

    def _add_handle(self, name, point, direction, lift, size):
        from pivy import coin
        sep = coin.SoSeparator()
        place = coin.SoTransform()
        shown = point + lift
        place.translation.setValue(shown.x, shown.y, shown.z)
        # a Translate1Dragger moves along its x axis: turn x onto the handle's direction
        turn = FreeCAD.Rotation(FreeCAD.Vector(1, 0, 0), direction).Q
        place.rotation.setValue(turn[0], turn[1], turn[2], turn[3])
        place.scaleFactor.setValue(size, size, size)
        material = coin.SoMaterial()
        material.diffuseColor = HANDLE_COLOURS.get(name, (0.8, 0.8, 0.1))
        dragger = coin.SoTranslate1Dragger()
        for n in (place, material, dragger):
            sep.addChild(n)
        dragger.addFinishCallback(lambda _d, dr, name=name: self.dropped(name))
        self.root.addChild(sep)
        self.handles[name] = (dragger, point, direction, size, lift)

    def handle_point(self, name):
        """Where a handle's reach is now (its start plus its drag, on the surface: the handle
        is drawn lifted off it), for the GUI test and scripts."""
        dragger, point, direction, size, _ = self.handles[name]
        return point + direction * (dragger.translation.getValue()[0] * size)

    def dropped(self, name):
        """A handle let go: its reach is set from where it lies, as one undo step."""
        obj = self.obj
        try:
            with Transaction(obj.Document, "Drag %s of %s" % (name, obj.Label)):
                value = obj.Proxy.set_blend_reach(obj, name, self.handle_point(name))
                obj.Document.recompute()
            FreeCAD.Console.PrintMessage("%s: %s = %.4g\n" % (obj.Label, name, value))
        except Exception as e:
            FreeCAD.Console.PrintError("%s: %s\n" % (obj.Label, e))
        self.schedule()  # (the recompute's refresh comes to the same one build)

    def schedule(self):
        """One build once the event in hand is done: a dragger's callback must not remove the
        dragger it runs in, and a drop and the recompute it causes ask for the same build."""
        if not self.pending:
            from PySide import QtCore
            self.pending = True
            QtCore.QTimer.singleShot(0, self._build_pending)

    def _build_pending(self):
        self.pending = False
        try:
            shown = _guides.get((self.obj.Document.Name, self.obj.Name)) is self
        except Exception:  # the object or its document is gone
            shown = False
        if shown:  # (not hidden in the meantime)
            self.build()

    def remove(self):
        if self.root is not None and self.scene is not None:
            self.scene.removeChild(self.root)
        self.root, self.scene = None, None
        self.handles = {}


def show(obj):
    key = (obj.Document.Name, obj.Name)
    if key in _guides:
        _guides[key].build()
    else:
        _guides[key] = Guide(obj)
    return _guides[key]


def hide(key=None):
    for k in ([key] if key else list(_guides)):
        guide = _guides.pop(k, None)
        if guide is not None:
            try:
                guide.remove()
            except Exception:  # the object or its document is gone
                pass


def guide_of(obj):
    return _guides.get((obj.Document.Name, obj.Name))


class SelectionObserver:
    def addSelection(self, doc, obj, sub, pos):
        blend = _blend(doc, obj)
        if blend is not None:
            show(blend)

    def removeSelection(self, doc, obj, sub):
        hide((doc, obj))

    def setSelection(self, doc):
        hide()
        for o in FreeCADGui.Selection.getSelection():
            if _blend(o.Document.Name, o.Name) is not None:
                show(o)

    def clearSelection(self, doc):
        hide()


def refresh(obj):
    """After a recompute of a blend whose guide is up: the guide follows the new values."""
    guide = guide_of(obj)
    if guide is not None:
        guide.schedule()


def install():
    """Starts watching the selection (once)."""
    global _observer
    if _observer is None:
        _observer = SelectionObserver()
        FreeCADGui.Selection.addObserver(_observer)
