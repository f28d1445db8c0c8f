"""FRepCAD's core as a Python module: FRep solids as functions F(x, y, z) >= 0 inside.

Every node type of the registry is a function here, with the registry's parameter names::

    import frepcore as fc
    part = fc.box((2, 2, 2), corner=(-1, -1, -1)) & fc.sphere(1.3)
    for axis in ((1, 0, 0), (0, 1, 0), (0, 0, 1)):
        part = part - fc.cylinder(0.5, 0, axis=axis)     # length 0: infinite
    report = part.export("part.stl", resolution=0.02)  # checked by CGAL first
    print(report["text"])

Operators: ``a | b`` union, ``a & b`` intersection, ``a - b`` difference, ``~a``
complement. One-input operations are also methods: ``s.translate((1, 0, 0))``,
``s.rotate((0, 0, 1), 45)``, ``s.scale(2)``. Long work (``mesh``, ``export``) releases
the GIL, takes ``progress=callable(fraction) -> bool`` and raises ``Cancelled`` when the
callback returns False; a cancelled export writes no file.
"""

import inspect
import math
import os
import textwrap

from ._frepcore import Cancelled, EmptySolid, Mesh, Node, node_types, parse_model, read_mesh
from ._frepcore import parse_hyperfun
from ._frepcore import check_param, node_reference_markdown
from ._frepcore import mesh_field, vdb_grids, vdb_to_mesh, vdb_reader
from ._frepcore import Lattice, deform_mesh, deform_vdb, read_lattice, parse_lattice
from ._frepcore import read_3mf, read_3mf_beams, write_3mf, materials
from ._frepcore import HSpline, parse_hs, read_hs, read_step_summary, attach_cylinder, envelope
from ._frepcore import hspline_shell_lattice
from ._frepcore import set_threads, use_one_job_memory_policy
from ._frepcore import MeshSettings, mesh_settings_table
from ._frepcore import EXIT_STATUS, __version__
from ._frepcore import DEFAULT_CELLS  # cells along the longest side when no resolution is given

__all__ = ["Cancelled", "EmptySolid", "Mesh", "MeshSettings", "mesh_settings_table", "Node", "Shape", "node_types", "parse_model", "parse_hyperfun", "read_mesh",
           "load", "automatic_box", "NotPrintable", "from_mesh", "from_vdb", "vdb_grids",
           "vdb_to_mesh", "vdb_reader", "Lattice", "deform_mesh", "deform_vdb", "read_lattice",
           "parse_lattice", "read_3mf", "read_3mf_beams", "write_3mf", "materials", "HSpline", "parse_hs",
           "read_hs", "read_step_summary", "attach_cylinder", "envelope", "hspline_shell_lattice",
           "mesh_settings", "EXIT_STATUS",
           "exit_status_of", "progress_part"]

# Positional order of the parameters of the primitive functions, where the registry's order
# (placement first) would be awkward to call: fc.cylinder(radius, length).
_POSITIONAL = {
    "sphere": ["radius", "center"],
    "box": ["size", "corner"],
    "cylinder": ["radius", "length", "center", "axis"],
    "cone": ["radius1", "radius2", "height", "base", "axis"],
    "torus": ["major_radius", "minor_radius", "center", "axis"],
    "ellipsoid": ["radii", "center"],
    "halfspace": ["normal", "point"],
    "rotate": ["axis", "angle", "center"],
    "twist": ["rate", "axis", "center"],
    "taper": ["scale2", "length", "scale1", "axis", "start"],
}


# Older spellings of the meshing options, still accepted: keyword -> (option, value), the
# value None meaning the keyword's own.
_OLDER_KEYWORDS = {
    "sharp": ("sharp_features", None),
    "fewer_triangles": ("drop_flat_vertices", None),
    "refine_thin_parts": ("refine", "thin-parts"),
    "refine_tips": ("refine", "tips"),
}


def mesh_settings(settings=None, **options):
    """A MeshSettings from `settings` (a MeshSettings or None: the defaults) with `options`
    (the names of mesh_settings_table(), or their older spellings) set on it. An unknown name
    is a TypeError listing the allowed ones; a bad value a ValueError naming the option."""
    result = MeshSettings() if settings is None else MeshSettings(**settings.to_dict())
    refine = None
    for name, value in options.items():
        if name in _OLDER_KEYWORDS:
            option, meaning = _OLDER_KEYWORDS[name]
            if meaning is None:
                setattr(result, option, value)
            elif value and refine != "tips":  # (refine_tips wins over refine_thin_parts)
                refine = meaning
            continue
        if not hasattr(MeshSettings, name) or name.startswith("_"):
            raise TypeError("unknown meshing option '%s'; allowed: %s"
                            % (name, ", ".join(row["name"] for row in mesh_settings_table())))
        setattr(result, name, value)
    if refine is not None and "refine" not in options:
        result.refine = refine
    return result


