"""Hierarchical B-spline surfaces in FreeCAD (seed 003's hsplines): an HSpline feature whose
hierarchy lives in its properties, so that it saves, reopens, undoes and recomputes like any
feature (seed 003 had to fake this with .hs side files).

- The surface is one exact B-spline face (the hierarchy flattened by knot insertion, not a
  fit); a closed hspline (periodic both ways, like a torus) is a solid when MakeSolid is on,
  so FRep operations, Part booleans and STEP take it as it is.
- The hierarchy: level 0's knots (KnotsU, KnotsV; PeriodU/PeriodV > 0 for a periodic
  direction) and every CV as (CvLevels, CvI, CvJ, CvValues): level 0 positions, finer levels
  offsets along the parent's u tangent, v tangent and normal, so detail follows the parent.
- Tagged holds the tagged CVs as (level, i, j) triples: tags drive Refine and Zero Offsets
  and the display; the draggers of edit mode sit on tagged CVs that may move.

Scripting:
    import FRepHSpline as H
    obj = H.make_torus(doc, 10, 8, 20, 6)
    H.set_tags(obj, [(0, 3, 3), (0, 4, 3)])
    H.refine(obj)                        # the tagged CVs; level 1 appears
    H.move_cv(obj, (1, 8, 8), point)     # refused with the reason when the CV is fixed
    H.zero_offsets(obj); H.unrefine(obj)
    doc.recompute()
"""

import FreeCAD

from FRepPaths import frepcore
from FRepErrors import one_line_errors
from FRepProxy import FeatureProxy

GROUP = "HSpline"
DATA_GROUP = "HSpline data"
CV_GROUP = "CVs"
CV_PREFIX = "Cv_"
DATA = ("KnotsU", "PeriodU", "KnotsV", "PeriodV", "CvLevels", "CvI", "CvJ", "CvValues")


# The hierarchy of each feature as last built from or written to its properties, so that a drag
# does not rebuild 10,000 CVs from property lists twice. Any change of a data property (undo,
# a document restore, a script) drops the entry; our own edits put the new one back.
_CACHE = {}


def _key(obj):
    return (obj.Document.Name, obj.Name)


def is_hspline(obj):
    return isinstance(getattr(obj, "Proxy", None), HSplineFeature)


