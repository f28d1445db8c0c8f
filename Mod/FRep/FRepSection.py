"""Section: where a plane cuts an FRep solid, as FreeCAD wires. The contours come from
frepcore (marching squares on the plane, each vertex found on the solid's surface), one
closed polygon per loop, holes included; the shape is a compound of wires that Sketcher
(external geometry), Part (Face, Extrude) and PartDesign take like any other edges.

Scripting: FRepSection.make(solid, origin=(0, 0, 5), normal=(0, 0, 1)) returns the feature.
"""

import FreeCAD

import FRepTree
from FRepErrors import one_line_errors
from FRepPaths import frepcore
from FRepProxy import FeatureProxy, add_property

GROUP = "Section"
DEFAULT_CELLS = 256


class SectionFeature(FeatureProxy):
    def setup(self, obj):
        def add(kind, name, doc, value=None):
            add_property(obj, kind, name, GROUP, doc, value)

        add("App::PropertyLink", "Source", "The FRep solid (or any FRep input) to cut.")
        add("App::PropertyVectorDistance", "Origin", "A point of the cutting plane.")
        add("App::PropertyVector", "Normal", "The cutting plane's normal; the contours turn "
            "counterclockwise round the solid seen against it.", FreeCAD.Vector(0, 0, 1))
        add("App::PropertyInteger", "Cells", "Grid cells along the longer side of the solid "
            "as the plane sees it: more follow the surface closer. Allowed: 2 to 4096.",
            DEFAULT_CELLS)
        if "Loops" not in obj.PropertiesList:
            obj.addProperty("App::PropertyInteger", "Loops", GROUP,
                            "Closed contours in the section (read-only).")
            obj.setEditorMode("Loops", 1)

    @one_line_errors
    def execute(self, obj):
        import Part
        if obj.Source is None:
            raise ValueError("%s: property 'Source' is empty; link the FRep solid to cut"
                             % obj.Label)
        if not 2 <= obj.Cells <= 4096:
            raise ValueError("%s: property 'Cells' = %d is out of range; allowed: 2 to 4096"
                             % (obj.Label, obj.Cells))
        if obj.Normal.Length == 0:
            raise ValueError("%s: property 'Normal' is the zero vector; give the plane's "
                             "direction" % obj.Label)
        shape = FRepTree.shape_of(obj.Source)
        loops = shape.section(tuple(obj.Origin), tuple(obj.Normal), cells=obj.Cells)
        wires = []
        for points, closed in loops:
            vertices = [FreeCAD.Vector(*p) for p in points]
            if closed:
                vertices.append(vertices[0])
            wires.append(Part.makePolygon(vertices))
        obj.Loops = sum(1 for _, closed in loops if closed)
        # no loops: a null shape, which a dependent refuses in a line (FreeCAD 0.20's
        # Extrude crashes on an empty compound)
        obj.Shape = Part.makeCompound(wires) if wires else Part.Shape()
        if not wires:
            FreeCAD.Console.PrintWarning("%s: the plane does not cut %s\n"
                                         % (obj.Label, obj.Source.Label))


def make(source, doc=None, origin=None, normal=(0, 0, 1), cells=DEFAULT_CELLS,
         name="Section"):
    """A Section feature of `source`; the plane through origin (default: the middle of the
    solid's box) with this normal."""
    doc = doc or source.Document
    obj = doc.addObject("Part::FeaturePython", name)
    SectionFeature(obj)
    if FreeCAD.GuiUp:
        import FRepViewProviders
        FRepViewProviders.ViewProviderSection(obj.ViewObject)
    obj.Source = source
    if origin is None:
        box, _ = frepcore.automatic_box(FRepTree.shape_of(source), cells=cells)
        origin = [(lo + hi) / 2 for lo, hi in zip(box[0], box[1])]
    obj.Origin = FreeCAD.Vector(*origin)
    obj.Normal = FreeCAD.Vector(*normal)
    obj.Cells = cells
    return obj