def _with_settings_signature(function, before):
    """Gives `function` (taking **options) the signature help() and IDEs show: the
    parameters `before` as written, then each meshing option with its C++ default."""
    params = [p for name, p in inspect.signature(function).parameters.items()
              if name in before]
    params += [inspect.Parameter(row["name"], inspect.Parameter.KEYWORD_ONLY,
                                 default=row["default"]) for row in mesh_settings_table()]
    function.__signature__ = inspect.Signature(params)
    lines = [textwrap.fill("%s: %s" % (row["name"], row["help"].replace("{", "").replace(
        "}", "")), 92, initial_indent=" " * 8, subsequent_indent=" " * 12)
        for row in mesh_settings_table()]
    function.__doc__ = (function.__doc__ or "") + "\n    Meshing options:\n" + "\n".join(lines)
    return function


class NotPrintable(ValueError):
    """An export refused because the mesh failed the CGAL check; .report has the details."""

    def __init__(self, message, report):
        super().__init__(message)
        self.report = report


def exit_status_of(error):
    """frepcad's exit status (EXIT_STATUS) for the exception that ended a command: a mesh
    not printable or a solid with no point inside (EmptySolid), a cancel, bad input
    (ValueError, OSError, running out of memory), else an internal error (a bug)."""
    if isinstance(error, (NotPrintable, EmptySolid)):
        return EXIT_STATUS["not_printable"]
    if isinstance(error, (Cancelled, KeyboardInterrupt)):
        return EXIT_STATUS["cancelled"]
    if isinstance(error, (ValueError, OSError, MemoryError)):
        return EXIT_STATUS["bad_input"]
    return EXIT_STATUS["internal_error"]


