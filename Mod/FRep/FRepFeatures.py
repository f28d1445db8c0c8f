"""The FRep feature classes: one per registry node type, generated at import.

Each feature is a Mesh::FeaturePython whose state is entirely its properties: the registry's
parameters (typed, with units, ranges and tooltips), its inputs (a link `Base` for one-input
operations, a link list `Shapes` for the others), `Bypass` on operations, and the Placement.
Its Mesh property holds the preview at the document's preview resolution; a hidden feature
keeps an empty one until it is shown again.

Scripting:
    import FRepFeatures as F
    s = F.make("sphere", doc, radius=1.3)
    b = F.make("box", doc, corner=(-1, -1, -1), size=(2, 2, 2))
    i = F.make("intersection", doc, inputs=[b, s])
    doc.recompute()
"""

import FreeCAD

import FRepMeshing
import FRepPoints
import FRepProperties as props
import FRepTree
from FRepErrors import FeatureError, one_line_errors
from FRepProxy import FeatureProxy
from FRepPaths import frepcore

NODE_TYPES = {t["type"]: t for t in frepcore.node_types()}

# (document name, object name) of each execute, in order: lets tests and benchmarks count
# exactly what a change recomputed. Bounded so a long session does not grow it forever.
EXECUTIONS = []
_MAX_LOG = 10000


def input_property(info):
    """'Base' (one input), 'Shapes' (several) or None (a primitive)."""
    if info["inputs"]["max"] == 0:
        return None
    return "Base" if info["inputs"]["max"] == 1 else "Shapes"


def linked_inputs(obj):
    prop = input_property(NODE_TYPES[obj.Proxy.FREP_TYPE])
    if prop == "Base":
        return [obj.Base] if obj.Base is not None else []
    if prop == "Shapes":
        return list(obj.Shapes)
    return []


def depends_on(obj, target):
    """Whether obj reaches target through its links (safe on cyclic graphs)."""
    seen, todo = set(), [obj]
    while todo:
        o = todo.pop()
        if o == target:
            return True
        if o.Name in seen:
            continue
        seen.add(o.Name)
        todo.extend(o.OutList)
    return False


def cycle_offenders(obj, inputs):
    return [i for i in inputs if i is not None and depends_on(i, obj)]


def cycle_message(obj, offenders):
    return ("%s: refused to link %s: %s already depend%s on %s, so the link would make a "
            "cycle" % (obj.Label, ", ".join("'%s'" % o.Label for o in offenders),
                       "they" if len(offenders) > 1 else "it",
                       "" if len(offenders) > 1 else "s", obj.Label))


def set_inputs(obj, inputs):
    """Links inputs to an operation; raises ValueError (and links nothing) on a cycle."""
    offenders = cycle_offenders(obj, inputs)
    if offenders:
        raise ValueError(cycle_message(obj, offenders))
    info = NODE_TYPES[obj.Proxy.FREP_TYPE]
    prop = input_property(info)
    if prop is None:
        raise ValueError("%s: a %s takes no inputs" % (obj.Label, info["type"]))
    if prop == "Base":
        if len(inputs) != 1:
            raise ValueError("%s: property 'Base' takes exactly one input, got %d"
                             % (obj.Label, len(inputs)))
        obj.Base = inputs[0]
    else:
        obj.Shapes = list(inputs)


