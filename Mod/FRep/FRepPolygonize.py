"""The Polygonize feature: the full-resolution mesh of an FRep solid, as a Mesh feature.

Seed 000's polygoniser settings: bounding box (automatic from the tree's interval bounds by
default), grid resolution and method. Long meshing shows FreeCAD's progress indicator and can
be cancelled; a cancelled recompute leaves the previous mesh in place.
"""

import FreeCAD

import FRepMeshing
import FRepTree
from FRepProxy import FeatureProxy
from FRepPaths import frepcore

GROUP = "Polygonize"
# Both closed, manifold and oriented by design (docs/mesher.md): "Cubes" caps each crossed
# cube with a fan (a third of the triangles, creases placed); "Marching tetrahedra" is the
# mesher before 0.3, kept selectable for one release.
METHODS = ["Cubes", "Marching tetrahedra"]
MESHER_OF_METHOD = {"Cubes": "cubes", "Marching tetrahedra": "tetra"}
REFINEMENTS = ["Off", "Thin parts", "Thin parts and tips"]


class Polygonize(FeatureProxy):
    def setup(self, obj):
        def add(kind, name, doc, value=None):
            if name not in obj.PropertiesList:
                obj.addProperty(kind, name, GROUP, doc)
                if value is not None:
                    setattr(obj, name, value)

        add("App::PropertyLink", "Source", "The FRep feature (or Part primitive) to mesh.")
        add("App::PropertyBool", "AutoBounds",
            "Bounding box from the solid's interval bounds (padded by 1.5 cells).", True)
        add("App::PropertyVectorDistance", "BoundsMin", "Low corner of the box when "
            "AutoBounds is off.", FreeCAD.Vector(-10, -10, -10))
        add("App::PropertyVectorDistance", "BoundsMax", "High corner of the box when "
            "AutoBounds is off.", FreeCAD.Vector(10, 10, 10))
        add("App::PropertyLength", "Resolution", "Cell size; 0 derives it from Cells.", 0)
        add("App::PropertyInteger", "Cells", "Cells along the longest side of the box when "
            "Resolution is 0. Allowed: 4 to 4096.", FRepMeshing.DEFAULT_EXPORT_CELLS)
        add("App::PropertyEnumeration", "Method", "Polygonisation method: Cubes (a third "
            "of the triangles, creases placed) or Marching tetrahedra (the mesher before "
            "0.3).", METHODS)
        if list(obj.getEnumerationsOfProperty("Method")) != METHODS:
            # a document from before 0.3 had one method to store: it meshes with the new
            # default from now on (Marching tetrahedra stays selectable)
            obj.Method = METHODS
            obj.Method = "Cubes"
        add("App::PropertyLength", "Tolerance", "Simplify the mesh: far fewer triangles, the "
            "surface kept within this distance of the exact one (0: off). A tenth of the "
            "cell size is a good start.", 0)
        add("App::PropertyBool", "SharpFeatures", "Put vertices on the creases and corners "
            "(the Cubes mesher, and the simplifier with a Tolerance) instead of chamfering "
            "them within a cell.", True)
        # (a document saved without the property gets it on, as a new one: the same accuracy
        # with fewer triangles; one saved with it keeps its setting)
        add("App::PropertyBool", "FewerTriangles", "Drop the vertices where the surface is flat "
            "within a fiftieth of a cell, two triangles with each: 6 to 15 % fewer triangles, "
            "the same accuracy, a little longer meshing (the Cubes method).", True)
        # (a document saved without it gets Off: the mesh it had)
        if "RefineThinParts" not in obj.PropertiesList:
            add("App::PropertyEnumeration", "RefineThinParts", "Mesh the cubes where a part "
                "thinner than a cell passes between the grid's points again at half a cell: "
                "walls and fins the grid misses come back, slits it closes open again. With "
                "tips too, the tips of creases and slivers (the gyroid's), but creases there "
                "come out less clean. Takes longer.", REFINEMENTS)
            obj.RefineThinParts = "Off"
        # (a document saved without it gets one level: the mesh it had)
        add("App::PropertyInteger", "RefineLevels", "Levels of RefineThinParts: 2 or 3 mesh "
            "again at a quarter (an eighth) of a cell where parts hide between the half "
            "cells' points, and where the mesh lies over 0.3 cell from the surface: the "
            "gyroid within half a cell. Allowed: 1 to 3. Takes several times longer.", 1)
        # (a document saved without it gets it off: the mesh it had)
        add("App::PropertyBool", "StraightenCreases", "Merge the vertices either side of a "
            "chamfered or zig-zagging crease onto it and flip its edges along it (within a "
            "third of a cell): clean, straight creases. Needs SharpFeatures; takes a few "
            "times as long as meshing.", False)
        if "Triangles" not in obj.PropertiesList:
            obj.addProperty("App::PropertyInteger", "Triangles", GROUP,
                            "Triangles in the mesh (read-only).")
            obj.setEditorMode("Triangles", 1)
        self.show_box_mode(obj)

    def onChanged(self, obj, prop):
        if prop == "AutoBounds":
            self.show_box_mode(obj)

    @staticmethod
    def show_box_mode(obj):
        """BoundsMin/BoundsMax are read-only while AutoBounds decides the box."""
        if "BoundsMin" in obj.PropertiesList:
            for name in ("BoundsMin", "BoundsMax"):
                obj.setEditorMode(name, 1 if obj.AutoBounds else 0)

    def execute(self, obj):
        if obj.Source is None:
            raise ValueError("%s: property 'Source' is empty; link the FRep feature to mesh"
                             % obj.Label)
        shape = FRepTree.shape_of(obj.Source)
        box, cell = meshing_box(obj, shape)
        mesh = FRepMeshing.run_with_progress(
            "Polygonizing %s" % obj.Source.Label,
            lambda progress: _mesh_or_cancel(obj, shape, box, cell, progress))
        obj.Triangles = mesh.triangle_count
        FRepMeshing.warn_thin_parts(obj.Label, getattr(mesh, "thin_parts", None))
        FRepMeshing.report_straightened(obj.Label, getattr(mesh, "straightened", None))
        FRepMeshing.set_mesh(obj, FRepMeshing.to_freecad_mesh(mesh))