class Shape:
    """An FRep solid: an immutable tree node with operators and meshing."""

    __slots__ = ("node",)

    def __init__(self, node):
        if not isinstance(node, Node):
            raise TypeError("Shape wraps a frepcore.Node, got %s" % type(node).__name__)
        self.node = node

    # -- tree ---------------------------------------------------------------------------
    @property
    def type(self):
        return self.node.type

    @property
    def params(self):
        return self.node.params

    @property
    def inputs(self):
        return [Shape(n) for n in self.node.inputs]

    def __repr__(self):
        return "<frepcore.Shape %s %s>" % (self.type, self.params)

    # -- operators ------------------------------------------------------------------------
    def __or__(self, other):
        return _flattened("union", self, other)

    def __and__(self, other):
        return _flattened("intersection", self, other)

    def __sub__(self, other):
        if self.type == "difference" and self.params["alpha"] == 1.0:
            return Shape(Node("difference", {}, self.node.inputs + [_node(other)]))
        return difference(self, other)

    def __invert__(self):
        return complement(self)

    # -- evaluation ---------------------------------------------------------------------
    def __call__(self, x, y, z):
        return self.node.value(x, y, z)

    def values(self, points):
        """F at each (x, y, z) of points, evaluated in batches without the GIL."""
        return self.node.values(points)

    def gradient(self, x, y, z):
        return self.node.gradient(x, y, z)

    def interval(self, lo, hi):
        """Bounds of F over the box [lo, hi]: lo <= hi on each axis, finite or infinite."""
        for axis, a, b in zip("xyz", lo, hi):
            if not a <= b:  # (also NaN)
                raise ValueError("interval: lo %s = %r is not <= hi %s = %r" % (axis, a, axis, b))
        return self.node.interval(lo, hi)

    def bounds(self, search=1e6, tolerance=1e-4):
        """dict(empty, bounded, unbounded_sides, box) from interval branch and bound, within
        [-search, search] on each axis, to within tolerance."""
        if not (0 < search < math.inf):
            raise ValueError("bounds: search = %r must be a finite half-width > 0" % (search,))
        if not (0 < tolerance < math.inf):
            raise ValueError("bounds: tolerance = %r must be a finite length > 0" % (tolerance,))
        return self.node.bounds(search, tolerance)

    # -- meshing and export ---------------------------------------------------------------
    def mesh(self, resolution=None, bbox=None, cells=None, progress=None, normals=False,
             settings=None, **options):
        """Polygonises the solid; bbox and resolution default to automatic_box. The meshing
        options below (or a MeshSettings as settings=) are frepcad export's flags by the same
        names. The mesh's thin_parts dict counts the grid edges where parts thinner than a
        cell passed between the grid's points: 'solid' left out and 'gaps' closed with no
        surface near, 'tips' of creases cut short; 'example' is a point on one; with refine,
        'refined_cubes' counts the cubes meshed again at half a cell, and with refine_levels
        2 or 3 'refined_levels' and 'refined_deeper_cubes' those below. With
        straighten_creases the mesh's straightened says {'merged', 'flipped', 'seconds'}."""
        box, cell = automatic_box(self, resolution=resolution, bbox=bbox, cells=cells)
        return self.node.mesh(box, cell, progress, normals, mesh_settings(settings, **options))

    def section(self, origin=(0, 0, 0), normal=(0, 0, 1), u=None, cells=256, bbox=None,
                progress=None):
        """Where the plane through origin with this normal cuts the solid: a list of
        (points, closed) polylines, the solid on the left of each seen against the normal
        (holes turn the other way). u: the plane's first axis (default: one at right angles
        to the normal); the grid has `cells` cells along the longer side of the solid's box
        (or bbox) as the plane sees it. [] where the plane misses the solid."""
        n = _unit(normal, "normal")
        if u is None:  # the axis least along the normal, made perpendicular to it
            k = min(range(3), key=lambda i: abs(n[i]))
            u = [0.0, 0.0, 0.0]
            u[k] = 1.0
        u = [a - b * sum(x * y for x, y in zip(u, n)) for a, b in zip(u, n)]
        u = _unit(u, "u (along the normal)")
        v = (n[1] * u[2] - n[2] * u[1], n[2] * u[0] - n[0] * u[2], n[0] * u[1] - n[1] * u[0])
        box, _ = automatic_box(self, bbox=bbox, cells=cells)
        side = max(box[1][i] - box[0][i] for i in range(3))
        if not (isinstance(cells, int) and 2 <= cells <= 4096):
            raise ValueError("section: cells %r is not allowed; a whole number from 2 to 4096"
                             % (cells,))
        return self.node.section(tuple(origin), tuple(u), v, box, side / cells, progress)

    def export(self, path, resolution=None, bbox=None, cells=None, format="", check=True,
               progress=None, force=False, settings=None, **options):
        """Meshes, checks with CGAL and writes path atomically (libcore's export pipeline,
        the same as `frepcad export`, whose flags the meshing options below are); returns
        the check report (a dict with 'text', and 'thin_parts' as in mesh()). With
        straighten_creases the report's 'straightened' has 'merged', 'flipped' and
        'seconds'; with a tolerance it has 'triangles_before_simplify' and
        'largest_distance'.

        Raises NotPrintable (nothing written) when the check fails and force is not given,
        Cancelled when progress returns False (nothing written).
        """
        report = self.node.export(path, bbox=bbox, resolution=resolution, cells=cells,
                                  format=format, check=check, force=force, progress=progress,
                                  settings=mesh_settings(settings, **options))
        if check and not report["printable"] and not force:
            raise NotPrintable("%s: not written, the mesh is not printable: %s"
                               % (path, "; ".join(report["reasons"])), report)
        return report if check else None

    def export_beams(self, path, resolution=None, bbox=None, cells=None, unit="mm",
                     progress=None, force=False, settings=None, **options):
        """A strut lattice's struts as a 3MF beam lattice (`frepcad export --beams`): this
        shape must be a strut lattice cut to a part, or an infill with a strut lattice
        (lattice CELL_struts). The part's mesh clips the beams, an infill's skin is a mesh
        beside them. Returns dict(written, beams, vertices, clip_triangles, skin_triangles,
        printable, text, notes, seconds).

        Raises NotPrintable (nothing written) when a mesh of the file fails the check and
        force is not given, ValueError for a shape that is no strut lattice.
        """
        report = self.node.export_beams(path, bbox=bbox, resolution=resolution, cells=cells,
                                        unit=unit, force=force, progress=progress,
                                        settings=mesh_settings(settings, **options))
        if not report["written"]:
            raise NotPrintable("%s: not written, a mesh of the beam lattice's file is not "
                               "printable" % path, report)
        return report

    def deform(self, lattice, struts="curved"):
        """This solid bent by a Lattice: the ffd node with the lattice's box, divisions and
        points (pulled back through the lattice's inverse, so it has no gaps). struts:
        "straight" keeps a strut lattice's struts straight between their ends' images."""
        d = lattice.divisions
        return Shape(Node("ffd", {"rest_min": lattice.rest_min, "rest_max": lattice.rest_max,
                                  "divisions_x": d[0], "divisions_y": d[1], "divisions_z": d[2],
                                  "points": lattice.points, "struts": struts}, [self.node]))

    def to_json(self, bbox=None, resolution=None, description=""):
        return self.node.to_json(bbox, resolution, description)

    def to_vdb(self, path, voxel=None, bbox=None, cells=None, half_width=3.0, progress=None,
               fog=False):
        """Writes the solid as an OpenVDB level set (one float grid, 'surface'), or with
        fog=True a fog volume (0 outside, 1 inside); the box and voxel size follow
        automatic_box as for a mesh (voxel = the cell size). Returns the grid's description:
        a dict as vdb_grids() gives."""
        box, cell = automatic_box(self, resolution=voxel, bbox=bbox, cells=cells)
        return self.node.to_vdb(path, box, cell, half_width, progress, fog)