class FRepFeature(FeatureProxy):
    """Proxy of every FRep feature; subclasses only set FREP_TYPE."""

    FREP_TYPE = None

    def setup(self, obj):
        """Adds the properties the registry defines (also to documents saved before a
        parameter existed)."""
        info = NODE_TYPES[self.FREP_TYPE]
        for p in info["params"]:
            props.add_param_property(obj, p)
            source = FRepPoints.source_property(p["name"])
            if p["type"] == "points" and not p.get("follows") and \
                    source not in obj.PropertiesList:
                obj.addProperty("App::PropertyLink", source, props.INPUT_GROUP,
                                FRepPoints.source_tooltip(p))
        prop = input_property(info)
        if prop == "Base" and "Base" not in obj.PropertiesList:
            obj.addProperty("App::PropertyLink", "Base", props.INPUT_GROUP,
                            "The solid this operation applies to." if info["inputs"]["min"]
                            else "Optional input field; see the node's documentation.")
        elif prop == "Shapes" and "Shapes" not in obj.PropertiesList:
            obj.addProperty("App::PropertyLinkList", "Shapes", props.INPUT_GROUP,
                            "The solids combined, in order (at least %d)." % info["inputs"]["min"])
        if info["inputs"]["min"] > 0 and "Bypass" not in obj.PropertiesList:
            obj.addProperty("App::PropertyBool", "Bypass", props.PARAM_GROUP,
                            "Pass the first input through unchanged, ignoring this operation.")

    # -- what the view provider and the task panel ask the object (they never import this
    #    module: a view provider asks its object) --
    def category(self):
        return NODE_TYPES[self.FREP_TYPE]["category"]

    def inputs(self, obj):
        return linked_inputs(obj)

    def parameters(self):
        """The registry's parameters of this type (dicts as frepcore.node_types gives)."""
        return NODE_TYPES[self.FREP_TYPE]["params"]

    def blend_guide(self, obj):
        """A blend's guide (FRepBlendReach.guide); None for other features."""
        import FRepBlendReach
        return FRepBlendReach.guide(obj) if FRepBlendReach.is_blend(obj) else None

    def set_blend_reach(self, obj, name, point):
        import FRepBlendReach
        return FRepBlendReach.set_reach(obj, name, point)

    # -- the tree ------------------------------------------------------------------------------
    def local_shape(self, obj, builder):
        """This node over its inputs' shapes, before its own Placement."""
        info = NODE_TYPES[self.FREP_TYPE]
        params = {p["name"]: self.param_value(obj, p) for p in info["params"]}
        inputs = linked_inputs(obj)
        prop = input_property(info)
        least = info["inputs"]["min"]
        if prop and len(inputs) < least:
            raise ValueError("%s: property '%s' needs at least %d input%s (FRep features, "
                             "Part primitives, solids or meshes); it has %d" % (
                                 obj.Label, prop, least, "s" if least > 1 else "",
                                 len(inputs)))
        if least > 0 and obj.Bypass:
            return builder.shape(inputs[0])
        nodes = [builder.shape(i).node for i in inputs]
        try:
            node = frepcore.Node(self.FREP_TYPE, params, nodes, obj.Label)
        except ValueError as e:
            raise ValueError(props.in_property_terms(str(e), obj.Label, info)) from None
        return frepcore.Shape(node)

    def param_value(self, obj, param):
        """A parameter's value: from its property, or for a point list from the object its
        `<Name>Source` links (the list property is then not used, so not checked)."""
        if param["type"] == "points" and param.get("follows"):
            # taken from the followed parameter's source when it has one (rotations of a
            # Draft array's copies), else from its own list
            linked = getattr(obj, FRepPoints.source_property(param["follows"]), None)
            if linked is not None:
                return FRepPoints.position_rotations(obj, linked)
            return props.check_value(obj, self.FREP_TYPE, param)
        source = FRepPoints.source_property(param["name"])
        if param["type"] == "points" and getattr(obj, source, None) is not None:
            if param.get("path", False):
                arcs = getattr(obj, "Segments", "lines") == "arcs"
                return FRepPoints.path_points(obj, source, getattr(obj, source), arcs)
            return FRepPoints.position_points(obj, source, getattr(obj, source))
        return props.check_value(obj, self.FREP_TYPE, param)

    @one_line_errors
    def execute(self, obj):
        EXECUTIONS.append((obj.Document.Name, obj.Name))
        del EXECUTIONS[:-_MAX_LOG]
        builder = FRepTree.Builder()
        builder.stack.append(obj)
        shape = self.local_shape(obj, builder)
        # Bounds are cheap and find empty results even for hidden features.
        bounds = shape.bounds()
        FRepMeshing.require_not_empty(obj.Label, bounds)
        if not obj.Visibility:
            if obj.Mesh.CountFacets:
                FRepMeshing.set_mesh(obj, _empty_mesh())
            return
        box, cell = FRepMeshing.display_box(obj.Label, shape,
                                            FRepMeshing.preview_cells(obj.Document), bounds)
        _warn_detail_below(obj, cell)
        mesh = FRepMeshing.run_with_progress(
            "Meshing the preview of %s" % obj.Label,
            lambda progress: _preview_or_cancel(obj, shape, box, cell, progress))
        FRepMeshing.set_mesh(obj, FRepMeshing.to_freecad_mesh(mesh))

    def onBeforeChange(self, obj, prop):
        # The links before an assignment, to put back if it would make a cycle. Transient:
        # used within the one assignment, never saved.
        if prop in ("Base", "Shapes") and prop == input_property(NODE_TYPES[self.FREP_TYPE]):
            self._links_before = getattr(obj, prop)

    def onChanged(self, obj, prop):
        if "Restore" in obj.State:
            return
        if prop in ("Base", "Shapes") and prop == input_property(NODE_TYPES[self.FREP_TYPE]):
            offenders = cycle_offenders(obj, linked_inputs(obj))
            if offenders:
                message = cycle_message(obj, offenders)
                before = getattr(self, "_links_before", None)
                if before is None or (prop == "Shapes" and cycle_offenders(obj, before)):
                    kept = [i for i in linked_inputs(obj) if i not in offenders]
                    before = (kept[0] if kept else None) if prop == "Base" else kept
                setattr(obj, prop, before)
                FreeCAD.Console.PrintError(message + "\n")
        elif prop == "Visibility" and obj.Visibility and obj.Mesh.CountFacets == 0:
            _refresh_preview_later(obj)


