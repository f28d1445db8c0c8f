"""Point sample: points on an FRep solid's surface as a FreeCAD Points object (for Points'
tools, reverse engineering, or comparing with a scan). The points are the vertices of the
solid's mesh at `Cells` cells along its longest side: each found on the surface by root
finding on the exact field (creases and corners: placed on them from the gradient).

Scripting: FRepPointSample.make(solid, cells=64) returns the feature.
"""

import FreeCAD

import FRepTree
from FRepErrors import one_line_errors
from FRepPaths import frepcore
from FRepProxy import FeatureProxy, add_property

GROUP = "Point sample"
DEFAULT_CELLS = 64


class PointSampleFeature(FeatureProxy):
    def setup(self, obj):
        add_property(obj, "App::PropertyLink", "Source", GROUP,
                     "The FRep solid (or any FRep input) to sample.")
        add_property(obj, "App::PropertyInteger", "Cells", GROUP,
                     "Cells along the longest side of the solid's box: the points are about "
                     "a cell apart. Allowed: 4 to 1024.", DEFAULT_CELLS)
        if "Count" not in obj.PropertiesList:
            obj.addProperty("App::PropertyInteger", "Count", GROUP, "Points (read-only).")
            obj.setEditorMode("Count", 1)

    @one_line_errors
    def execute(self, obj):
        import Points
        if obj.Source is None:
            raise ValueError("%s: property 'Source' is empty; link the FRep solid to sample"
                             % obj.Label)
        if not 4 <= obj.Cells <= 1024:
            raise ValueError("%s: property 'Cells' = %d is out of range; allowed: 4 to 1024"
                             % (obj.Label, obj.Cells))
        shape = FRepTree.shape_of(obj.Source)
        box, cell = frepcore.automatic_box(shape, cells=obj.Cells)
        mesh = shape.node.mesh(box, cell)
        obj.Points = Points.Points([FreeCAD.Vector(*p) for p in mesh.points])
        obj.Count = mesh.vertex_count


def make(source, doc=None, cells=DEFAULT_CELLS, name="PointSample"):
    doc = doc or source.Document
    obj = doc.addObject("Points::FeaturePython", name)
    PointSampleFeature(obj)
    if FreeCAD.GuiUp:
        import FRepViewProviders
        FRepViewProviders.ViewProviderPointSample(obj.ViewObject)
    obj.Source = source
    obj.Cells = cells
    return obj
