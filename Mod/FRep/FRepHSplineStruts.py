"""Struts along an hspline as one parametric feature: a strut lattice in a shell along the
surface, its cells following the surface's parameters through an FFD lattice fitted to it
(`frepcad hspline lattice`, docs/struts.md). The fit is made again whenever the surface or a
setting changes, so moving the hspline's CVs moves the cells with it.

The feature is the ffd node at the top of that model (so exports, beam 3MFs and downstream
FRep operations see an ordinary FRep feature); its lattice comes from the fit, not from
properties, and its own settings are the shell's.

Scripting:
    import FRepHSpline as H, FRepHSplineStruts as S
    panel = H.make_plane(doc, 6, 5, 30.0, 20.0)
    struts = S.make_struts_along(doc, panel, thickness=3.0, cell=1.5)
    doc.recompute()
"""

import FreeCAD

import FRepFeatures
import FRepHSpline as H
import FRepProperties as props
from FRepErrors import one_line_errors
from FRepLattice import FFD_PARAMS
from FRepPaths import frepcore
from FRepProxy import add_property

GROUP = "Struts along"
MAX_DIVISIONS = 24  # as the core's fit allows


def _param(name, kind, doc, default, unit="", least=None, most=None, exclusive=False,
           allowed="", choices=None):
    """A parameter in the registry's terms, for the task panel's form."""
    p = {"name": name, "type": kind, "doc": doc, "default": default, "unit": unit,
         "min": least, "max": most, "min_exclusive": exclusive, "max_exclusive": False,
         "nonzero": False, "title": "", "allowed": allowed}
    if choices is not None:
        p["choices"] = list(choices)
    if "_" in name:  # (the panel's words: "Cell type", not "CellType")
        p["title"] = name.replace("_", " ").capitalize().replace(" u", " U").replace(" v", " V")
    return p


def _cell_types():
    struts = next(t for t in frepcore.node_types() if t["type"] == "strut_lattice")
    return next(p for p in struts["params"] if p["name"] == "cell_type")["choices"]


def shell_params():
    """The feature's own settings (the ffd's Struts follows them in the panel)."""
    return [
        _param("thickness", "real", "The shell's thickness across the surface (the cells "
               "fill it from one side to the other).", 1.0, "length", 0.0, None, True,
               "(0, inf)"),
        _param("cell", "real", "The cells' side along the surface and across it; 0: half "
               "the thickness (round a closed surface whole cells make a turn).", 0.0,
               "length", 0.0, None, False, "[0, inf)"),
        _param("cell_type", "choice", "The unit cell.", "octet", choices=_cell_types(),
               allowed="one of the unit cells"),
        _param("radius", "real", "The struts' radius; 0: a tenth of a cell.", 0.0, "length",
               0.0, None, False, "[0, inf)"),
        _param("divisions_u", "integer", "The fitted lattice's divisions along the surface's "
               "u; 0: level 0's CVs less one (at most %d)." % MAX_DIVISIONS, 0, "", 0,
               MAX_DIVISIONS, False, "an integer in [0, %d]" % MAX_DIVISIONS),
        _param("divisions_v", "integer", "The same along v.", 0, "", 0, MAX_DIVISIONS, False,
               "an integer in [0, %d]" % MAX_DIVISIONS),
    ]


_FFD = FRepFeatures.FEATURE_CLASSES["ffd"]
_FITS = {}  # (document, name) -> (the hspline read, settings, frepcore's result, shape)