def _warn_detail_below(obj, cell):
    """A warning where a length that sets the solid's detail (an infill's skin and sheets) is
    below the preview's cell: the preview then shows specks, not the part."""
    if obj.Proxy.FREP_TYPE != "infill":
        return
    for name in ("Wall", "Thickness"):
        value = getattr(obj, name).Value
        if not 0 < value < cell:
            continue
        FreeCAD.Console.PrintWarning(
            "%s: property '%s' = %.3g mm is below the preview's cell (%.3g mm): the preview "
            "shows it broken; the export meshes finer (or raise FRep > Preview quality)\n"
            % (obj.Label, name, value, cell))


def _preview_or_cancel(obj, shape, box, cell, progress):
    try:
        return shape.node.mesh(box, cell, progress)
    except frepcore.Cancelled:
        raise FeatureError("%s: the preview was cancelled; lower the preview quality (FRep > "
                           "Preview quality) or hide the feature, then recompute" % obj.Label)


def _empty_mesh():
    import Mesh
    return Mesh.Mesh()


def _refresh_preview_later(obj):
    """A hidden feature has no preview; build it when shown, without touching dependents."""
    if "Invalid" in obj.State:
        return
    if FreeCAD.GuiUp:
        from PySide import QtCore
        QtCore.QTimer.singleShot(0, lambda: obj.recompute() if obj.Document else None)
    else:
        obj.recompute()


def _generate_feature_classes():
    classes = {}
    for type_id in NODE_TYPES:
        name = props.type_class_name(type_id)
        cls = type(name, (FRepFeature,), {"FREP_TYPE": type_id,
                                          "__doc__": NODE_TYPES[type_id]["doc"],
                                          "__module__": __name__})
        globals()[name] = cls
        classes[type_id] = cls
    return classes


FEATURE_CLASSES = _generate_feature_classes()


# Lengths a feature made on inputs takes from their size, as fractions of the smallest side of
# their bounding box, instead of the registry's defaults (which suit a part a few units
# across): an infill of a 40 x 25 x 12 mm part gets a 0.48 mm skin, not 0.1 mm.
SIZED_FROM_INPUTS = {
    "infill": {"wall": 0.04, "cell": 0.3},
    "offset": {"distance": 0.05},
    "shell": {"thickness": 0.05},
}
# An infill's cells are at least this many of the preview's cells (the part's longest side
# over the preview quality), and its sheets this fraction of a cell: sheets a preview cell and
# a half across, which the preview shows as sheets rather than specks. (A sheet much thicker
# than a sixth of its cell fills the cell: the gyroid's |g| is below 1.5 everywhere.)
INFILL_CELL_PREVIEW_CELLS = 10
INFILL_SHEET_OF_CELL = 0.15
# An infill's drain holes are this fraction of a cell across.
INFILL_DRAIN_OF_CELL = 0.5


