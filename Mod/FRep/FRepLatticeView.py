"""The Lattice feature's view provider: its control net as lines and points, and in edit mode
(double-click) a Coin dragger on every control point. Each drag is one undo step: the
transaction opens when the drag starts and commits when it ends, after the lattice's Offsets
change and the document recomputes. A view provider asks its object: it never imports the
feature module."""


import FRepPaths
from FRepDraggers import DraggerHost
from FRepProxy import StatelessProxy


class ViewProviderLattice(DraggerHost, StatelessProxy):
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

    def dragger_size(self):
        obj = self.Object
        lo, hi = obj.Proxy.rest_box(obj)
        cells = [(hi[a] - lo[a]) / max(1, (obj.DivisionsX, obj.DivisionsY, obj.DivisionsZ)[a])
                 for a in range(3)]
        return 0.25 * min(cells)

    def build_draggers(self, vobj):
        obj = vobj.Object
        points = obj.Proxy.lattice(obj).points
        size = self.dragger_size()
        self.begin_draggers(vobj)
        d = (obj.DivisionsX, obj.DivisionsY, obj.DivisionsZ)
        index = 0
        for i in range(d[0] + 1):
            for j in range(d[1] + 1):
                for k in range(d[2] + 1):
                    self.add_dragger((i, j, k), points[index], size)
                    index += 1
        vobj.RootNode.addChild(self.edit_root)

    def drag_started(self, ijk):
        self.Object.Document.openTransaction("Move lattice point (%d, %d, %d)" % ijk)

    def apply_drag(self, ijk, delta):
        """Moves the point by delta as an offset (divided by Amount, which scales every
        offset)."""
        obj = self.Object
        amount = obj.Amount if abs(obj.Amount) > 1e-12 else 1.0
        obj.Proxy.nudge_point(obj, ijk, delta * (1.0 / amount))