class StrutsAlongFeature(_FFD):
    """The ffd node over a strut lattice cut to a shell, refitted to its Surface."""

    def setup(self, obj):
        super().setup(obj)
        add_property(obj, "App::PropertyLink", "Surface", GROUP,
                     "The hspline the cells follow (its parameters carry them).")
        for p in shell_params():
            props.add_param_property(obj, p)
        add_property(obj, "App::PropertyLength", "Deviation", GROUP,
                     "How closely the fitted lattice follows the surface, after the last "
                     "recompute (the cells' distance from where the surface's parameters put "
                     "them).")
        obj.setEditorMode("Deviation", 1)
        # the lattice and the input are the fit's business
        for p in FFD_PARAMS:
            obj.setEditorMode(props.property_name(p), 2)
        for name in ("Base", "PointsSource", "Bypass"):
            if name in obj.PropertiesList:
                obj.setEditorMode(name, 2)

    def parameters(self):
        struts = next(p for p in super().parameters() if p["name"] == "struts")
        return shell_params() + [struts]

    def inputs(self, obj):
        return []  # (the surface stays where the user put it in the tree)

    def settings(self, obj):
        """The shell's settings, checked: ValueError naming the property and what is allowed."""
        values = {}
        for p in shell_params():
            value = props.get_value(obj, p)
            name = props.property_name(p["name"])
            if p["type"] == "real" and not (value > 0 if p["min_exclusive"] else value >= 0):
                raise ValueError("%s: property '%s' = %s is out of range; allowed: %s mm"
                                 % (obj.Label, name, props.value_text(p, value), p["allowed"]))
            if p["type"] == "integer" and not p["min"] <= value <= p["max"]:
                raise ValueError("%s: property '%s' = %d is out of range; allowed: %s"
                                 % (obj.Label, name, value, p["allowed"]))
            values[p["name"]] = value
        values["straight"] = obj.Struts == "straight"
        return values

    def fit(self, obj):
        """frepcore.hspline_shell_lattice's result and the model's shape for the Surface as it
        is now (made again only when the surface or a setting changed)."""
        surface = obj.Surface
        if surface is None or not H.is_hspline(surface):
            raise ValueError("%s: property 'Surface' must link an HSpline (FRep hspline > "
                             "Plane, Cylinder, Torus or From face)" % obj.Label)
        settings = self.settings(obj)
        read = H._shared(surface)
        key = (obj.Document.Name, obj.Name)
        kept = _FITS.get(key)
        if kept is not None and kept[0] is read and kept[1] == settings:
            return kept[2], kept[3]
        try:
            result = frepcore.hspline_shell_lattice(
                read, settings["thickness"], cell=settings["cell"],
                cell_type=settings["cell_type"], radius=settings["radius"],
                divisions=(settings["divisions_u"], settings["divisions_v"]),
                source=surface.Label, straight=settings["straight"])
        except ValueError as e:
            raise ValueError("%s: %s" % (obj.Label, e)) from None
        shape = frepcore.Shape(frepcore.parse_model(result["model"], obj.Label)["root"])
        _FITS[key] = (read, settings, result, shape)
        return result, shape

    def local_shape(self, obj, builder):
        return self.fit(obj)[1]

    @one_line_errors
    def execute(self, obj):
        result, _ = self.fit(obj)
        if abs(float(obj.Deviation) - result["deviation"]) > 1e-12:
            obj.Deviation = result["deviation"]
        super().execute(obj)

    def onChanged(self, obj, prop):
        # (the ffd's own reaction to a changed Base does not apply: there is none)
        if prop == "Visibility":
            super().onChanged(obj, prop)


def make_struts_along(doc, surface, thickness, cell=0.0, cell_type="octet", radius=0.0,
                      divisions=(0, 0), straight=False, name="StrutsAlong"):
    """A Struts along feature on `surface` (an hspline): recompute to see it."""
    obj = doc.addObject("Mesh::FeaturePython", name)
    StrutsAlongFeature(obj)
    if FreeCAD.GuiUp:
        import FRepViewProviders
        FRepViewProviders.ViewProviderStrutsAlong(obj.ViewObject)
    obj.Surface = surface
    obj.Thickness = thickness
    obj.Cell = cell
    obj.CellType = cell_type
    obj.Radius = radius
    obj.DivisionsU, obj.DivisionsV = divisions
    obj.Struts = "straight" if straight else "curved"
    obj.Label = "Struts along " + surface.Label
    return obj


def default_shell_thickness(surface):
    """A shell thickness sized from the hspline: a twentieth of its bounding box's longest
    side, rounded to two significant digits."""
    box = surface.Shape.BoundBox if not surface.Shape.isNull() else None
    longest = max(box.XLength, box.YLength, box.ZLength) if box else 0.0
    if not longest > 0:
        raise ValueError("%s: the surface has no extent to size a shell from" % surface.Label)
    return float("%.2g" % (longest / 20.0))


def struts_along(surface, thickness, cell=0.0, cell_type="octet", divisions=(0, 0)):
    """A Struts along feature on `surface` and its first fit: (the feature,
    frepcore.hspline_shell_lattice's dict: divisions, deviation (how closely it follows),
    size). A wrong setting raises ValueError naming it and leaves no feature behind."""
    obj = make_struts_along(surface.Document, surface, thickness, cell=cell,
                            cell_type=cell_type, divisions=divisions)
    try:
        result, _ = obj.Proxy.fit(obj)
    except ValueError:
        surface.Document.removeObject(obj.Name)
        raise
    return obj, result