def inputs_extent(inputs):
    """(smallest, longest side) of the inputs' joint bounding box, or None when it is not
    known (an unbounded input)."""
    box = FreeCAD.BoundBox()
    for i in inputs:
        shape = getattr(i, "Shape", None)
        mesh = getattr(i, "Mesh", None)
        if i.isDerivedFrom("Part::Feature") and shape is not None and shape.BoundBox.isValid():
            box.add(shape.BoundBox)
        elif mesh is not None and mesh.CountFacets and not hasattr(i, "Proxy"):
            box.add(mesh.BoundBox)
        else:
            try:
                b = FRepTree.shape_of(i).bounds()
            except ValueError:
                return None
            if not b["bounded"] or b["empty"]:
                return None
            (x0, y0, z0), (x1, y1, z1) = b["box"]
            box.add(FreeCAD.BoundBox(x0, y0, z0, x1, y1, z1))
    if not box.isValid():
        return None
    sides = (box.XLength, box.YLength, box.ZLength)
    return min(sides), max(sides)


def size_from_inputs(obj, type_id, inputs, given=()):
    """Sets the lengths of SIZED_FROM_INPUTS (and an infill's sheet thickness) from the
    inputs' size, leaving those in `given` as they are."""
    extent = inputs_extent(inputs) if type_id in SIZED_FROM_INPUTS else None
    if extent is None or not extent[0] > 0:
        return
    smallest, longest = extent
    by_name = {p["name"]: p for p in NODE_TYPES[type_id]["params"]}
    values = {name: fraction * smallest
              for name, fraction in SIZED_FROM_INPUTS[type_id].items() if name not in given}
    if type_id == "infill":
        preview_cell = longest / FRepMeshing.preview_cells(obj.Document)
        if "cell" in values:
            values["cell"] = max(values["cell"], INFILL_CELL_PREVIEW_CELLS * preview_cell)
        if "thickness" not in given and "level" not in given:
            cell = values.get("cell", props.get_value(obj, by_name["cell"]))
            values["thickness"] = INFILL_SHEET_OF_CELL * cell
        if "drain_diameter" not in given:
            # wide enough to meet both of a sheet lattice's labyrinths
            cell = values.get("cell", props.get_value(obj, by_name["cell"]))
            values["drain_diameter"] = INFILL_DRAIN_OF_CELL * cell
    for name, value in values.items():
        props.set_value(obj, by_name[name], float("%.3g" % value))


def make(type_id, doc=None, inputs=(), name=None, hide_inputs=True, sized=False, **params):
    """Adds an FRep feature of a registry type; params use the registry's names. With sized,
    the lengths SIZED_FROM_INPUTS names not among params come from the inputs' size (what
    the toolbar commands do)."""
    if type_id not in NODE_TYPES:
        raise ValueError("unknown FRep node type '%s'; known types: %s"
                         % (type_id, ", ".join(NODE_TYPES)))
    doc = doc or FreeCAD.ActiveDocument
    info = NODE_TYPES[type_id]
    obj = doc.addObject("Mesh::FeaturePython", name or props.type_class_name(type_id))
    FEATURE_CLASSES[type_id](obj)
    if FreeCAD.GuiUp:
        import FRepViewProviders
        FRepViewProviders.ViewProviderFRep(obj.ViewObject)
    by_name = {p["name"]: p for p in info["params"]}
    for key, value in params.items():
        if key not in by_name:
            raise ValueError("%s: unknown parameter '%s'; parameters of %s: %s"
                             % (obj.Label, key, type_id, ", ".join(by_name)))
        props.set_value(obj, by_name[key], value)
    if inputs:
        set_inputs(obj, list(inputs))
        if sized:
            size_from_inputs(obj, type_id, inputs, given=params)
        if hide_inputs:
            for i in inputs:
                i.Visibility = False
    return obj
