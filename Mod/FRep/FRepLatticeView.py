"""The Lattice feature's view provider: its control net as lines and points, and in edit mode
(double-click) a Coin dragger on every control point. Each drag is one undo step: the
transaction opens when the drag starts and commits when it ends, after the lattice's Offsets
change and the document recomputes. A view provider asks its object: it never imports the
feature module."""

import FreeCAD

import FRepPaths
from FRepProxy import StatelessProxy


class ViewProviderLattice(StatelessProxy):
    def __init__(self, vobj):
        vobj.Proxy = self
        vobj.LineColor = (0.85, 0.35, 0.1)
        vobj.PointColor = (0.85, 0.35, 0.1)
        vobj.PointSize = 6
        vobj.DisplayMode = "Wireframe"

    def attach(self, vobj):
        self.Object = vobj.Object
        self.edit_root = None
        self.draggers = []

    def getIcon(self):
        return FRepPaths.icon("lattice", "deformation")

    def claimChildren(self):
        return []

    # -- edit mode: draggers ------------------------------------------------------------------
    def setEdit(self, vobj, mode=0):
        if mode != 0:
            return None
        import FreeCADGui
        import FRepTaskPanels
        self.build_draggers(vobj)
        FreeCADGui.Control.showDialog(FRepTaskPanels.LatticeEditPanel(vobj.Object))
        return True

    def unsetEdit(self, vobj, mode=0):
        if mode != 0:
            return None
        import FreeCADGui
        self.remove_draggers(vobj)
        FreeCADGui.Control.closeDialog()
        return True

    def doubleClicked(self, vobj):
        import FreeCADGui
        FreeCADGui.ActiveDocument.setEdit(vobj.Object.Name, 0)
        return True

    def dragger_size(self):
        obj = self.Object
        lo, hi = obj.Proxy.rest_box(obj)
        cells = [(hi[a] - lo[a]) / max(1, (obj.DivisionsX, obj.DivisionsY, obj.DivisionsZ)[a])
                 for a in range(3)]
        return 0.25 * min(cells)

    def build_draggers(self, vobj):
        from pivy import coin
        self.remove_draggers(vobj)
        obj = vobj.Object
        points = obj.Proxy.lattice(obj).points
        size = self.dragger_size()
        self.edit_root = coin.SoSeparator()
        self.draggers = []
        d = (obj.DivisionsX, obj.DivisionsY, obj.DivisionsZ)
        index = 0
        for i in range(d[0] + 1):
            for j in range(d[1] + 1):
                for k in range(d[2] + 1):
                    sep = coin.SoSeparator()
                    place = coin.SoTransform()
                    place.translation.setValue(*points[index])
                    place.scaleFactor.setValue(size, size, size)
                    dragger = coin.SoDragPointDragger()
                    sep.addChild(place)
                    sep.addChild(dragger)
                    self.edit_root.addChild(sep)
                    ijk = (i, j, k)
                    dragger.addStartCallback(lambda _d, _dr, ijk=ijk: self.drag_started(ijk))
                    dragger.addFinishCallback(
                        lambda _d, dr, ijk=ijk, s=size: self.drag_finished(ijk, dr, s))
                    self.draggers.append((ijk, dragger, size))
                    index += 1
        vobj.RootNode.addChild(self.edit_root)

    def remove_draggers(self, vobj):
        if self.edit_root is not None:
            vobj.RootNode.removeChild(self.edit_root)
        self.edit_root = None
        self.draggers = []

    def dragger(self, ijk):
        """The dragger of control point (i, j, k), for the GUI test and scripts."""
        for index, dragger, size in self.draggers:
            if index == ijk:
                return dragger, size
        raise KeyError(ijk)

    def drag_started(self, ijk):
        self.Object.Document.openTransaction("Move lattice point (%d, %d, %d)" % ijk)

    def drag_finished(self, ijk, dragger, size):
        """Moves the point by the dragger's translation (in its scaled frame) as an offset
        (divided by Amount, which scales every offset), recomputes and commits the step."""
        obj = self.Object
        doc = obj.Document
        t = dragger.translation.getValue()
        delta = FreeCAD.Vector(t[0] * size, t[1] * size, t[2] * size)
        amount = obj.Amount if abs(obj.Amount) > 1e-12 else 1.0
        try:
            obj.Proxy.nudge_point(obj, ijk, delta * (1.0 / amount))
            doc.recompute()
            doc.commitTransaction()
        except Exception as e:  # a refused move leaves the document as it was
            doc.abortTransaction()
            FreeCAD.Console.PrintError("%s: %s\n" % (obj.Label, e))
        # The draggers move to the new points once this callback has returned.
        from PySide import QtCore
        vobj = obj.ViewObject
        QtCore.QTimer.singleShot(0, lambda: self.build_draggers(vobj)
                                 if self.edit_root is not None else None)
