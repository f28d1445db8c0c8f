#!/usr/bin/python3.11
"""How fast the workbench follows a drag on a big hspline (issue 15's goal: at least 30
updates a second on a 5-level surface with 10,000 CVs). Headless FreeCAD: the HSpline feature
holds the same 5-level hierarchy as bench_hspline.cpp (a torus refined over shrinking regions,
every movable CV given an offset); one update is what a drag's end does: a level-0 CV moves
(the hierarchy rebuilt from the properties, the CV moved, the properties written back) and
the document recomputes (flattening, the exact Part B-spline face and solid). The steps are
also timed alone. JSON to the path given (run by `make bench`).

    FREECAD_USER_HOME=build/freecad-home FREPCORE_PATH=build/python \\
        /usr/bin/python3.11 bench/hspline_latency.py build/bench-hspline.json
"""

import json
import math
import statistics
import sys
import time

sys.path.append("/usr/lib/freecad-python3/lib")
import FreeCAD  # noqa: E402

import FRepHSpline as H  # noqa: E402
from FRepPaths import frepcore  # noqa: E402

REPEATS = 15


def five_levels():
    h = frepcore.HSpline.torus(16, 12, 30, 10)
    for level, limit in enumerate((1 << 20, 16, 24, 30)):
        h.refine(level, [(i, j) for _, i, j in h.cvs(level) if i < limit and j < limit])
    for level in range(1, h.level_count):
        for _, i, j in h.select_movable(level):
            h.set_value(level, i, j, (0, 0, 0.05 * math.sin(0.7 * i + 1.3 * j) / level))
    return h


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
    start = FreeCAD.Vector(*H.hspline_of(obj).position(0, 5, 5))
    updates, moves, recomputes, rebuilds, faces = [], [], [], [], []
    for k in range(REPEATS):
        target = start + FreeCAD.Vector(0, 0, 0.5 * (k % 2))
        t0 = time.perf_counter()
        H.move_cv(obj, (0, 5, 5), target)
        t1 = time.perf_counter()
        doc.recompute()
        t2 = time.perf_counter()
        updates.append(t2 - t0)
        moves.append(t1 - t0)
        recomputes.append(t2 - t1)
        rebuilds.append(timed(lambda: (H._CACHE.clear(), H.hspline_of(obj))))  # cold
        faces.append(timed(lambda: obj.Proxy.execute(obj)))
    result = {
        "cvs": obj.CvCount, "levels": obj.Levels,
        "update": summary(updates),
        "updates_per_second": 1.0 / statistics.median(updates),
        "move_cv_with_properties": summary(moves),
        "recompute": summary(recomputes),
        "hierarchy_from_properties": summary(rebuilds),
        "execute_face_and_solid": summary(faces),
    }
    with open(out, "w") as f:
        json.dump(result, f, indent=1)
    print("hspline, %d CVs on %d levels: one drag update %.1f ms median (%.0f a second); "
          "move with properties %.1f ms, recompute %.1f ms (hierarchy rebuilt from properties, cold: %.1f ms)"
          % (obj.CvCount, obj.Levels, result["update"]["median_ms"], result["updates_per_second"],
             result["move_cv_with_properties"]["median_ms"], result["recompute"]["median_ms"],
             result["hierarchy_from_properties"]["median_ms"]))
    FreeCAD.closeDocument(doc.Name)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "bench-hspline.json")
