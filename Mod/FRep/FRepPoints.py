"""Point lists from FreeCAD objects, for the `<Name>Source` link of a point-list parameter.

A path (the sweep's) comes from any edge, wire, sketch or Draft wire, sampled finely enough
that the polyline stays within a thousandth of the path's size. A set of positions (the
instancer's) comes from mesh vertices, a point cloud, a Draft array's copies or any shape's
vertices (a sketch's points, Draft points)."""

import FreeCAD

SAMPLING = 1e-3  # deflection, relative to the path's bounding-box diagonal


def source_property(param_name):
    import FRepProperties as props
    return props.property_name(param_name) + "Source"


def source_tooltip(param):
    name = props_name(param)
    if param.get("path", False):
        return ("Take %s from an edge, wire, sketch or Draft wire (sampled) instead of the "
                "list." % name)
    return ("Take %s from an object instead of the list: mesh vertices, a point cloud, the "
            "copies of a Draft array (their positions) or a shape's vertices." % name)


def props_name(param):
    import FRepProperties as props
    return props.property_name(param["name"])


# Draft's array objects: their shape is a compound of the copies, each with its placement.
DRAFT_ARRAYS = ("Array", "PathArray", "PathTwistedArray", "PointArray", "PathLinkArray",
                "PointLinkArray")


def position_points(owner, prop, source):
    """Points from the source in the owner's local coordinates: link arrays' placements,
    the copies of a Draft array, mesh vertices, point clouds or a shape's vertices."""
    placed = _placements(source)
    if not placed:
        raise ValueError("%s: property '%s' links '%s' (%s), which has no points; link a mesh, "
                         "a point cloud, a Draft array or a shape with vertices"
                         % (owner.Label, prop, source.Label, source.TypeId))
    back = owner.Placement.inverse()
    return [tuple(back.multVec(p)) for p, _ in placed]


def position_rotations(owner, source):
    """The copies' rotations (rotation vectors: axis times degrees) in the owner's local
    coordinates, for a source whose copies are turned (Draft arrays); [] when none is."""
    import math
    turns = [r for _, r in _placements(source)]
    if all(r is None or abs(r.Angle) < 1e-12 for r in turns):
        return []
    # (on a copy: inverted() on the object's own Rotation touches the object in FreeCAD 0.20)
    back = FreeCAD.Rotation(*owner.Placement.Rotation.Q).inverted()
    out = []
    for r in turns:
        local = back.multiply(r or FreeCAD.Rotation())
        angle = math.degrees(local.Angle)
        out.append(tuple(local.Axis * angle) if angle > 1e-12 else (0.0, 0.0, 0.0))
    return out


def _placements(source):
    """[(position, rotation or None)] of the source's copies or points."""
    placements = getattr(source, "PlacementList", None)
    if placements:  # a link array: copies without their own shapes
        return [(q.Base, q.Rotation) for q in (source.Placement.multiply(p) for p in placements)]
    mesh = getattr(source, "Mesh", None)
    if mesh is not None and hasattr(mesh, "Points") and hasattr(mesh, "Facets"):
        return [(FreeCAD.Vector(p.x, p.y, p.z), None) for p in mesh.Points]
    cloud = getattr(source, "Points", None)
    if cloud is not None and hasattr(cloud, "Points"):
        return [(p, None) for p in cloud.Points]
    shape = getattr(source, "Shape", None)
    if shape is None or shape.isNull():
        return []
    proxy_type = getattr(getattr(source, "Proxy", None), "Type", None)
    if proxy_type in DRAFT_ARRAYS and (shape.Edges or shape.Faces):
        # each copy is a child shape placed by the array
        return [(c.Placement.Base, c.Placement.Rotation) for c in shape.childShapes()]
    return [(v.Point, None) for v in shape.Vertexes]


def path_points(owner, prop, source, arcs=False):
    """The source's first wire as points, in the owner's local coordinates (document
    coordinates moved back by the owner's Placement). `arcs`: start, middle and end of each
    piece (the sweep's segments "arcs"): lines and circular arcs exactly, other curves as
    short straight pieces."""
    shape = getattr(source, "Shape", None)
    if shape is None or not shape.Edges:
        raise ValueError("%s: property '%s' links '%s' (%s), which has no edges; link an edge, "
                         "wire, sketch or Draft wire" % (owner.Label, prop, source.Label,
                                                         source.TypeId))
    import Part
    wires = shape.Wires or [Part.Wire(Part.__sortEdges__(shape.Edges))]
    if len(wires) > 1:
        FreeCAD.Console.PrintWarning("%s: '%s' has %d wires; the sweep follows the first\n"
                                     % (owner.Label, source.Label, len(wires)))
    wire = wires[0]
    deflection = max(SAMPLING * shape.BoundBox.DiagonalLength, 1e-9)
    points = _arc_points(wire, deflection) if arcs else wire.discretize(Deflection=deflection)
    back = owner.Placement.inverse()
    return [tuple(back.multVec(p)) for p in points]


def _arc_points(wire, deflection):
    """[start, middle, end, middle, end, ...] along the wire's edges in order."""
    edges = wire.OrderedEdges
    out = []
    for i, edge in enumerate(edges):
        chain = _edge_chain(edge, deflection)
        # follow the wire: turn an edge round where it ends at the path so far (or, for the
        # first edge, where it starts at the next one)
        if out:
            if (chain[-1] - out[-1]).Length < (chain[0] - out[-1]).Length:
                chain.reverse()
        elif len(edges) > 1:
            ends = [v.Point for v in edges[1].Vertexes]
            if min((chain[0] - e).Length for e in ends) < min((chain[-1] - e).Length
                                                              for e in ends):
                chain.reverse()
        out += chain[1:] if out else chain
    return out


def _edge_chain(edge, deflection):
    """One edge as start, middle, end[, middle, end ...]: a line or an arc of a circle as
    itself (a whole circle as two halves), any other curve as short straight pieces."""
    import Part
    a, b = edge.FirstParameter, edge.LastParameter
    if isinstance(edge.Curve, (Part.Line, Part.LineSegment)):
        params = [a, 0.5 * (a + b), b]
    elif isinstance(edge.Curve, Part.Circle):
        n = 2 if edge.isClosed() else 1  # an arc's start and end must differ
        params = [a + (b - a) * k / (2 * n) for k in range(2 * n + 1)]
    else:
        points = edge.discretize(Deflection=deflection)
        chain = [points[0]]
        for p, q in zip(points, points[1:]):
            chain += [(p + q) * 0.5, q]
        return chain
    return [edge.valueAt(t) for t in params]
