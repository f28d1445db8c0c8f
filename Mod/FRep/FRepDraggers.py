"""Point draggers for view providers in edit mode (the lattice's control points, an hspline's
tagged CVs): one Coin SoDragPointDragger per point, each drag one undo step. A host view
provider has edit_root and draggers, and defines drag_started(key) and apply_drag(key,
delta), and optionally drag_moved(key, dragger, size) for a live preview."""

import FreeCAD


class DraggerHost:
    def doubleClicked(self, vobj):
        """A double-click opens edit mode (setEdit puts the draggers up)."""
        import FreeCADGui
        FreeCADGui.ActiveDocument.setEdit(vobj.Object.Name, 0)
        return True

    def begin_draggers(self, vobj):
        """Starts a new set of draggers (the old ones removed); returns its Coin root."""
        from pivy import coin
        self.remove_draggers(vobj)
        self.edit_root = coin.SoSeparator()
        self.draggers = []
        return self.edit_root

    def add_dragger(self, key, position, size):
        """A dragger at `position`, drawn `size` large, reporting drags of `key`."""
        from pivy import coin
        sep = coin.SoSeparator()
        place = coin.SoTransform()
        place.translation.setValue(*position)
        place.scaleFactor.setValue(size, size, size)
        dragger = coin.SoDragPointDragger()
        sep.addChild(place)
        sep.addChild(dragger)
        self.edit_root.addChild(sep)
        dragger.addStartCallback(lambda _d, _dr, key=key: self.drag_started(key))
        if hasattr(self, "drag_moved"):
            dragger.addMotionCallback(lambda _d, dr, key=key, s=size: self.drag_moved(key, dr, s))
        dragger.addFinishCallback(lambda _d, dr, key=key, s=size: self.drag_finished(key, dr, s))
        self.draggers.append((key, dragger, size))

    def remove_draggers(self, vobj):
        if getattr(self, "edit_root", None) is not None:
            vobj.RootNode.removeChild(self.edit_root)
        self.edit_root = None
        self.draggers = []

    def dragger(self, key):
        """(dragger, size) of a point, for the GUI test and scripts."""
        for k, dragger, size in self.draggers:
            if k == tuple(key):
                return dragger, size
        raise KeyError(key)

    def drag_finished(self, key, dragger, size):
        """Applies the dragger's translation (in its scaled frame) as one undo step: the
        transaction drag_started opened is committed after a recompute, or aborted when the
        move is refused (the document left as it was). The draggers are rebuilt at the new
        points once Coin's callback has returned."""
        obj = self.Object
        doc = obj.Document
        t = dragger.translation.getValue()
        try:
            self.apply_drag(key, FreeCAD.Vector(t[0] * size, t[1] * size, t[2] * size))
            doc.recompute()
            doc.commitTransaction()
        except Exception as e:
            doc.abortTransaction()
            FreeCAD.Console.PrintError("%s: %s\n" % (obj.Label, e))
        from PySide import QtCore
        vobj = obj.ViewObject
        QtCore.QTimer.singleShot(0, lambda: self.build_draggers(vobj)
                                 if self.edit_root is not None else None)
