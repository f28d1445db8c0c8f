"""Where a blend acts, for its guide in the 3D view: Pasko's blend adds
a0 / (1 + (f1/a1)^2 + (f2/a2)^2) to the set operation, so the term exceeds FRACTION of its
strength a0 where (f1/a1)^2 + (f2/a2)^2 < 1/FRACTION - 1: a tube about the curve where the two
surfaces meet. Its handles sit on that curve's nearest point to the blend's middle, moved along
each surface to where the other input's field is -a (union: outside it) or +a (intersection:
inside it), which is where the term has fallen to half: dragging one there sets that reach
to the field's value at the point dropped.

Everything here is in the blend's own coordinates (its inputs' document coordinates; the
view provider's root applies the blend's Placement)."""

import FreeCAD

import FRepTree
from FRepPaths import frepcore

FRACTION = 0.1  # the guide: where the added term exceeds a tenth of its strength
BLENDS = ("blend_union", "blend_intersection", "bounded_blend")
GUIDE_CELLS = 40


def is_blend(obj):
    return getattr(getattr(obj, "Proxy", None), "FREP_TYPE", None) in BLENDS


def _inputs(obj, builder=None):
    inputs = obj.Proxy.inputs(obj)
    if len(inputs) < 2:
        raise ValueError("%s: a blend guide needs the blend's two inputs; it has %d"
                         % (obj.Label, len(inputs)))
    builder = builder or FRepTree.Builder()
    return [builder.shape(i) for i in inputs]


def _operation(obj):
    if obj.Proxy.FREP_TYPE == "bounded_blend":
        return obj.Operation
    return "intersection" if obj.Proxy.FREP_TYPE == "blend_intersection" else "union"


def _unit(v):
    return v * (1.0 / v.Length) if v.Length > 1e-12 else None


def _gradient(shape, p):
    return FreeCAD.Vector(*shape.gradient(p.x, p.y, p.z)[1])


def _meeting_point(f1, f2, box):
    """A point where both surfaces pass (the curve they meet on), near the box's middle:
    the best of a coarse grid, then alternating projections onto each surface."""
    n = 12
    lo, hi = box
    grid = [FreeCAD.Vector(lo[0] + (hi[0] - lo[0]) * (a + 0.5) / n,
                           lo[1] + (hi[1] - lo[1]) * (b + 0.5) / n,
                           lo[2] + (hi[2] - lo[2]) * (c + 0.5) / n)
            for a in range(n) for b in range(n) for c in range(n)]
    pts = [(p.x, p.y, p.z) for p in grid]
    v1, v2 = f1.values(pts), f2.values(pts)
    centre = (FreeCAD.Vector(*lo) + FreeCAD.Vector(*hi)) * 0.5
    size = (FreeCAD.Vector(*hi) - FreeCAD.Vector(*lo)).Length
    best = min(range(len(grid)),
               key=lambda k: abs(v1[k]) + abs(v2[k]) + 1e-3 * (grid[k] - centre).Length / size)
    p = grid[best]
    for _ in range(30):
        for f in (f1, f2):
            g = _gradient(f, p)
            if g.Length < 1e-12:
                return None
            p = p - g * (f.values([(p.x, p.y, p.z)])[0] / (g.Length ** 2))
    if max(abs(f.values([(p.x, p.y, p.z)])[0]) for f in (f1, f2)) > 1e-6 * max(size, 1e-9):
        return None
    return p