class HSplineFeature(FeatureProxy):
    def setup(self, obj):
        add = obj.addProperty
        have = obj.PropertiesList
        for name, kind, doc in (
                ("KnotsU", "App::PropertyFloatList",
                 "Level 0's knots along u: CVs + 4 for an open direction, one period's worth "
                 "(one per CV) for a periodic one."),
                ("KnotsV", "App::PropertyFloatList", "Level 0's knots along v (as KnotsU)."),
                ("PeriodU", "App::PropertyFloat", "The period along u; 0: open."),
                ("PeriodV", "App::PropertyFloat", "The period along v; 0: open."),
                ("CvLevels", "App::PropertyIntegerList", "Each CV's level."),
                ("CvI", "App::PropertyIntegerList", "Each CV's index along u on its level."),
                ("CvJ", "App::PropertyIntegerList", "Each CV's index along v on its level."),
                ("CvValues", "App::PropertyVectorList",
                 "Each CV's value: level 0 its position, finer levels its offset along the "
                 "parent's u tangent, v tangent and normal.")):
            if name not in have:
                add(kind, name, DATA_GROUP, doc)
            obj.setEditorMode(name, 1)  # edited through the commands, which keep it whole
        if "Tagged" not in have:
            add("App::PropertyIntegerList", "Tagged", GROUP,
                "The tagged CVs as level, i, j triples: what Refine and Zero Offsets act on "
                "and where edit mode puts draggers.")
        if "MakeSolid" not in have:
            add("App::PropertyBool", "MakeSolid", GROUP,
                "A closed hspline (periodic in u and v) is a solid rather than a face.")
            obj.MakeSolid = True
        for name, doc in (("Levels", "How many levels the hierarchy has."),
                          ("CvCount", "How many CVs it has on all levels.")):
            if name not in have:
                add("App::PropertyInteger", name, GROUP, doc)
            obj.setEditorMode(name, 1)

    def onChanged(self, obj, prop):
        if prop in DATA or prop.startswith(CV_PREFIX):
            _CACHE.pop(_key(obj), None)

    # For the view provider and the panel, which do not import this module.
    def hspline(self, obj):
        return _shared(obj)

    def solid_mesh(self, obj, tolerance):
        """For FRep features (FRepSolids): the closed hspline's own tessellation within
        `tolerance`, checked closed by construction; None (MeshPart then tessellates the Part
        shape) when it is open, not a solid, or placed elsewhere than where it was modelled."""
        h = _shared(obj)
        if not (h.closed and obj.MakeSolid) or not obj.Placement.isIdentity():
            return None
        return h.tessellate(tolerance)

    def nudge(self, obj, cvs, delta, along_normal=0.0):
        return nudge_cvs(obj, cvs, delta, along_normal)

    def tags(self, obj):
        return tags(obj)

    def tag(self, obj, how, level=0):
        return tag(obj, how, level=level)

    def refine(self, obj):
        return refine(obj)

    def zero_offsets(self, obj):
        return zero_offsets(obj)

    def unrefine(self, obj):
        return unrefine(obj)

    def expose_cv(self, obj, cv):
        return expose_cv(obj, cv)

    def toggle_tag(self, obj, cv):
        cv = tuple(cv)
        if cv in tags(obj):
            set_tags(obj, [c for c in tags(obj) if c != cv])
        else:
            tag_cv(obj, cv)

    @one_line_errors
    def execute(self, obj):
        h = _shared(obj)
        # The exact B-spline face (a solid when closed), built by OpenCASCADE in frepcore with
        # our tessellation attached as its triangulation, so the 3D view draws that instead of
        # meshing a face of thousands of poles again (docs/performance.md).
        obj.Shape = _shape_from_binary(h.brep_binary(bool(h.closed and obj.MakeSolid)))
        if obj.Levels != h.level_count:
            obj.Levels = h.level_count
        if obj.CvCount != h.cv_count:
            obj.CvCount = h.cv_count


def _shared(obj):
    """The feature's hierarchy, shared: read it, never change it."""
    h = _CACHE.get(_key(obj))
    if h is None:
        try:
            h = frepcore.HSpline.from_arrays(
                list(obj.KnotsU), obj.PeriodU, list(obj.KnotsV), obj.PeriodV, list(obj.CvLevels),
                list(obj.CvI), list(obj.CvJ), [tuple(v) for v in obj.CvValues])
        except ValueError as e:
            raise ValueError("%s: %s" % (obj.Label, e)) from None
        for cv, name in exposed_cvs(obj).items():  # a CV's own property wins over CvValues
            if h.has_cv(*cv):
                try:
                    h.set_value(cv[0], cv[1], cv[2], tuple(getattr(obj, name)))
                except ValueError as e:
                    raise ValueError("%s: property '%s': %s" % (obj.Label, name, e)) from None
        _CACHE[_key(obj)] = h
    return h


def _shape_from_binary(data):
    """A Part shape from OpenCASCADE binary BRep (Part.Shape.importBinary reads files only; a
    RAM-backed temporary file where there is one)."""
    import os
    import tempfile
    import Part
    folder = "/dev/shm" if os.path.isdir("/dev/shm") and os.access("/dev/shm", os.W_OK) else None
    fd, path = tempfile.mkstemp(suffix=".brep", dir=folder)
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        shape = Part.Shape()
        shape.importBinary(path)
    finally:
        os.remove(path)
    if shape.isNull():
        raise RuntimeError("the hspline's shape could not be read back from OpenCASCADE")
    return shape


def hspline_of(obj):
    """The feature's hierarchy as a frepcore.HSpline of the caller's own (ValueError naming
    the object when its properties do not describe one)."""
    return _shared(obj).copy()


