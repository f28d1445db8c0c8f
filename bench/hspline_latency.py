#!/usr/bin/python3
"""How fast the workbench follows a drag on a big hspline (the goal: at least 30
updates a second on a 5-level surface with 10,000 CVs). Headless FreeCAD: the HSpline feature
holds the same 5-level hierarchy as bench_hspline.cpp (a torus refined over shrinking regions,
every movable CV given an offset); one update is what a drag's end does: a level-0 CV moves
(the hierarchy rebuilt from the properties, the CV moved, the properties written back) and
the document recomputes (flattening, the exact Part B-spline face and solid). The steps are
also timed alone. JSON to the path given (run by `make bench`).

    FREECAD_USER_HOME=build/freecad-home FREPCORE_PATH=build/python \\
        /usr/bin/python3 bench/hspline_latency.py build/bench-hspline.json
"""

import json
import math
import statistics
import sys
import time

sys.path += ["/usr/lib/freecad-python3/lib", "/usr/lib/freecad/lib"]  # FreeCAD 0.20, 1.0
import FreeCAD  # noqa: E402

import FRepHSpline as H  # noqa: E402
from FRepPaths import frepcore  # noqa: E402

REPEATS = 15


def five_levels():
    h = frepcore.HSpline.torus(16, 12, 30, 10)
    for level, limit in enumerate((1 << 20, 16, 26, 32)):
        h.refine(level, [(i, j) for _, i, j in h.cvs(level) if i < limit and j < limit])
    for level in range(1, h.level_count):
        for _, i, j in h.select_movable(level):
            h.set_value(level, i, j, (0, 0, 0.05 * math.sin(0.7 * i + 1.3 * j) / level))
    return h


def redraw():
    """In the GUI: the 3D view takes the new face (Part's own tessellation for display) and
    draws it; nothing to do headless."""
    if FreeCAD.GuiUp:
        import FreeCADGui
        FreeCADGui.ActiveDocument.ActiveView.redraw()
        FreeCADGui.updateGui()


def timed(work):
    start = time.perf_counter()
    work()
    return time.perf_counter() - start


def summary(seconds):
    ms = sorted(1000 * s for s in seconds)
    return {"median_ms": statistics.median(ms), "min_ms": ms[0], "max_ms": ms[-1], "runs": len(ms)}


def main(out):
    doc = FreeCAD.newDocument("hspline_latency")
    obj = H.make_hspline(doc, five_levels())
    doc.recompute()
    if FreeCAD.GuiUp:
        import FreeCADGui
        FreeCADGui.ActiveDocument.ActiveView.viewIsometric()
        FreeCADGui.ActiveDocument.ActiveView.fitAll()
        redraw()
    start = FreeCAD.Vector(*H.hspline_of(obj).position(0, 5, 5))
    updates, moves, recomputes, rebuilds, faces, cold = [], [], [], [], [], []
    for k in range(REPEATS):
        target = start + FreeCAD.Vector(0, 0, 0.5 * (k % 2))
        # Side by side: the same update with the hierarchy rebuilt from the properties at
        # both steps, as before the cache (an undo or a script's property change still does).
        t0 = time.perf_counter()
        H._CACHE.clear()
        H.move_cv(obj, (0, 5, 5), target + FreeCAD.Vector(0, 0, 0.25))
        H._CACHE.clear()
        doc.recompute()
        redraw()
        cold.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        H.move_cv(obj, (0, 5, 5), target)
        t1 = time.perf_counter()
        doc.recompute()
        redraw()
        t2 = time.perf_counter()
        updates.append(t2 - t0)
        moves.append(t1 - t0)
        recomputes.append(t2 - t1)
        rebuilds.append(timed(lambda: (H._CACHE.clear(), H.hspline_of(obj))))  # cold
        faces.append(timed(lambda: obj.Proxy.execute(obj)))
    result = {
        "where": "GUI (Xvfb, software OpenGL), with redraw" if FreeCAD.GuiUp else "headless",
        "cvs": obj.CvCount, "levels": obj.Levels,
        "update": summary(updates),
        "updates_per_second": 1.0 / statistics.median(updates),
        "update_rebuilding_the_hierarchy": summary(cold),
        "move_cv_with_properties": summary(moves),
        "recompute": summary(recomputes),
        "hierarchy_from_properties": summary(rebuilds),
        "execute_face_and_solid": summary(faces),
    }
    if FreeCAD.GuiUp:
        result.update(gui_drag(doc, obj))
    with open(out, "w") as f:
        json.dump(result, f, indent=1)
    print("hspline (%s), %d CVs on %d levels: one drag update %.1f ms median (%.0f a second; %.1f ms "
          "when the hierarchy is rebuilt from the properties); "
          "move with properties %.1f ms, recompute %.1f ms (hierarchy rebuilt from properties, cold: %.1f ms)"
          % (result["where"], obj.CvCount, obj.Levels, result["update"]["median_ms"], result["updates_per_second"],
             result["update_rebuilding_the_hierarchy"]["median_ms"],
             result["move_cv_with_properties"]["median_ms"], result["recompute"]["median_ms"],
             result["hierarchy_from_properties"]["median_ms"]))
    if FreeCAD.GuiUp:
        print("hspline drag in the GUI: %.1f ms a preview frame median (%.0f a second; the "
              "surface %.1f ms, the redraw %.1f ms, a redraw of the unchanged view %.1f ms), "
              "%.0f ms to release (document change, recompute, Part's own tessellation)"
              % (result["preview_frame"]["median_ms"], 1000 / result["preview_frame"]["median_ms"],
                 result["preview_compute"]["median_ms"], result["preview_redraw"]["median_ms"],
                 result["redraw_unchanged"]["median_ms"],
                 result["release"]["median_ms"]))
    FreeCAD.closeDocument(doc.Name)


def gui_drag(doc, obj):
    """Edit mode, a dragger on level-0 CV (0, 5, 5): preview frames as the dragger moves
    (each redrawn), then the release that changes the document."""
    import FreeCADGui
    cv = (0, 5, 5)
    H.set_tags(obj, [cv])
    FreeCADGui.getDocument(doc.Name).setEdit(obj.Name, 0)
    FreeCADGui.updateGui()
    vp = obj.ViewObject.Proxy
    frames, releases, computes, draws, still = [], [], [], [], []
    for drag in range(3):
        dragger, size = vp.dragger(cv)
        vp.drag_started(cv)
        for k in range(REPEATS):
            dragger.translation.setValue(0, 0, 0.2 * (k + 1))
            frames.append(timed(lambda: (vp.drag_moved(cv, dragger, size), redraw())))
            dragger.translation.setValue(0, 0, 0.2 * (k + 1.5))
            computes.append(timed(lambda: vp.drag_moved(cv, dragger, size)))
            draws.append(timed(redraw))
            still.append(timed(redraw))  # nothing changed: what drawing the view costs here
        releases.append(timed(lambda: (vp.drag_finished(cv, dragger, size), redraw())))
        FreeCADGui.updateGui()
    FreeCADGui.getDocument(doc.Name).resetEdit()
    return {"preview_frame": summary(frames), "release": summary(releases),
            "preview_compute": summary(computes), "preview_redraw": summary(draws),
            "redraw_unchanged": summary(still)}


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "bench-hspline.json")
