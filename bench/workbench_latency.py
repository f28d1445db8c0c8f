#!/usr/bin/python3
"""Recompute latency of the csg example in FreeCAD after a parameter change, headless and
(through workbench_latency_gui.FCMacro under Xvfb) in the GUI, where the time also covers
the 3D view taking the new preview and redrawing.

For each preview resolution: open examples/csg.FCStd, then repeatedly change Ball.Radius and
recompute; the time from the change to the end of the recompute is what a user waits for
the 3D view to follow (the GUI then only redraws). The recompute of the visible Part is also
broken down into its steps (tree, bounds, meshing, hand-over to FreeCAD) by timing each
step alone. Results: JSON to the path given (run by `make bench`, see scripts/bench.sh).

    FREECAD_USER_HOME=build/freecad-home FREPCORE_PATH=build/python \\
        /usr/bin/python3 bench/workbench_latency.py build/bench-workbench.json
"""

import json
import os
import statistics
import sys
import time

sys.path += ["/usr/lib/freecad-python3/lib", "/usr/lib/freecad/lib"]  # FreeCAD 0.20, 1.0
import FreeCAD  # noqa: E402

import FRepFeatures  # noqa: E402
import FRepMeshing  # noqa: E402
import FRepTree  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXAMPLE = os.path.join(ROOT, "examples", "csg.FCStd")
CELLS = (32, 48, 64, 96)
REPEATS = 15
RADII = (1.25, 1.3)


def timed(work):
    start = time.perf_counter()
    result = work()
    return time.perf_counter() - start, result


def summary(seconds):
    ms = sorted(1000 * s for s in seconds)
    return {"median_ms": statistics.median(ms), "min_ms": ms[0],
            "p90_ms": ms[int(0.9 * (len(ms) - 1))], "runs": len(ms)}


def redraw():
    """In the GUI: the 3D view draws the new preview (nothing to do headless)."""
    if FreeCAD.GuiUp:
        import FreeCADGui
        FreeCADGui.ActiveDocument.ActiveView.redraw()
        FreeCADGui.updateGui()


def measure(cells):
    doc = FreeCAD.openDocument(EXAMPLE)
    if FreeCAD.GuiUp:
        import FreeCADGui
        FreeCADGui.ActiveDocument.ActiveView.viewIsometric()
        FreeCADGui.ActiveDocument.ActiveView.fitAll()
    try:
        FRepMeshing.set_preview_cells(doc, cells)
        ball, part = doc.getObject("Ball"), doc.getObject("Part")
        latencies, drawn = [], []
        for i in range(REPEATS + 1):
            del FRepFeatures.EXECUTIONS[:]
            ball.Radius = RADII[i % 2]
            start = time.perf_counter()
            doc.recompute()  # in the GUI this includes the view provider taking the mesh
            recomputed_at = time.perf_counter()
            redraw()
            if i:  # the first run warms caches
                latencies.append(recomputed_at - start)
                drawn.append(time.perf_counter() - start)
        recomputed = sorted(name for _, name in FRepFeatures.EXECUTIONS)
        # The visible feature's recompute, step by step.
        steps = {"tree": [], "bounds": [], "mesh": [], "to_freecad": []}
        for _ in range(REPEATS):
            t, shape = timed(lambda: FRepTree.shape_of(part))
            steps["tree"].append(t)
            t, bounds = timed(shape.bounds)
            steps["bounds"].append(t)
            box, cell = FRepMeshing.display_box(part.Label, shape, cells, bounds)
            t, mesh = timed(lambda: shape.node.mesh(box, cell))
            steps["mesh"].append(t)
            t, _ = timed(lambda: FRepMeshing.set_mesh(part, FRepMeshing.to_freecad_mesh(mesh)))
            steps["to_freecad"].append(t)
        return {"preview_cells": cells, "triangles": part.Mesh.CountFacets,
                "recomputed": recomputed, "latency": summary(latencies),
                "latency_with_redraw": summary(drawn) if FreeCAD.GuiUp else None,
                "steps_median_ms": {k: summary(v)["median_ms"] for k, v in steps.items()}}
    finally:
        FreeCAD.closeDocument(doc.Name)


def mode():
    return "GUI (Xvfb, software OpenGL)" if FreeCAD.GuiUp else "headless"


def main(out):
    results = []
    for cells in CELLS:
        r = measure(cells)
        results.append(r)
        print("%s: csg, preview %3d cells: %7d triangles, recompute after Ball.Radius change: "
              "median %6.1f ms (min %6.1f, p90 %6.1f)%s; steps %s; recomputed %s"
              % (mode(), cells, r["triangles"], r["latency"]["median_ms"], r["latency"]["min_ms"],
                 r["latency"]["p90_ms"],
                 ", with redraw %.1f ms" % r["latency_with_redraw"]["median_ms"]
                 if FreeCAD.GuiUp else "",
                 ", ".join("%s %.1f" % kv for kv in r["steps_median_ms"].items()),
                 " ".join(r["recomputed"])))
    tmp = out + ".tmp"
    with open(tmp, "w") as f:
        json.dump({"benchmark": "workbench recompute latency, csg example, " + mode(),
                   "default_preview_cells": FRepMeshing.DEFAULT_PREVIEW_CELLS,
                   "cpu_count": os.cpu_count(), "results": results}, f, indent=1)
    os.replace(tmp, out)
    print("results written to %s" % out)


if __name__ == "__main__":
    main(sys.argv[1])
