"""Point lists from FreeCAD objects: the `<Points>Source` link of a node with a point-list
parameter (the sweep's path) takes its points from any edge, wire, sketch or Draft wire,
sampled finely enough that the polyline stays within a thousandth of the path's size."""

import FreeCAD

SAMPLING = 1e-3  # deflection, relative to the path's bounding-box diagonal


def source_property(param_name):
    import FRepProperties as props
    return props.property_name(param_name) + "Source"


def path_points(owner, prop, source):
    """The source's first wire as points, in the owner's local coordinates (document
    coordinates moved back by the owner's Placement)."""
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
    points = wire.discretize(Deflection=deflection)
    back = owner.Placement.inverse()
    return [tuple(back.multVec(p)) for p in points]
