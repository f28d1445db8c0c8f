"""Repair and the printability report for any mesh in a FreeCAD document (Mesh features,
Polygonize results, imported STL/3MF): the work is libcore's (docs/manufacturing.md); this
module hands meshes over and makes the document objects.

A repair never changes its input: the repaired mesh is a new Mesh feature beside it (one undo
step, made by the command), and the input is hidden as Part's booleans hide theirs.
"""

import FreeCAD

import FRepMeshing
from FRepPaths import frepcore

THIN_COLOR = (0.9, 0.1, 0.1)
SOUND_COLOR = (0.75, 0.75, 0.75)


def is_mesh_object(obj):
    """A document object holding a mesh (Mesh::Feature and its Python subclasses)."""
    return obj is not None and obj.isDerivedFrom("Mesh::Feature")


def frepcore_mesh(obj):
    """The object's mesh as a frepcore.Mesh, in world coordinates (its placement applied)."""
    if not is_mesh_object(obj):
        raise ValueError("%s is not a mesh; select a Mesh feature (an imported STL, 3MF, OBJ "
                         "or PLY, or a Polygonize result)" % obj.Label)
    points, facets = obj.Mesh.Topology
    if not facets:
        raise ValueError("%s: the mesh has no triangles" % obj.Label)
    return frepcore.Mesh([(p.x, p.y, p.z) for p in points], [tuple(f) for f in facets])


def repair(obj, rebuild="auto", voxel=0.0, progress=None, max_deviation=-1.0,
           allow_more_pieces=False):
    """Repairs the mesh of `obj` into a new Mesh feature '<label> repaired'; returns (the new
    object, or None when the result is still not printable or not faithful to the input: more
    pieces, or farther than max_deviation from it; the report dict). The input is hidden only
    when the repair succeeds."""
    mesh = frepcore_mesh(obj)

    def work(tick):
        try:
            return mesh.repair(rebuild=rebuild, voxel=voxel, max_deviation=max_deviation,
                               allow_more_pieces=allow_more_pieces, name=obj.Label,
                               progress=tick)
        except frepcore.Cancelled:
            raise RuntimeError("repair of %s cancelled; nothing changed" % obj.Label)

    if progress is not None:
        fixed, report = work(progress)
    else:
        fixed, report = FRepMeshing.run_with_progress("Repairing %s" % obj.Label, work)
    if not report["accepted"]:
        return None, report
    doc = obj.Document
    out = doc.addObject("Mesh::Feature", "Repaired")
    out.Label = obj.Label + " repaired"
    out.Mesh = FRepMeshing.to_freecad_mesh(fixed)
    if FreeCAD.GuiUp and getattr(obj, "ViewObject", None) is not None:
        obj.ViewObject.Visibility = False
    return out, report


def printability(obj, min_wall=None, material=None, density=0.0, up=(0, 0, 1), overhang=45.0):
    """The check plus the printability report of the object's mesh (a dict, with 'thickness'
    per triangle and 'thin': the indices of the triangles thinner than min_wall)."""
    if material:
        known = frepcore.materials()
        if material not in known:
            raise ValueError("unknown material '%s'; known: %s" % (material, ", ".join(known)))
        density = known[material]
    report = frepcore_mesh(obj).printability(up=tuple(up), overhang=overhang,
                                             min_wall=min_wall, density=density, name=obj.Label)
    report["thin"] = ([i for i, w in enumerate(report["thickness"]) if 0 <= w < min_wall]
                      if min_wall else [])
    return report


def show_thin_regions(obj, thin):
    """Colours the given triangles of a Mesh feature's view red and the rest grey (its
    segments: FreeCAD draws a mesh's segments in the colours given); no-op without a GUI."""
    if not FreeCAD.GuiUp or getattr(obj, "ViewObject", None) is None:
        return False
    mesh = obj.Mesh.copy()
    thin = sorted(set(thin))
    rest = sorted(set(range(mesh.CountFacets)) - set(thin))
    for segment in (thin, rest):
        if segment:
            mesh.addSegment(segment)
    obj.Mesh = mesh
    colors = ([THIN_COLOR] if thin else []) + ([SOUND_COLOR] if rest else [])
    obj.ViewObject.highlightSegments(colors)
    return True
