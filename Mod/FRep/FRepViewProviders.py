"""View providers: icons per node type, inputs shown as children in the tree (as Part
booleans do), and inputs shown again when an operation is deleted."""

import FRepPaths
from FRepProxy import StatelessProxy


class ViewProviderFRep(StatelessProxy):
    def __init__(self, vobj):
        vobj.Proxy = self

    def attach(self, vobj):
        self.Object = vobj.Object

    def getIcon(self):
        import FRepFeatures
        type_id = self.Object.Proxy.FREP_TYPE
        return FRepPaths.icon(type_id, FRepFeatures.NODE_TYPES[type_id]["category"])

    def claimChildren(self):
        import FRepFeatures
        return FRepFeatures.linked_inputs(self.Object)

    def onDelete(self, vobj, subelements):
        import FRepFeatures
        for obj in FRepFeatures.linked_inputs(vobj.Object):
            obj.Visibility = True
        return True


class ViewProviderPolygonize(ViewProviderFRep):
    def getIcon(self):
        return FRepPaths.icon("polygonize")

    def claimChildren(self):
        return [self.Object.Source] if self.Object.Source else []

    def onDelete(self, vobj, subelements):
        if vobj.Object.Source:
            vobj.Object.Source.Visibility = True
        return True