def _box(obj, blended, reach):
    """The box the guide is meshed in, in the blend's frame: the blend's bounds (or, where it
    is unbounded, its preview's) grown by three reaches and a tenth."""
    bounds = blended.bounds()
    if bounds["empty"]:
        raise ValueError("%s: the blend is empty; there is nothing to guide" % obj.Label)
    if bounds["bounded"]:
        lo, hi = (FreeCAD.Vector(*c) for c in bounds["box"])
    elif obj.Mesh.CountPoints:
        inv = FreeCAD.Placement(obj.Placement).inverse()
        points = [inv.multVec(FreeCAD.Vector(*p)) for p in
                  ((x, y, z) for x in (obj.Mesh.BoundBox.XMin, obj.Mesh.BoundBox.XMax)
                   for y in (obj.Mesh.BoundBox.YMin, obj.Mesh.BoundBox.YMax)
                   for z in (obj.Mesh.BoundBox.ZMin, obj.Mesh.BoundBox.ZMax))]
        lo = FreeCAD.Vector(*(min(p[k] for p in points) for k in range(3)))
        hi = FreeCAD.Vector(*(max(p[k] for p in points) for k in range(3)))
    else:
        raise ValueError("%s: the blend is unbounded and has no preview to size its guide by; "
                         "show it first" % obj.Label)
    grow = 0.1 * (hi - lo).Length + 3 * reach
    return ((lo.x - grow, lo.y - grow, lo.z - grow), (hi.x + grow, hi.y + grow, hi.z + grow))


def guide(obj):
    """dict(mesh: the region where the blend acts (frepcore mesh, or None when it is empty in
    the box), anchor: a point where the surfaces meet (or None), handles: [(property, point,
    direction, lift)]: the point where the reach is now, the line it moves on, and how far off
    the surface to draw it). ValueError naming the blend when its inputs cannot be built."""
    builder = FRepTree.Builder()  # (the inputs built once, for them and the blend)
    shapes = _inputs(obj, builder)
    f1, f2 = shapes[0], shapes[1]
    a1, a2 = float(obj.A1), float(obj.A2)
    blended = obj.Proxy.local_shape(obj, builder)
    box = _box(obj, blended, max(a1, a2))
    # The region, as a coat on the blend's surface (a band 1.5 cells either side of it), so the
    # view shows where on the part the blend acts rather than a cloud around it.
    coat = 1.5 * max(box[1][k] - box[0][k] for k in range(3)) / GUIDE_CELLS
    region = frepcore.Node(
        "formula", {"formula": "min(%r - (f1/a1)^2 - (f2/a2)^2, t - abs(f3))"
                               % (1.0 / FRACTION - 1.0),
                    "parameters": "a1 = %r, a2 = %r, t = %r" % (a1, a2, coat)},
        [f1.node, f2.node, blended.node], obj.Label + " guide")
    if obj.Proxy.FREP_TYPE == "bounded_blend" and len(shapes) > 2:
        region = frepcore.Node("intersection", {}, [region, shapes[2].node], obj.Label + " guide")
    try:
        mesh = frepcore.Shape(region).mesh(bbox=box, cells=GUIDE_CELLS)
    except frepcore.EmptySolid:
        mesh = None
    anchor = _meeting_point(f1, f2, box)
    handles = []
    if anchor is not None:
        n1, n2 = _unit(_gradient(f1, anchor)), _unit(_gradient(f2, anchor))
        sign = 1.0 if _operation(obj) == "intersection" else -1.0
        for name, own, other, reach in (("A1", n1, n2, a1), ("A2", n2, n1, a2)):
            # along the other surface, away from (union) or into (intersection) this input
            d = own - other * own.dot(other) if own and other else None
            d = _unit(d * sign) if d is not None else None
            if d is None:
                continue
            g = _gradient(f1 if name == "A1" else f2, anchor)
            rate = abs(g.dot(d)) or 1.0
            # drawn lifted off the other surface, clear of the material the blend adds there
            lift = other * -(abs(float(obj.A0)) + 0.25 * reach)
            handles.append((name, anchor + d * (reach / rate), d, lift))
    return {"mesh": mesh, "anchor": anchor, "handles": handles}


def set_reach(obj, name, point):
    """Sets reach A1 or A2 to the size of that input's field at `point` (where the blend's
    term is then half its strength along the other surface). Returns the value set."""
    if name not in ("A1", "A2"):
        raise ValueError("%s: a blend's reaches are A1 and A2, not %s" % (obj.Label, name))
    shapes = _inputs(obj)
    f = shapes[0] if name == "A1" else shapes[1]
    value = abs(f.values([(point.x, point.y, point.z)])[0])
    if not value > 0:
        raise ValueError("%s: %s must be more than 0; drag the handle off the surface"
                         % (obj.Label, name))
    setattr(obj, name, value)
    return value
