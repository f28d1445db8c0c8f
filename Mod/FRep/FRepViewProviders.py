"""View providers: icons per node type, inputs shown as children in the tree (as Part
booleans do), inputs shown again when an operation is deleted, and double-click to edit the
parameters in a task panel. A view provider asks its object (its proxy's category(),
inputs() and parameters()); it never imports the feature module."""

import FRepPaths
from FRepProxy import StatelessProxy


class ViewProviderFRep(StatelessProxy):
    def __init__(self, vobj):
        vobj.Proxy = self

    def attach(self, vobj):
        self.Object = vobj.Object

    def getIcon(self):
        proxy = self.Object.Proxy
        return FRepPaths.icon(proxy.FREP_TYPE, proxy.category())

    def claimChildren(self):
        return self.Object.Proxy.inputs(self.Object)

    def onDelete(self, vobj, subelements):
        for obj in vobj.Object.Proxy.inputs(vobj.Object):
            obj.Visibility = True
        return True

    # Double-click (or Edit) opens the parameters' task panel; mode 0 is the default edit.
    def updateData(self, obj, prop):
        if prop == "Mesh":  # a blend's guide, when it is up, follows the new values
            import FRepBlendGuideView
            FRepBlendGuideView.refresh(obj)

    def setEdit(self, vobj, mode=0):
        if mode != 0:
            return None
        import FreeCADGui
        import FRepTaskPanels
        FreeCADGui.Control.showDialog(FRepTaskPanels.ParametersPanel(vobj.Object))
        return True

    def unsetEdit(self, vobj, mode=0):
        if mode != 0:
            return None
        import FreeCADGui
        FreeCADGui.Control.closeDialog()
        return True

    def doubleClicked(self, vobj):
        import FreeCADGui
        FreeCADGui.ActiveDocument.setEdit(vobj.Object.Name, 0)
        return True


class ViewProviderAttachment(ViewProviderFRep):
    """An hspline attachment: edit mode is the Attach panel (the rectangle, the limb)."""

    def getIcon(self):
        return FRepPaths.icon("hspline_attach")

    def setEdit(self, vobj, mode=0):
        if mode != 0:
            return None
        import FreeCADGui
        import FRepHSplineAttachPanel
        FreeCADGui.Control.showDialog(FRepHSplineAttachPanel.AttachPanel(vobj.Object))
        return True


class ViewProviderStrutsAlong(ViewProviderFRep):
    """Struts along an hspline: its own icon; the surface stays where it is in the tree."""

    def getIcon(self):
        return FRepPaths.icon("hspline_struts")


class ViewProviderSection(ViewProviderFRep):
    """A section's wires: drawn thick and orange over the solid they cut."""

    def attach(self, vobj):
        self.Object = vobj.Object
        vobj.LineWidth = 3.0
        vobj.LineColor = (0.85, 0.45, 0.05)

    def getIcon(self):
        return FRepPaths.icon("section")

    def claimChildren(self):
        return []

    def onDelete(self, vobj, subelements):
        return True

    def setEdit(self, vobj, mode=0):  # its plane and cells are plain properties
        return None

    def doubleClicked(self, vobj):
        return False


class ViewProviderPointSample(ViewProviderSection):
    """Sampled points: drawn larger than FreeCAD's default so a sparse sample shows."""

    def attach(self, vobj):
        self.Object = vobj.Object
        if hasattr(vobj, "PointSize"):
            vobj.PointSize = 3.0

    def getIcon(self):
        return FRepPaths.icon("point_sample")


class ViewProviderPolygonize(ViewProviderFRep):
    def getIcon(self):
        return FRepPaths.icon("polygonize")

    def claimChildren(self):
        return [self.Object.Source] if self.Object.Source else []

    def onDelete(self, vobj, subelements):
        if vobj.Object.Source:
            vobj.Object.Source.Visibility = True
        return True

    def setEdit(self, vobj, mode=0):  # its settings are plain properties
        return None

    def doubleClicked(self, vobj):
        return False
