"""Enveloping in FreeCAD (seed 003, 3.5): an Envelope feature binds the CVs of chosen levels of
an hspline (its Base, the rest pose) to skeleton segments, so that moving a segment deforms the
surface. Near a joint the finer level's CVs take a frame between the two segments' (the joint
bends round, it does not collapse: seed 003's figure 3.2); finer levels that are not enveloped
follow their parents' frames. The result is an hspline itself: it draws, exports, attaches and
makes a solid like any other, and its CVs are the segments' to move (edit the Base instead).

A segment is a straight line (a Part Line, a Draft line, a sketch of one line) or an object
that is only a placement (a Local Coordinate System, a Datum): such a one runs from its origin
to the next segment's origin (the last one along its local Z axis, as long as the one before
it). The pose the segments had when they were bound is the rest pose (RestPlacements); Set
rest pose binds them where they are now.

Scripting:
    import FRepHSpline as H, FRepHSplineEnvelope as E
    arm = H.make_cylinder(doc, 8, 12, 10, 80)
    upper, fore = E.make_line(doc, (0, 0, 0), (0, 0, 40)), E.make_line(doc, (0, 0, 40), (0, 0, 80))
    env = E.make_envelope(doc, arm, [upper, fore])
    fore.Placement = FreeCAD.Placement(FreeCAD.Vector(), FreeCAD.Rotation(FreeCAD.Vector(1, 0, 0), 90),
                                       FreeCAD.Vector(0, 0, 40))
    doc.recompute()                      # the arm bends at the elbow
"""

import FreeCAD

import FRepHSpline as H
from FRepErrors import one_line_errors
from FRepPaths import frepcore
from FRepProxy import add_property

GROUP = "Envelope"


# -- segments -----------------------------------------------------------------------------------
def _straight_edge(obj):
    shape = getattr(obj, "Shape", None)
    if shape is None or shape.isNull() or len(shape.Edges) != 1:
        return None
    edge = shape.Edges[0]
    if type(edge.Curve).__name__ not in ("Line", "LineSegment") or len(edge.Vertexes) != 2:
        return None
    return edge


def _is_placement_only(obj):
    shape = getattr(obj, "Shape", None)
    return hasattr(obj, "Placement") and (shape is None or shape.isNull() or not shape.Edges
                                          or obj.TypeId in ("PartDesign::CoordinateSystem",
                                                            "Part::LocalCoordinateSystem"))


def segment_poses(obj, segments):
    """Each segment's (start, end, frame placement) where it is now; ValueError naming the
    Envelope and the segment for one that is neither a line nor a placement."""
    out = []
    for k, seg in enumerate(segments):
        edge = _straight_edge(seg)
        if edge is not None:
            start, end = edge.Vertexes[0].Point, edge.Vertexes[1].Point
            if (end - start).Length <= 0:
                raise ValueError("%s: segment '%s' has zero length" % (obj.Label, seg.Label))
            # The frame turns with the line's placement (so a turn about the line's own axis
            # counts), and by the least rotation for a change of its end points.
            # (a copy: calls on the object's own Rotation touch the object in FreeCAD 0.20)
            placed = FreeCAD.Rotation(*seg.Placement.Rotation.Q)
            local = placed.inverted().multVec(end - start)
            turn = placed.multiply(FreeCAD.Rotation(FreeCAD.Vector(1, 0, 0), local))
            out.append((start, end, FreeCAD.Placement(start, turn)))
        elif _is_placement_only(seg):
            out.append((FreeCAD.Vector(seg.Placement.Base), None, FreeCAD.Placement(seg.Placement)))
        else:
            raise ValueError("%s: property 'Segments': '%s' is neither a straight line (one "
                             "straight edge) nor a placement (a coordinate system)"
                             % (obj.Label, seg.Label))
    # placements run to the next segment's start, the last one along its Z axis
    for k, (start, end, frame) in enumerate(out):
        if end is None:
            if k + 1 < len(out):
                end = out[k + 1][0]
            else:
                before = (out[k - 1][1] - out[k - 1][0]).Length if k > 0 else 10.0
                end = start + frame.Rotation.multVec(FreeCAD.Vector(0, 0, 1)) * before
            out[k] = (start, end, frame)
    return out


def _matrix12(placement):
    m = placement.toMatrix()
    return (m.A11, m.A12, m.A13, m.A14, m.A21, m.A22, m.A23, m.A24, m.A31, m.A32, m.A33, m.A34)


def make_line(doc, start, end, name="Segment"):
    """A Part Line from start to end: a segment to envelope with."""
    line = doc.addObject("Part::Line", name)
    line.X1, line.Y1, line.Z1 = start
    line.X2, line.Y2, line.Z2 = end
    return line


def make_skeleton(doc, base):
    """Two lines along the hspline's longest side through its middle, jointed halfway: a
    skeleton to start from."""
    box = base.Shape.BoundBox
    lengths = (box.XLength, box.YLength, box.ZLength)
    axis = lengths.index(max(lengths))
    lo, hi, mid = FreeCAD.Vector(box.Center), FreeCAD.Vector(box.Center), box.Center
    lo[axis] = (box.XMin, box.YMin, box.ZMin)[axis]
    hi[axis] = (box.XMax, box.YMax, box.ZMax)[axis]
    return [make_line(doc, tuple(lo), tuple(mid), "Bone"), make_line(doc, tuple(mid), tuple(hi), "Bone")]