def from_mesh(source, method="exact", voxel=0.0, name="mesh"):
    """A closed triangle mesh as a solid (its signed distance, positive inside).

    source: a mesh file's path (.stl, .obj, .ply; the shape is then a `mesh_sdf` node that a
    model file can hold), a frepcore.Mesh, or (points, triangles). method 'exact' measures
    the distance to the triangles themselves; 'grid' samples them once into an OpenVDB level
    set at `voxel` (0: 1/256 of the mesh's largest side), faster to evaluate and tolerant of
    overlapping shells. Open meshes are refused (OSError) with the count of their holes' edges.
    """
    if isinstance(source, (str, os.PathLike)):
        return Shape(Node("mesh_sdf", {"path": os.path.abspath(source), "method": method,
                                       "voxel": voxel}, [], name))
    if not isinstance(source, Mesh):
        points, triangles = source
        source = Mesh(points, triangles)
    return Shape(mesh_field(source, method, voxel, name))


def from_vdb(path, grid="", interpolation="linear", iso=0.0):
    """A float or double grid of an OpenVDB file as a solid (a `vdb_grid` node): a level set
    is inside below iso, any other grid above it. grid: its name ('' : the first scalar
    grid); interpolation 'linear' or 'quadratic'."""
    return Shape(Node("vdb_grid", {"path": os.path.abspath(path), "grid": grid,
                                   "interpolation": interpolation, "iso": iso}, [], "vdb_grid"))


def _node(value):
    if isinstance(value, Shape):
        return value.node
    if isinstance(value, Node):
        return value
    raise TypeError("expected a frepcore.Shape, got %s" % type(value).__name__)


def _flattened(type_id, a, b):
    """a | b | c gives one union of three, not a union of a union."""
    inputs = []
    for s in (a, b):
        n = _node(s)
        if n.type == type_id and n.params["alpha"] == 1.0:
            inputs.extend(n.inputs)
        else:
            inputs.append(n)
    return Shape(Node(type_id, {}, inputs))


def progress_part(progress, start, share):
    """The part [start, start + share) of a progress(fraction) callback's bar as a callback of
    its own (None for None): Python's side of libcore's one progress type (base/progress.h),
    so that no caller scales fractions by hand."""
    if progress is None:
        return None
    return lambda f: progress(start + share * f)


def _unit(vector, what):
    """vector scaled to length 1; ValueError naming `what` for a zero or non-finite one."""
    v = [float(c) for c in vector]
    length = math.sqrt(sum(c * c for c in v))
    if len(v) != 3 or not (length > 0) or not math.isfinite(length):
        raise ValueError("section: %s %r is not a direction; three finite numbers, not all 0"
                         % (what, tuple(vector)))
    return [c / length for c in v]