def store(obj, h, values_only=False):
    """Writes a hierarchy into the feature's properties (in the open transaction: one undo
    step) and drops tags of CVs it no longer has. values_only: the CVs are the same ones,
    only their values changed (a move, zero offsets): one property is written."""
    if values_only:
        obj.CvValues = h.to_arrays(values_only=True)["values"]  # tuples, taken as they are
    else:
        a = h.to_arrays()
        obj.KnotsU, obj.PeriodU = a["knots_u"], a["period_u"]
        obj.KnotsV, obj.PeriodV = a["knots_v"], a["period_v"]
        obj.CvLevels, obj.CvI, obj.CvJ = a["levels"], a["i"], a["j"]
        obj.CvValues = [FreeCAD.Vector(*v) for v in a["values"]]
        kept = [c for c in tags(obj) if h.has_cv(*c)]
        if kept != tags(obj):
            set_tags(obj, kept)
    for cv, name in exposed_cvs(obj).items():  # a drag of an exposed CV moves its property
        if h.has_cv(*cv):
            value = FreeCAD.Vector(*h.value(*cv))
            if (getattr(obj, name) - value).Length > 0:
                setattr(obj, name, value)
    _CACHE[_key(obj)] = h


def make_hspline(doc, h, name="HSpline"):
    obj = doc.addObject("Part::FeaturePython", name)
    HSplineFeature(obj)
    if FreeCAD.GuiUp:
        import FRepHSplineView
        FRepHSplineView.ViewProviderHSpline(obj.ViewObject)
    store(obj, h)
    return obj


def make_plane(doc, cvs_u=8, cvs_v=8, size_u=100.0, size_v=100.0, name="HSpline"):
    return make_hspline(doc, frepcore.HSpline.plane(cvs_u, cvs_v, size_u, size_v), name)


def make_cylinder(doc, cvs_around=8, cvs_along=8, radius=20.0, height=60.0, name="HSpline"):
    return make_hspline(doc, frepcore.HSpline.cylinder(cvs_around, cvs_along, radius, height), name)


def make_torus(doc, cvs_around=10, cvs_tube=8, major_radius=30.0, minor_radius=10.0,
               name="HSpline"):
    return make_hspline(doc, frepcore.HSpline.torus(cvs_around, cvs_tube, major_radius,
                                                    minor_radius), name)


def hspline_from_surface(surface, label="the face"):
    """A level-0 frepcore.HSpline with exactly the surface of a Part B-spline surface (degree
    raised to 3 where lower; rational or higher-degree surfaces are refused with the reason)."""
    import Part
    if not isinstance(surface, Part.BSplineSurface):
        raise ValueError("%s is a %s, not a B-spline surface; convert it first (Part > Convert "
                         "to NURBS) or start from a plane, cylinder or torus"
                         % (label, type(surface).__name__))
    s = surface.copy()
    if s.isURational() or s.isVRational():
        raise ValueError("%s is rational (it has weights, as exact circles do); an hspline is "
                         "a polynomial B-spline, so it cannot take it exactly" % label)
    if s.UDegree > 3 or s.VDegree > 3:
        raise ValueError("%s has degree %d x %d; an hspline is bicubic (degree 3 at most)"
                         % (label, s.UDegree, s.VDegree))
    s.increaseDegree(3, 3)
    axes = []
    for knots, mults, periodic in ((s.getUKnots(), s.getUMultiplicities(), s.isUPeriodic()),
                                   (s.getVKnots(), s.getVMultiplicities(), s.isVPeriodic())):
        if periodic:  # one period: every knot but the closing one, with its multiplicity
            flat = [k for k, m in zip(knots[:-1], mults[:-1]) for _ in range(m)]
            axes.append((flat, knots[-1] - knots[0]))
        else:
            axes.append(([k for k, m in zip(knots, mults) for _ in range(m)], 0.0))
    poles = s.getPoles()  # [u][v]
    nu, nv = len(poles), len(poles[0])

    def ours(k, n, periodic):  # our CV c is OpenCASCADE's pole (c + 3) mod n when periodic
        return (k + 3) % n if periodic else k

    positions = [tuple(poles[ours(i, nu, s.isUPeriodic())][ours(j, nv, s.isVPeriodic())])
                 for j in range(nv) for i in range(nu)]
    return frepcore.HSpline.from_grid(axes[0][0], axes[0][1], axes[1][0], axes[1][1], positions)


def make_from_face(doc, face, label="the face", name="HSpline"):
    """An hspline whose level 0 is the (untrimmed) B-spline surface of a Part face."""
    return make_hspline(doc, hspline_from_surface(face.Surface, label), name)


