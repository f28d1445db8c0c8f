"""The HSpline feature's view provider: the exact surface as Part draws it, with the CVs of one
level over it (ShowLevel; -1 the finest), movable CVs green, fixed ones grey, tagged ones red,
and their control net. Edit mode (double-click) opens the HSpline panel, puts a dragger on
every tagged CV that may move (each drag one undo step) and tags a CV on Ctrl+click, refusing
fixed ones with the reason. A view provider asks its object: it never imports the feature
module."""

import FreeCAD

import FRepPaths
from FRepDraggers import DraggerHost
from FRepProxy import StatelessProxy

MOVABLE = (0.1, 0.6, 0.2)
FIXED = (0.55, 0.55, 0.55)
TAGGED = (0.9, 0.1, 0.1)


def shown_level(vobj, h):
    level = vobj.ShowLevel
    return h.level_count - 1 if level < 0 or level >= h.level_count else level


class ViewProviderHSpline(DraggerHost, StatelessProxy):
    def __init__(self, vobj):
        vobj.Proxy = self
        self.setup(vobj)
        vobj.ShapeColor = (0.8, 0.7, 0.45)

    def setup(self, vobj):
        have = vobj.PropertiesList
        if "ShowLevel" not in have:
            vobj.addProperty("App::PropertyInteger", "ShowLevel", "HSpline",
                             "The level whose CVs are drawn; -1: the finest.")
            vobj.ShowLevel = -1
        if "SurfaceLevel" not in have:
            vobj.addProperty("App::PropertyInteger", "SurfaceLevel", "HSpline",
                             "Draw the surface at this level of detail (the levels up to it); "
                             "-1: all levels, the exact surface. The Shape is always exact.")
            vobj.SurfaceLevel = -1
        if "ShowCvs" not in have:
            vobj.addProperty("App::PropertyBool", "ShowCvs", "HSpline",
                             "Draw the CVs of ShowLevel and their control net.")
            vobj.ShowCvs = True

    def attach(self, vobj):
        from pivy import coin
        self.Object = vobj.Object
        self.setup(vobj)
        self.overlay = coin.SoSeparator()
        self.overlay.setName("HSplineCvs")
        vobj.RootNode.addChild(self.overlay)
        self.edit_root = None
        self.draggers = []
        self.callback = None
        self.panel = None  # the edit panel while open (it shows the tag count)
        self.preview = None
        self.detail = None

    def getIcon(self):
        return FRepPaths.icon("hspline")

    # Every edit ends in a recompute that assigns the Shape (an undo restores it too), so the
    # Shape stands for the data properties: one rebuild per edit, not one per property. A tag
    # changes only the overlay's colours and the draggers, not the surface drawn.
    def updateData(self, obj, prop):
        if prop == "Shape":
            self.rebuild()
        elif prop == "Tagged":
            self.rebuild(surface=False)
        if prop in ("Tagged", "Shape") and self.panel is not None:
            self.panel.describe()  # (its counts: a Ctrl+click tags without the panel)

    def onChanged(self, vobj, prop):
        if prop in ("ShowLevel", "ShowCvs"):
            self.rebuild(surface=False)
        elif prop in ("Visibility", "SurfaceLevel"):
            self.rebuild()

    # -- the CV overlay -------------------------------------------------------------------------
    def overlay_data(self):
        """(level, cvs, positions, colours, net index pairs) of the drawn level."""
        obj = self.Object
        h = obj.Proxy.hspline(obj)
        level = shown_level(obj.ViewObject, h)
        cvs = h.cvs(level)
        positions = h.positions(level)
        tagged = set(_tags(obj))
        colours = [TAGGED if c in tagged else MOVABLE if h.movable(*c) else FIXED for c in cvs]
        index = {c[1:]: k for k, c in enumerate(cvs)}
        nu, nv = h.grid_size(level)
        pu, pv = h.periodic
        net = []
        for (i, j), k in index.items():
            for di, dj in ((1, 0), (0, 1)):
                a, b = i + di, j + dj
                if pu:
                    a %= nu
                if pv:
                    b %= nv
                if (a, b) in index:
                    net.append((k, index[(a, b)]))
        return level, cvs, positions, colours, net

    def rebuild(self, surface=True):
        """The CV overlay (and the draggers in edit mode) again; with `surface`, the level of
        detail drawn too."""
        from pivy import coin
        overlay = getattr(self, "overlay", None)
        if overlay is None:
            return
        overlay.removeAllChildren()
        if surface:
            self.update_detail()
        obj = self.Object
        vobj = obj.ViewObject
        if not vobj.ShowCvs or not vobj.Visibility:
            return
        try:
            _, _, positions, colours, net = self.overlay_data()
        except (ValueError, RuntimeError, AttributeError):
            return  # a broken hierarchy shows the feature's error, not a half overlay
        pick = coin.SoPickStyle()
        pick.style = coin.SoPickStyle.UNPICKABLE
        overlay.addChild(pick)
        coords = coin.SoCoordinate3()
        coords.point.setValues(0, len(positions), [list(p) for p in positions])
        overlay.addChild(coords)
        lines = coin.SoSeparator()
        colour = coin.SoBaseColor()
        colour.rgb = (0.35, 0.35, 0.45)
        style = coin.SoDrawStyle()
        style.lineWidth = 1
        index = []
        for a, b in net:
            index.extend((a, b, -1))
        line_set = coin.SoIndexedLineSet()
        line_set.coordIndex.setValues(0, len(index), index)
        for n in (colour, style, line_set):
            lines.addChild(n)
        overlay.addChild(lines)
        points = coin.SoSeparator()
        binding = coin.SoMaterialBinding()
        binding.value = coin.SoMaterialBinding.PER_VERTEX
        material = coin.SoMaterial()
        material.diffuseColor.setValues(0, len(colours), [list(c) for c in colours])
        dots = coin.SoDrawStyle()
        dots.pointSize = 7
        point_set = coin.SoPointSet()
        point_set.numPoints = len(positions)
        for n in (binding, material, dots, point_set):
            points.addChild(n)
        overlay.addChild(points)
        if self.edit_root is not None:
            self.build_draggers(vobj)

    # -- edit mode ----------------------------------------------------------------------------
    def setEdit(self, vobj, mode=0):
        if mode != 0:
            return None
        import FreeCADGui
        import FRepHSplinePanel
        self.build_draggers(vobj)
        self.remove_callback()  # (one callback, however often edit mode is entered)
        try:
            view = FreeCADGui.ActiveDocument.ActiveView
            self.callback = (view, view.addEventCallback("SoMouseButtonEvent", self.clicked))
        except Exception:  # no 3D view
            self.callback = None
        self.panel = FRepHSplinePanel.HSplinePanel(vobj.Object)
        FreeCADGui.Control.showDialog(self.panel)
        return True

    def remove_callback(self):
        if getattr(self, "callback", None) is not None:
            view, cb = self.callback
            try:
                view.removeEventCallback("SoMouseButtonEvent", cb)
            except Exception:  # the view is gone
                pass
        self.callback = None

    def unsetEdit(self, vobj, mode=0):
        if mode != 0:
            return None
        import FreeCADGui
        self.remove_draggers(vobj)
        self.remove_callback()
        self.panel = None
        FreeCADGui.Control.closeDialog()
        return True

    def dragger_size(self):
        b = self.Object.Shape.BoundBox
        return max(b.DiagonalLength, 1e-6) / 60

    def build_draggers(self, vobj):
        obj = vobj.Object
        h = obj.Proxy.hspline(obj)
        size = self.dragger_size()
        self.begin_draggers(vobj)
        for cv in _tags(obj):
            if h.has_cv(*cv) and h.movable(*cv):
                self.add_dragger(cv, h.position(*cv), size)
        vobj.RootNode.addChild(self.edit_root)

    def drag_started(self, cv):
        self.Object.Document.openTransaction("Move hspline CV (%d, %d, %d)" % cv)
        self.start_preview()

    # While a CV is dragged the document does not change: the view shows a preview, the same
    # vertices of our own tessellation moved (Part's tessellation of a large B-spline face takes
    # far longer than a frame). The release makes the one document change.
    def stand_in(self, level=-1):
        """A Coin mesh of our own tessellation of the levels up to `level` put in place of
        Part's drawing of the surface (its display-mode switch set aside): a drag's preview,
        or a level of detail. Returns (root, (coords, normals), us, vs, switch state to
        restore)."""
        from pivy import coin
        obj = self.Object
        h = obj.Proxy.hspline(obj)
        b = obj.Shape.BoundBox
        t = h.tessellation(max(b.DiagonalLength, 1e-6) * 2e-4, level)
        root = coin.SoSeparator()
        colour = coin.SoMaterial()
        colour.diffuseColor = (0.95, 0.75, 0.35)
        hints = coin.SoShapeHints()
        hints.vertexOrdering = coin.SoShapeHints.COUNTERCLOCKWISE
        hints.shapeType = coin.SoShapeHints.UNKNOWN_SHAPE_TYPE
        points, unit = t["points"], t["normals"]
        coords = coin.SoCoordinate3()
        coords.point.setValues(0, len(points), points)
        # Normals from the surface itself, so Coin need not compute them every frame.
        normals = coin.SoNormal()
        normals.vector.setValues(0, len(unit), unit)
        binding = coin.SoNormalBinding()
        binding.value = coin.SoNormalBinding.PER_VERTEX_INDEXED
        faces = coin.SoIndexedFaceSet()
        index = []
        for a, b_, c in t["mesh"].triangles:
            index.extend((a, b_, c, -1))
        faces.coordIndex.setValues(0, len(index), index)
        for n in (colour, hints, coords, normals, binding, faces):
            root.addChild(n)
        obj.ViewObject.RootNode.addChild(root)
        switch = getattr(obj.ViewObject, "SwitchNode", None)
        shown = switch.whichChild.getValue() if switch is not None else None
        if switch is not None:
            switch.whichChild = -1
        return root, (coords, normals), t["us"], t["vs"], shown

    def remove_stand_in(self, stand_in):
        root, _, _, _, shown = stand_in
        vobj = self.Object.ViewObject
        vobj.RootNode.removeChild(root)
        switch = getattr(vobj, "SwitchNode", None)
        if switch is not None and shown is not None:
            switch.whichChild = shown

    # A level of detail (view property SurfaceLevel): the surface of the levels up to it
    # drawn in place of the exact one, which the feature's Shape stays.
    def update_detail(self):
        if getattr(self, "detail", None) is not None:
            self.remove_stand_in(self.detail)
            self.detail = None
        vobj = self.Object.ViewObject
        if self.preview is not None or not vobj.Visibility:
            return
        try:
            levels = self.Object.Proxy.hspline(self.Object).level_count
        except (ValueError, RuntimeError, AttributeError):  # not (yet) a whole hierarchy
            return
        if 0 <= vobj.SurfaceLevel < levels - 1:
            self.detail = self.stand_in(vobj.SurfaceLevel)

    def start_preview(self):
        self.stop_preview()
        if getattr(self, "detail", None) is not None:
            self.remove_stand_in(self.detail)
            self.detail = None
        self.preview = self.stand_in()
        self.preview_runs = {}  # per CV: the grid runs a drag of it can move

    def drag_moved(self, cv, dragger, size):
        """One preview frame: the CV moved in a copy of the hierarchy, the preview's
        vertices put where the new surface has them."""
        if self.preview is None:
            return
        obj = self.Object
        root, (coords, normals), us, vs, _ = self.preview
        t = dragger.translation.getValue()
        h = obj.Proxy.hspline(obj).copy()
        p = FreeCAD.Vector(*h.position(*cv)) + FreeCAD.Vector(t[0], t[1], t[2]) * size
        try:
            h.move_cv(cv[0], cv[1], cv[2], tuple(p))
        except ValueError:
            return
        if cv not in self.preview_runs:
            self.preview_runs[cv] = h.reach_runs(us, vs, *cv)
        runs = self.preview_runs[cv]
        for (start, _), (points, unit) in zip(runs, h.points_in_runs(us, vs, runs)):
            coords.point.setValues(start, len(points), points)
            normals.vector.setValues(start, len(unit), unit)

    def stop_preview(self):
        if self.preview is not None:
            self.remove_stand_in(self.preview)
            self.preview = None

    def drag_finished(self, cv, dragger, size):
        self.stop_preview()
        DraggerHost.drag_finished(self, cv, dragger, size)

    def apply_drag(self, cv, delta):
        self.Object.Proxy.nudge(self.Object, [cv], tuple(delta))

    def pick(self, view, position):
        """The drawn CV nearest the view ray through a screen position, within a few
        dragger sizes, or None."""
        level, cvs, positions, _, _ = self.overlay_data()
        origin = view.getPoint(*position)
        direction = view.getViewDirection()
        best, best_distance = None, 3 * self.dragger_size()
        for cv, p in zip(cvs, positions):
            d = FreeCAD.Vector(*p) - origin
            off = (d - direction * d.dot(direction)).Length
            if off < best_distance:
                best, best_distance = cv, off
        return best

    def clicked(self, event):
        if event.get("State") != "DOWN" or event.get("Button") != "BUTTON1" or \
                not event.get("CtrlDown"):
            return
        import FreeCADGui
        view = FreeCADGui.ActiveDocument.ActiveView
        cv = self.pick(view, event["Position"])
        if cv is not None:
            self.toggle_tag(cv)

    def toggle_tag(self, cv):
        """Tags or untags a CV (one undo step); a fixed CV is refused, the reason on the
        status bar and the console."""
        obj = self.Object
        doc = obj.Document
        doc.openTransaction("Tag hspline CV")
        try:
            obj.Proxy.toggle_tag(obj, cv)
            doc.commitTransaction()
        except ValueError as e:
            doc.abortTransaction()
            FreeCAD.Console.PrintWarning("%s\n" % e)
            if FreeCAD.GuiUp:
                import FreeCADGui
                FreeCADGui.getMainWindow().statusBar().showMessage(str(e), 8000)
            return False
        return True