def automatic_box(shape, resolution=None, bbox=None, cells=None, padding_cells=1.5,
                  bounds=None):
    """The meshing box and cell size for shape: libcore's box policy (the one `frepcad
    export` and every export use).

    bbox defaults to the solid's interval bounds, padded so the surface never touches the
    box; resolution (cell size) defaults to the longest side over `cells` (default 128).
    Raises ValueError for an empty or unbounded solid when bbox is not given. `bounds` may
    pass a result of shape.bounds() already at hand.
    """
    if bbox is not None:
        bbox = _box_pair(bbox)
    return _node(shape).choose_box(bbox=bbox, resolution=resolution or None, cells=cells,
                                   padding_cells=padding_cells, bounds=bounds)


def _box_pair(bbox):
    if len(bbox) == 6:
        return list(bbox[:3]), list(bbox[3:])
    if len(bbox) == 2:
        return list(bbox[0]), list(bbox[1])
    raise ValueError("bounding box: needs (xmin, ymin, zmin, xmax, ymax, zmax) or (min, max)")


def load(path):
    """Reads a .json model or a HyperFun program (.hf): (Shape, export settings dict with bbox
    and resolution). path: a str or os.PathLike."""
    path = os.fspath(path)
    with open(path, encoding="utf-8") as f:
        text = f.read()
    if path.lower().endswith(".hf"):
        model = parse_hyperfun(text, path)
    else:
        model = parse_model(text, path, os.path.dirname(os.path.abspath(path)))
    return Shape(model["root"]), {"bbox": model["bbox"], "resolution": model["resolution"]}


def _make_function(info):
    type_id = info["type"]
    names = [p["name"] for p in info["params"]]
    order = _POSITIONAL.get(type_id, names)
    min_in, max_in = info["inputs"]["min"], info["inputs"]["max"]  # max None: any number

    def params_from(args, kwargs):
        if len(args) > len(order):
            raise TypeError("%s() takes at most %d parameters (%s), got %d"
                            % (type_id, len(order), ", ".join(order), len(args)))
        params = dict(zip(order, args))
        for k, v in kwargs.items():
            if k in params:
                raise TypeError("%s(): parameter '%s' given twice" % (type_id, k))
            params[k] = v
        return params

    if min_in == 0:
        def make(*args, **kwargs):
            return Shape(Node(type_id, params_from(args, kwargs), [], type_id))
    elif max_in == 1:
        def make(shape, *args, **kwargs):
            return Shape(Node(type_id, params_from(args, kwargs), [_node(shape)], type_id))
    else:
        def make(*shapes, **kwargs):
            return Shape(Node(type_id, kwargs, [_node(s) for s in shapes], type_id))

    # the parameters in their positional order (keyword-only after it), as help() shows them
    by_name = {p["name"]: p for p in info["params"]}
    ordered = [by_name[n] for n in order] + [p for p in info["params"] if p["name"] not in order]
    lines = ["%s: %s" % (type_id, info["doc"]), "", "Formula: " + info["formula"], "",
             "Parameters:"]
    for p in ordered:
        unit = " [%s]" % p["unit"] if p["unit"] else ""
        lines.append("  %s%s = %r: %s (allowed: %s)" % (p["name"], unit, p["default"], p["doc"],
                                                        p["allowed"]))
    P = inspect.Parameter
    if min_in == 0:
        head, kind = [], P.POSITIONAL_OR_KEYWORD
    elif max_in == 1:
        head, kind = [P("shape", P.POSITIONAL_ONLY)], P.POSITIONAL_OR_KEYWORD
    else:
        head, kind = [P("shapes", P.VAR_POSITIONAL)], P.KEYWORD_ONLY
    make.__signature__ = inspect.Signature(head + [
        P(p["name"], kind if p["name"] in order else P.KEYWORD_ONLY, default=p["default"])
        for p in ordered])
    make.__name__ = type_id
    make.__qualname__ = type_id
    make.__doc__ = "\n".join(lines)
    return make


def _install_node_functions():
    for info in node_types():
        fn = _make_function(info)
        type_id, inputs = info["type"], info["inputs"]
        globals()[type_id] = fn
        __all__.append(type_id)
        if inputs["min"] == 1 and inputs["max"] == 1 and type_id != "complement":
            setattr(Shape, type_id, fn)


_install_node_functions()


_with_settings_signature(Shape.mesh, ("self", "resolution", "bbox", "cells", "progress",
                                      "normals", "settings"))
_with_settings_signature(Shape.export, ("self", "path", "resolution", "bbox", "cells", "format",
                                        "check", "progress", "force", "settings"))
