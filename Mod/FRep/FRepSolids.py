"""Any FreeCAD solid or closed mesh as an FRep input: a signed-distance field.

A Part shape with solids (a PartDesign Body's Tip, a Part boolean, an imported STEP) is
tessellated by MeshPart at the document's solid tolerance, a Mesh feature is taken as it is,
and either becomes frepcore's exact signed distance to its triangles (CGAL AABB tree), so the
FRep solid is the tessellated part at any meshing resolution. A mesh that is not clean enough
for the exact distance (self-intersecting triangles) falls back to an OpenVDB level set.

Fields are cached per source object and rebuilt only when the source's geometry changes: a
recompute that changes only FRep parameters (an infill's cell size) reuses the field.
"""

import hashlib
import os
import tempfile

import FreeCAD

from FRepPaths import frepcore

TOLERANCE_KEY = "FRepSolidTolerance"  # in the document's Meta: mm, or absent for automatic
RELATIVE_TOLERANCE = 1e-3  # automatic: this fraction of the shape's bounding box diagonal
MIN_TOLERANCE = 1e-4
ANGULAR_DEFLECTION = 0.35  # radians between facet normals along a curved face

_CACHE = {}  # (document, object) -> (fingerprint, Shape)
BUILDS = []  # (document, object) of each field built, newest last (for tests and timing)
_MAX_CACHED = 16


def is_solid_input(obj):
    """A Mesh feature, or an object whose Shape holds at least one solid."""
    if obj.isDerivedFrom("Mesh::Feature"):
        return True
    shape = getattr(obj, "Shape", None)
    return obj.isDerivedFrom("Part::Feature") and shape is not None and len(shape.Solids) > 0


def solid_tolerance(doc, shape=None):
    """The chord tolerance (mm) solids are tessellated at: the document's setting, else
    RELATIVE_TOLERANCE of the shape's diagonal."""
    value = doc.Meta.get(TOLERANCE_KEY)
    if value:
        return float(value)
    diagonal = shape.BoundBox.DiagonalLength if shape is not None else 100.0
    return max(MIN_TOLERANCE, RELATIVE_TOLERANCE * diagonal)


def set_solid_tolerance(doc, mm):
    """Sets the document's tessellation tolerance for solid inputs (None: automatic) and
    recomputes the FRep features that use solids."""
    if mm is not None and not (mm > 0):
        raise ValueError("%s: solid tolerance %r is not allowed; allowed: a length > 0 mm, or "
                         "None for automatic" % (doc.Label, mm))
    meta = dict(doc.Meta)
    if mm is None:
        meta.pop(TOLERANCE_KEY, None)
    else:
        meta[TOLERANCE_KEY] = repr(float(mm))
    doc.Meta = meta
    for obj in doc.Objects:
        if is_solid_input(obj):
            for user in obj.InList:
                user.touch()


def _part_fingerprint(shape, tolerance):
    # Every vertex (placed), every face's area and the volume: an edit that leaves all of
    # them unchanged does not change the solid. (Not the BREP text: it also holds the
    # triangulations that tessellating or displaying the shape attaches to its faces.)
    numbers = [shape.Volume, shape.Area, len(shape.Edges)]
    numbers += [c for v in shape.Vertexes for c in (v.Point.x, v.Point.y, v.Point.z)]
    numbers += [f.Area for f in shape.Faces]
    digest = hashlib.sha1(repr(numbers).encode("ascii")).hexdigest()
    return ("part", digest, tolerance)


def _mesh_fingerprint(mesh):
    b = mesh.BoundBox
    return ("mesh", mesh.CountPoints, mesh.CountFacets, round(mesh.Volume, 9),
            round(mesh.Area, 9), b.XMin, b.YMin, b.ZMin, b.XMax, b.YMax, b.ZMax)


def as_frepcore_mesh(freecad_mesh):
    """A FreeCAD mesh into frepcore through a binary STL (the fast hand-over)."""
    fd, path = tempfile.mkstemp(suffix=".stl", prefix="frep-solid-")
    os.close(fd)
    try:
        freecad_mesh.write(path)
        return frepcore.read_mesh(path)
    finally:
        os.remove(path)


# frepcore's words for a mesh whose only defect is that its triangles meet: its shells still
# bound an inside, which a level set can take.
_OVERLAPPING = "its triangles intersect each other"
# where frepcore's reason ends and its advice for the command line begins
_CLI_ADVICE = "; the exact distance needs"


def _distance_field(obj, mesh, voxel):
    name = "%s (%s)" % (obj.Label, obj.TypeId)
    try:
        return frepcore.from_mesh(mesh, "exact", 0.0, name)
    except OSError as e:
        reason = str(e).split(_CLI_ADVICE)[0]
        if _OVERLAPPING not in reason:
            raise OSError("%s: cannot be an FRep input: %s; select it and use FRep > Repair mesh "
                          "to mend it (FRep > Printability lists every defect)"
                          % (obj.Label, reason)) from None
        FreeCAD.Console.PrintWarning(
            "%s: its triangles intersect each other; using an OpenVDB level set (voxel %g mm) "
            "instead of the exact distance (FRep > Repair mesh removes the intersections)\n"
            % (obj.Label, voxel))
        return frepcore.from_mesh(mesh, "grid", voxel, name)


def solid_shape(obj):
    """The object's solid as a frepcore.Shape in document coordinates (cached)."""
    key = (obj.Document.Name, obj.Name)
    if obj.isDerivedFrom("Mesh::Feature"):
        mesh = obj.Mesh  # points already placed
        if mesh.CountFacets == 0:
            raise ValueError("%s: the mesh is empty" % obj.Label)
        fingerprint = _mesh_fingerprint(mesh)
        tolerance = None
    else:
        shape = obj.Shape
        if not shape.Solids:
            raise ValueError("%s (%s) has no solid; FRep inputs are FRep features, solids "
                             "(Part, PartDesign, imported STEP) and closed meshes"
                             % (obj.Label, obj.TypeId))
        tolerance = solid_tolerance(obj.Document, shape)
        fingerprint = _part_fingerprint(shape, tolerance)
    cached = _CACHE.get(key)
    if cached is not None and cached[0] == fingerprint:
        return cached[1]
    if tolerance is None:
        source = as_frepcore_mesh(mesh)
        voxel = max(mesh.BoundBox.DiagonalLength / 400.0, MIN_TOLERANCE)
    else:
        # A feature that can tessellate its own solid faster and closer to it than MeshPart
        # (an hspline: its exact surface, evaluated) offers solid_mesh(obj, tolerance).
        own = getattr(getattr(obj, "Proxy", None), "solid_mesh", None)
        source = own(obj, tolerance) if own is not None else None
        if source is None:
            import MeshPart
            tessellated = MeshPart.meshFromShape(Shape=shape, LinearDeflection=tolerance,
                                                 AngularDeflection=ANGULAR_DEFLECTION,
                                                 Relative=False)
            source = as_frepcore_mesh(tessellated)
        voxel = max(2 * tolerance, shape.BoundBox.DiagonalLength / 400.0)
    field = _distance_field(obj, source, voxel)
    BUILDS.append(key)
    del BUILDS[:-100]
    if len(_CACHE) >= _MAX_CACHED:
        _CACHE.pop(next(iter(_CACHE)))
    _CACHE[key] = (fingerprint, field)
    return field