# -- CVs with a property of their own -------------------------------------------------------
def cv_property(level, i, j):
    """The name of a CV's own property (expose_cv)."""
    return "%s%d_%d_%d" % (CV_PREFIX, level, i, j)


def exposed_cvs(obj):
    """{(level, i, j): property name} of the CVs with a property of their own."""
    out = {}
    for name in obj.PropertiesList:
        if name.startswith(CV_PREFIX) and obj.getGroupOfProperty(name) == CV_GROUP:
            try:
                cv = tuple(int(v) for v in name[len(CV_PREFIX):].split("_"))
            except ValueError:
                continue
            if len(cv) == 3:
                out[cv] = name
    return out


def expose_cv(obj, cv):
    """Gives a CV a vector property of its own (its value: level 0 a position, finer levels
    the offset along the parent's u tangent, v tangent and normal), which the property view,
    expressions and spreadsheets can drive; it takes the place of the CV's entry in CvValues.
    A fixed CV is refused. Returns the property's name."""
    h = _shared(obj)
    if not h.has_cv(*cv):
        raise ValueError("%s: there is no CV %s" % (obj.Label, tuple(cv)))
    if not h.movable(*cv):
        raise ValueError("%s: CV (level %d, i %d, j %d) is fixed, so it gets no property of its "
                         "own; refine around it first" % ((obj.Label,) + tuple(cv)))
    name = cv_property(*cv)
    if name not in obj.PropertiesList:
        doc = ("CV (level %d, i %d, j %d): " % tuple(cv)) + (
            "its position" if cv[0] == 0 else
            "its offset along the parent's u tangent, v tangent and normal")
        obj.addProperty("App::PropertyVector", name, CV_GROUP, doc)
        setattr(obj, name, FreeCAD.Vector(*h.value(*cv)))
    return name


# -- tags ----------------------------------------------------------------------------------
def tags(obj):
    t = list(obj.Tagged)
    return [tuple(t[k:k + 3]) for k in range(0, len(t) - len(t) % 3, 3)]


def set_tags(obj, cvs):
    flat = []
    for c in sorted(set(tuple(c) for c in cvs)):
        flat.extend(c)
    if list(obj.Tagged) != flat:
        obj.Tagged = flat


def tag_cv(obj, cv, h=None):
    """Tags one CV for moving; a fixed CV is refused with the reason (seed 003's Softimage
    could not refuse it at selection time)."""
    h = h or _shared(obj)
    if not h.has_cv(*cv):
        raise ValueError("%s: there is no CV %s" % (obj.Label, tuple(cv)))
    if not h.movable(*cv):
        raise ValueError("%s: CV (level %d, i %d, j %d) is fixed: a CV of a refined level moves "
                         "only with the whole 7 x 7 block of CVs around it; refine around it "
                         "first" % ((obj.Label,) + tuple(cv)))
    set_tags(obj, tags(obj) + [tuple(cv)])


def tag(obj, how, level=0, region=None, mode="set"):
    """Tags by a rule: "level", "movable", "region" ((u0, u1, v0, v1) at level), "along_u",
    "along_v", "neighbours" (of the tags), "non_zero", "untag_fixed", "none". mode "add"
    adds to the tags."""
    h = _shared(obj)
    current = tags(obj)
    chosen = {
        "level": lambda: h.select_level(level),
        "movable": lambda: h.select_movable(level),
        "region": lambda: h.select_region(level, *region),
        "along_u": lambda: h.select_along_u(current),
        "along_v": lambda: h.select_along_v(current),
        "neighbours": lambda: h.select_neighbours(current),
        "non_zero": lambda: h.select_non_zero(-1),
        "untag_fixed": lambda: h.keep_movable(current),
        "none": lambda: [],
    }
    if how not in chosen:
        raise ValueError("%s: no tag rule '%s'; rules: %s" % (obj.Label, how, ", ".join(chosen)))
    cvs = chosen[how]()
    set_tags(obj, current + cvs if mode == "add" else cvs)
    return tags(obj)