def _tags(obj):
    t = list(obj.Tagged)
    return [tuple(t[k:k + 3]) for k in range(0, len(t) - len(t) % 3, 3)]


class ViewProviderEnvelope(ViewProviderHSpline):
    """An Envelope draws as an hspline (its CVs follow the segments, so edit mode is its Base's:
    double-click opens the Base's edit panel) and holds its Base and segments in the tree."""

    def getIcon(self):
        return FRepPaths.icon("hspline_envelope")

    def claimChildren(self):
        obj = self.Object
        return ([obj.Base] if obj.Base is not None else []) + list(obj.Segments)

    def setupContextMenu(self, vobj, menu):
        """Set rest pose: bind the segments where they are now (one undo step)."""
        from PySide import QtGui
        action = QtGui.QAction(QtGui.QIcon(FRepPaths.icon("hspline_envelope")), "Set rest pose",
                               menu)
        action.setToolTip("Bind the segments where they are now: the surface takes its Base's "
                          "shape in the current pose")
        action.triggered.connect(lambda: self.set_rest_pose(vobj.Object))
        menu.addAction(action)

    def set_rest_pose(self, obj):
        from FRepGuiHelpers import Transaction
        try:
            with Transaction(obj.Document, "Set rest pose of %s" % obj.Label):
                obj.Proxy.set_rest_pose(obj)
                obj.Document.recompute()
        except ValueError as e:
            FreeCAD.Console.PrintError("%s\n" % e)

    def setEdit(self, vobj, mode=0):
        if mode != 0:
            return None
        base = vobj.Object.Base
        if base is not None and base.ViewObject is not None:
            import FreeCADGui
            from PySide import QtCore
            gui_doc = FreeCADGui.getDocument(base.Document.Name)
            # after this edit request has been turned down, not inside it
            QtCore.QTimer.singleShot(0, lambda: gui_doc.setEdit(base.Name, 0))
        return False