# -- the feature --------------------------------------------------------------------------------
class EnvelopeFeature(H.HSplineFeature):
    # Its CVs follow the segments: the hspline edits refuse it (FRepHSpline._edited).
    DERIVED = True

    def setup(self, obj):
        super().setup(obj)
        add_property(obj, "App::PropertyLink", "Base", GROUP,
                     "The hspline in its rest pose (edit its CVs there).")
        add_property(obj, "App::PropertyLinkList", "Segments", GROUP,
                     "The skeleton: straight lines or placements, in order along the chain; "
                     "two segments meet at a joint where one ends and the next starts.")
        add_property(obj, "App::PropertyIntegerList", "EnvelopedLevels", GROUP,
                     "The levels whose CVs the segments carry: level 0 each CV with its "
                     "nearest segment, finer levels blending the two segments' frames near a "
                     "joint. Levels not listed follow their parents' frames.", [0, 1])
        add_property(obj, "App::PropertyLength", "JointReach", GROUP,
                     "How far from a joint (across it) finer CVs blend the two frames, and "
                     "where level 0 is refined; 0: 1.25 times the control net's mean edge.")
        add_property(obj, "App::PropertyBool", "RefineJoints", GROUP,
                     "Refine level 0 around each joint first (in this result only), so that "
                     "level 1 has CVs to bend the joint round.", True)
        add_property(obj, "App::PropertyPlacementList", "RestPlacements", GROUP,
                     "Each segment's frame in the rest pose (Set rest pose binds the segments "
                     "where they are now).")
        add_property(obj, "App::PropertyVectorList", "RestEnds", GROUP,
                     "Each segment's start and end in the rest pose, in pairs.")
        add_property(obj, "App::PropertyStringList", "RestNames", GROUP,
                     "The segments the rest pose was taken of, by name.")
        for name in ("RestPlacements", "RestEnds", "RestNames"):
            obj.setEditorMode(name, 1)
        add_property(obj, "App::PropertyString", "Binding", GROUP,
                     "How many CVs each segment carries, after the last recompute.")
        obj.setEditorMode("Binding", 1)

    def onChanged(self, obj, prop):
        super().onChanged(obj, prop)
        # (not while the document is read back: the rest pose comes from the file then)
        if prop == "Segments" and "RestNames" in obj.PropertiesList and \
                "Restore" not in obj.State:
            keep_rest_pose(obj)

    def inputs(self, obj):
        return [obj.Base] if obj.Base is not None else []

    def set_rest_pose(self, obj):  # for the view provider's context menu
        set_rest_pose(obj)

    @one_line_errors
    def execute(self, obj):
        if not H.is_hspline(obj.Base) or obj.Base == obj:
            raise ValueError("%s: property 'Base' must link an HSpline" % obj.Label)
        if not obj.Segments:
            raise ValueError("%s: property 'Segments' is empty; give the lines or placements "
                             "that carry the surface" % obj.Label)
        now = segment_poses(obj, obj.Segments)
        keep_rest_pose(obj, now)
        segments = []
        for k, (start, end, frame) in enumerate(now):
            rest = FreeCAD.Placement(obj.RestPlacements[k])
            motion = frame.multiply(rest.inverse())
            segments.append((tuple(obj.RestEnds[2 * k]), tuple(obj.RestEnds[2 * k + 1]),
                             _matrix12(motion)))
        levels = list(obj.EnvelopedLevels)
        try:
            result = frepcore.envelope(H._shared(obj.Base), segments, levels,
                                       float(obj.JointReach), bool(obj.RefineJoints))
        except ValueError as e:
            raise ValueError("%s: %s" % (obj.Label, e)) from None
        H.store(obj, result["hspline"])
        binding = "; ".join("%s %d CVs" % (s.Label, n)
                            for s, n in zip(obj.Segments, result["bound_per_segment"]))
        binding += "; %d blended across %d joint(s), reach %.3g mm" % (
            result["blended"], len(result["joints"]), result["joint_reach"])
        if obj.Binding != binding:
            obj.Binding = binding
        super().execute(obj)


def keep_rest_pose(obj, now=None):
    """The rest pose of each segment: kept for segments bound before, taken where it is now
    (`now`: segment_poses, when the caller has them) for a new one."""
    names = [s.Name for s in obj.Segments]
    if names == list(obj.RestNames):
        return
    if now is None:
        try:
            now = segment_poses(obj, obj.Segments)
        except ValueError:
            return  # execute says why
    old = {name: (obj.RestPlacements[k], obj.RestEnds[2 * k], obj.RestEnds[2 * k + 1])
           for k, name in enumerate(obj.RestNames)
           if k < len(obj.RestPlacements) and 2 * k + 1 < len(obj.RestEnds)}
    placements, ends = [], []
    for seg, (start, end, frame) in zip(obj.Segments, now):
        rest = old.get(seg.Name, (frame, start, end))
        placements.append(rest[0])
        ends += [rest[1], rest[2]]
    obj.RestPlacements, obj.RestEnds, obj.RestNames = placements, ends, names


def set_rest_pose(obj):
    """Binds the segments where they are now: the surface takes its Base's shape again."""
    now = segment_poses(obj, obj.Segments)
    obj.RestPlacements = [frame for _, _, frame in now]
    obj.RestEnds = [p for start, end, _ in now for p in (start, end)]
    obj.RestNames = [s.Name for s in obj.Segments]
    obj.touch()


def make_envelope(doc, base, segments, name="Envelope"):
    obj = doc.addObject("Part::FeaturePython", name)
    EnvelopeFeature(obj)
    if FreeCAD.GuiUp:
        import FRepHSplineView
        FRepHSplineView.ViewProviderEnvelope(obj.ViewObject)
    obj.Base = base
    obj.Segments = list(segments)
    set_rest_pose(obj)
    H.store(obj, H.hspline_of(base))  # the rest pose until the first recompute
    base.Visibility = False
    return obj