# -- edits (each one property change set: one undo step inside a transaction) --------------
def _edited(obj, change, values_only=False):
    if getattr(obj.Proxy, "DERIVED", False):
        raise ValueError("%s: its CVs follow its segments; edit the CVs of its Base '%s' "
                         "instead" % (obj.Label, obj.Base.Label if obj.Base else "(none)"))
    h = hspline_of(obj)
    try:
        result = change(h)
    except ValueError as e:
        raise ValueError("%s: %s" % (obj.Label, e)) from None
    store(obj, h, values_only)
    return result


def _given_or_tagged(obj, cvs, what):
    cvs = [tuple(c) for c in (cvs if cvs is not None else tags(obj))]
    if not cvs:
        raise ValueError("%s: %s needs tagged CVs; tag some first (Tag tools, or Ctrl+click in "
                         "edit mode)" % (obj.Label, what))
    return cvs


def refine(obj, cvs=None):
    """Refines around the given CVs (default: the tagged ones); tags move to the new CVs that
    may move, so the next drag works on the new detail."""
    cvs = _given_or_tagged(obj, cvs, "Refine")
    old = _shared(obj)
    before = {c for level in range(old.level_count) for c in old.cvs(level)}

    def change(h):
        h.refine_selection(cvs)
        return [c for c in h.keep_movable([c for lv in range(h.level_count) for c in h.cvs(lv)])
                if c not in before]
    fresh = _edited(obj, change)
    set_tags(obj, fresh)
    return fresh


def zero_offsets(obj, cvs=None):
    cvs = [c for c in _given_or_tagged(obj, cvs, "Zero Offsets") if c[0] > 0]
    if not cvs:
        raise ValueError("%s: Zero Offsets acts on CVs of level 1 and finer; level 0's CVs have "
                         "positions, not offsets" % obj.Label)
    _edited(obj, lambda h: h.zero_offsets(cvs), values_only=True)


def unrefine(obj):
    """Removes the CVs with zero offsets that no detail needs, and empty levels; the surface
    does not change. Returns how many CVs went."""
    return _edited(obj, lambda h: h.unrefine())


def move_cv(obj, cv, point):
    _edited(obj, lambda h: h.move_cv(cv[0], cv[1], cv[2], tuple(point)), values_only=True)


def nudge_cvs(obj, cvs, delta=(0, 0, 0), along_normal=0.0):
    """Moves CVs by a vector in space and a distance along their own frame's normal."""
    def change(h):
        for level, i, j in cvs:
            p = FreeCAD.Vector(*h.position(level, i, j)) + FreeCAD.Vector(*delta)
            if along_normal:
                u, v = h.reference(level, i, j)
                n = h.evaluate(u, v, level - 1 if level > 0 else 0)["normal"]
                p += FreeCAD.Vector(*n) * along_normal
            h.move_cv(level, i, j, tuple(p))
    _edited(obj, change, values_only=True)


def set_make_solid(obj):
    """'To Solid': the closed hspline becomes (stays) a solid; an open one cannot."""
    h = _shared(obj)
    if not h.closed:
        raise ValueError("%s: only a closed hspline (periodic in u and v, like a torus) bounds a "
                         "solid; this one is open along %s" % (
                             obj.Label, " and ".join(a for a, p in zip("uv", h.periodic) if not p)))
    obj.MakeSolid = True


# -- files -----------------------------------------------------------------------------------
def import_hs(doc, path, name=None):
    import os
    h = frepcore.read_hs(path)
    return make_hspline(doc, h, name or os.path.splitext(os.path.basename(path))[0] or "HSpline")


def export_hs(obj, path, optimised=False):
    _shared(obj).write_hs(path, optimised)


def export_step(obj, path):
    """STEP through OpenCASCADE (a solid when closed); returns its summary dict."""
    return _shared(obj).write_step(path)


def export_mesh(obj, path, tolerance=0.01, force=False):
    """The surface tessellated within `tolerance`, checked by CGAL, written atomically only
    when printable (or with force). Returns the check report."""
    mesh = _shared(obj).tessellate(tolerance)
    report = mesh.check()
    if not report["printable"] and not force:
        raise ValueError("%s: the mesh is not printable, nothing was written:\n%s" % (
            obj.Label, report["text"]))
    mesh.write(path)
    return report
