"""The Polygonize feature: the full-resolution mesh of an FRep solid, as a Mesh feature.

Seed 000's polygoniser settings: bounding box (automatic from the tree's interval bounds by
default), grid resolution and method. Long meshing shows FreeCAD's progress indicator and can
be cancelled; a cancelled recompute leaves the previous mesh in place.
"""

import FreeCAD

import FRepMeshing
import FRepTree
from FRepErrors import FeatureError, one_line_errors
from FRepProxy import FeatureProxy, add_property
from FRepPaths import frepcore

GROUP = "Polygonize"


class SettingProperty:
    """A meshing option (a row of frepcore.mesh_settings_table()) as a property: its name,
    its FreeCAD type, the labels an enumeration shows for the option's words, and the
    property an older document held it in (taken over when the document is reopened)."""

    def __init__(self, option, name, kind, labels=None, older=None):
        self.option, self.name, self.kind, self.labels, self.older = (option, name, kind,
                                                                     labels, older)

    def value(self, obj):
        """The option's value from the property (the table's default where the document
        has no such property: a document saved before it existed meshes as it did)."""
        if self.name not in obj.PropertiesList:
            return DEFAULTS[self.option]
        value = getattr(obj, self.name)
        if self.labels:
            return self.labels.get(value, DEFAULTS[self.option])
        if self.option == "tolerance":
            return value.Value or None  # (0: off)
        return value

    def default(self):
        """The property's value for the option's default."""
        value = DEFAULTS[self.option]
        if self.labels:
            return next(label for label, word in self.labels.items() if word == value)
        return 0 if value is None else value


# Both meshers are closed, manifold and oriented by design (docs/mesher.md).
SETTING_PROPERTIES = [
    SettingProperty("mesher", "Mesher", "App::PropertyEnumeration",
                    {"Cubes": "cubes", "Marching tetrahedra": "tetra"}, older="Method"),
    SettingProperty("sharp_features", "SharpFeatures", "App::PropertyBool"),
    SettingProperty("drop_flat_vertices", "DropFlatVertices", "App::PropertyBool",
                    older="FewerTriangles"),
    SettingProperty("refine", "Refine", "App::PropertyEnumeration",
                    {"Off": "off", "Thin parts": "thin-parts", "Thin parts and tips": "tips"},
                    older="RefineThinParts"),
    SettingProperty("refine_levels", "RefineLevels", "App::PropertyInteger"),
    SettingProperty("straighten_creases", "StraightenCreases", "App::PropertyBool"),
    SettingProperty("tolerance", "Tolerance", "App::PropertyLength"),
]
PROPERTY_OF_OPTION = {p.option: p.name for p in SETTING_PROPERTIES}
TABLE = {row["name"]: row for row in frepcore.mesh_settings_table()}
DEFAULTS = {name: row["default"] for name, row in TABLE.items()}
assert set(PROPERTY_OF_OPTION) == set(TABLE), "a meshing option has no property"


def spell_properties(text):
    """A text of frepcore's table with each {option} as its property's name."""
    for option, name in PROPERTY_OF_OPTION.items():
        text = text.replace("{%s}" % option, "'%s'" % name)
    return text


def add_setting_properties(obj):
    """The meshing options' properties, tooltips from the table; an older document's
    properties are taken over under the names they have now."""
    for prop in SETTING_PROPERTIES:
        older = None
        if prop.older and prop.older in obj.PropertiesList:
            older = getattr(obj, prop.older)
            # (a document from before 0.3 had one mesher to store, whatever its label: it
            # meshes with the default from now on)
            if prop.labels and list(obj.getEnumerationsOfProperty(prop.older)) != list(
                    prop.labels):
                older = prop.default()
            obj.removeProperty(prop.older)
        if prop.name not in obj.PropertiesList:
            tip = spell_properties(TABLE[prop.option]["help"])
            obj.addProperty(prop.kind, prop.name, GROUP, tip[0].upper() + tip[1:] + ".")
            if prop.labels:
                setattr(obj, prop.name, list(prop.labels))
            setattr(obj, prop.name, prop.default())
        if older is not None:
            setattr(obj, prop.name, older if not prop.labels or older in prop.labels
                    else prop.default())


def settings_of(obj):
    """frepcore.MeshSettings from a Polygonize feature's properties; a ValueError naming
    the property where they are out of range or contradict each other."""
    settings = frepcore.MeshSettings(**{p.option: p.value(obj) for p in SETTING_PROPERTIES})
    problem = settings.problem()
    if problem is not None:
        raise ValueError("%s: property %s" % (obj.Label, spell_properties(problem[1])))
    return settings


class Polygonize(FeatureProxy):
    def setup(self, obj):
        def add(kind, name, doc, value=None):
            add_property(obj, kind, name, GROUP, doc, value)

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
        add_setting_properties(obj)
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

    @one_line_errors
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


def _mesh_or_cancel(obj, shape, box, cell, progress):
    settings = settings_of(obj)
    try:
        return shape.node.mesh(box, cell, progress, False, settings)
    except frepcore.Cancelled:
        raise FeatureError("%s: polygonizing was cancelled; the previous mesh is kept"
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
