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
CAVITY_COLOR = (0.15, 0.45, 0.95)
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
    per triangle, 'thin': the indices of the triangles thinner than min_wall, and
    'cavity_triangles': those of the walls of enclosed cavities)."""
    if material:
        known = frepcore.materials()
        if material not in known:
            raise ValueError("unknown material '%s'; known: %s" % (material, ", ".join(known)))
        density = known[material]
    report = frepcore_mesh(obj).printability(up=tuple(up), overhang=overhang,
                                             min_wall=min_wall, density=density, name=obj.Label)
    report["thin"] = ([i for i, w in enumerate(report["thickness"]) if 0 <= w < min_wall]
                      if min_wall else [])
    report["cavity_triangles"] = [i for i, k in enumerate(report["cavity_of"]) if k >= 0]
    return report


def show_regions(obj, thin, cavity_walls=()):
    """Colours the given triangles of a Mesh feature's view: thin ones red, the walls of
    cavities blue, the rest grey (its segments: FreeCAD draws a mesh's segments in the colours
    given); no-op without a GUI. A triangle both thin and a cavity's wall shows as thin."""
    if not FreeCAD.GuiUp or getattr(obj, "ViewObject", None) is None:
        return False
    mesh = obj.Mesh.copy()
    if mesh.countSegments():
        # segments only add up: a mesh built from the same topology starts without them,
        # so a second check replaces the first one's colours
        import Mesh
        placement = mesh.Placement
        mesh.Placement = FreeCAD.Placement()
        mesh = Mesh.Mesh(mesh.Topology)
        mesh.Placement = placement
    thin = sorted(set(thin))
    walls = sorted(set(cavity_walls) - set(thin))
    rest = sorted(set(range(mesh.CountFacets)) - set(thin) - set(walls))
    colors = []
    for segment, color in ((thin, THIN_COLOR), (walls, CAVITY_COLOR), (rest, SOUND_COLOR)):
        if segment:
            mesh.addSegment(segment)
            colors.append(color)
    obj.Mesh = mesh
    obj.ViewObject.highlightSegments(colors)
    return True


def infill_of(obj):
    """The infill feature whose solid a mesh object shows: the object itself (an FRep
    feature's preview) or a Polygonize feature's Source; None for any other mesh."""
    for candidate in (obj, getattr(obj, "Source", None)):
        proxy = getattr(candidate, "Proxy", None)
        if getattr(proxy, "FREP_TYPE", None) == "infill":
            return candidate
    return None


def most_drain_holes():
    """The infill node's limit on its parameter 'drain_holes' (the registry's)."""
    infill = next(t for t in frepcore.node_types() if t["type"] == "infill")
    return next(p["max_points"] for p in infill["params"] if p["name"] == "drain_holes")


def drain_cavities(infill, report, up=(0, 0, 1)):
    """Adds a drain hole where the printability report says each cavity drains (a point of
    its floor; largest cavity first, up to the infill's limit) to the infill's DrainHoles,
    along the build direction;
    returns how many were added. The points are the mesh's (world) coordinates, turned into
    the infill's own before its placement."""
    if getattr(infill, "DrainHolesSource", None) is not None:
        raise ValueError("%s: its drain holes come from %s (property 'DrainHolesSource'); add "
                         "the points there, or clear the link" % (
                             infill.Label, infill.DrainHolesSource.Label))
    into_infill = infill.getGlobalPlacement().inverse()
    holes = list(infill.DrainHoles)
    room = max(0, most_drain_holes() - len(holes))
    added = [into_infill.multVec(FreeCAD.Vector(*c["drain_at"]))
             for c in report["print"]["cavity_list"][:room]]
    if not added:
        return 0
    infill.DrainHoles = holes + added
    infill.DrainAxis = into_infill.Rotation.multVec(FreeCAD.Vector(*up))
    return len(added)