def simplification(obj):
    """(tolerance or None, sharp features) from a Polygonize feature's settings."""
    tolerance = obj.Tolerance.Value if "Tolerance" in obj.PropertiesList else 0.0
    sharp = obj.SharpFeatures if "SharpFeatures" in obj.PropertiesList else True
    return (tolerance or None), sharp


def fewer_triangles(obj):
    """Whether a Polygonize feature drops the mesher's flat vertices (FewerTriangles)."""
    return bool(obj.FewerTriangles) if "FewerTriangles" in obj.PropertiesList else True


def refinement_of(obj):
    """(refine_thin_parts, refine_tips) for frepcore from a Polygonize feature's
    RefineThinParts."""
    choice = obj.RefineThinParts if "RefineThinParts" in obj.PropertiesList else "Off"
    return choice != "Off", choice == "Thin parts and tips"


def refinement_levels(obj):
    """frepcore's refine_levels from a Polygonize feature's RefineLevels; an error naming the
    property where it is out of range, or asks for levels with RefineThinParts off."""
    levels = obj.RefineLevels if "RefineLevels" in obj.PropertiesList else 1
    if not 1 <= levels <= 3:
        raise ValueError("%s: property 'RefineLevels' is %d; allowed: 1 to 3"
                         % (obj.Label, levels))
    if levels > 1 and not refinement_of(obj)[0]:
        raise ValueError("%s: property 'RefineLevels' %d needs 'RefineThinParts' on (the "
                         "levels are that refinement's); turn RefineThinParts on or set "
                         "RefineLevels to 1" % (obj.Label, levels))
    return levels


def straightens_creases(obj):
    """Whether a Polygonize feature straightens its creases; an error naming the properties
    where it asks for that without sharp features."""
    if not ("StraightenCreases" in obj.PropertiesList and obj.StraightenCreases):
        return False
    if "SharpFeatures" in obj.PropertiesList and not obj.SharpFeatures:
        raise ValueError("%s: property 'StraightenCreases' needs 'SharpFeatures' on (they find "
                         "the creases); turn SharpFeatures on or StraightenCreases off"
                         % obj.Label)
    return True


def mesh_keywords(obj):
    """frepcore's meshing keywords (mesh() and export() alike) from a Polygonize feature's
    settings, simplification apart."""
    refine_thin_parts, refine_tips = refinement_of(obj)
    return {"mesher": mesher_of(obj), "fewer_triangles": fewer_triangles(obj),
            "refine_thin_parts": refine_thin_parts, "refine_tips": refine_tips,
            "refine_levels": refinement_levels(obj),
            "straighten_creases": straightens_creases(obj)}


def mesher_of(obj):
    """frepcore's mesher name ('cubes' or 'tetra') for a Polygonize feature's Method."""
    method = obj.Method if "Method" in obj.PropertiesList else METHODS[0]
    return MESHER_OF_METHOD.get(method, "cubes")


def _mesh_or_cancel(obj, shape, box, cell, progress):
    tolerance, sharp = simplification(obj)
    try:
        return shape.node.mesh(box, cell, progress, False, tolerance, sharp,
                               **mesh_keywords(obj))
    except frepcore.Cancelled:
        raise RuntimeError("%s: polygonizing was cancelled; the previous mesh is kept"
                           % obj.Label)


def meshing_box(obj, shape):
    """(box, cell size) from a Polygonize feature's settings; errors name the property."""
    if not FRepMeshing.MIN_CELLS <= obj.Cells <= FRepMeshing.MAX_CELLS:
        raise ValueError("%s: property 'Cells' = %d is out of range; allowed: %d to %d"
                         % (obj.Label, obj.Cells, FRepMeshing.MIN_CELLS,
                            FRepMeshing.MAX_CELLS))
    resolution = obj.Resolution.Value or None
    if obj.AutoBounds:
        try:
            return frepcore.automatic_box(shape, resolution=resolution, cells=obj.Cells)
        except ValueError as e:
            raise ValueError("%s: property 'AutoBounds': cannot bound '%s': %s; or turn "
                             "AutoBounds off and set BoundsMin and BoundsMax"
                             % (obj.Label, obj.Source.Label, e))
    lo, hi = obj.BoundsMin, obj.BoundsMax
    if not (lo.x < hi.x and lo.y < hi.y and lo.z < hi.z):
        raise ValueError("%s: properties 'BoundsMin' %s and 'BoundsMax' %s make an empty box; "
                         "each component of BoundsMin must be below BoundsMax"
                         % (obj.Label, tuple(lo), tuple(hi)))
    return frepcore.automatic_box(shape, resolution=resolution, cells=obj.Cells,
                                  bbox=((lo.x, lo.y, lo.z), (hi.x, hi.y, hi.z)))


def make(source, doc=None, name="Polygonize", **settings):
    doc = doc or source.Document
    obj = doc.addObject("Mesh::FeaturePython", name)
    Polygonize(obj)
    if FreeCAD.GuiUp:
        import FRepViewProviders
        FRepViewProviders.ViewProviderPolygonize(obj.ViewObject)
    obj.Source = source
    for key, value in settings.items():
        setattr(obj, key, value)
    source.Visibility = False
    return obj
