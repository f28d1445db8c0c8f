#!/usr/bin/env python3
"""frepcad repair beside admesh on meshes broken on purpose.

Makes intended shapes with frepcad export (FRep models, so the intended surface is known),
breaks each in one way per input (holes, flipped triangles, inside-out, duplicate triangles,
degenerate triangles, cracks of near-duplicate vertices, intersecting shells, dents pushed
through the surface, non-manifold fins, and several at once), repairs every input with both
tools, and judges every output with the same CGAL check (frepcad check) and its distance from
the intended shape (frepcad compare). Prints a Markdown table per defect kind and the totals.

usage: repair_comparison.py FREPCAD [WORK_DIR] [--markdown OUT.md]
"""
import json
import os
import random
import shutil
import struct
import subprocess
import sys
import tempfile
import time

MODELS = {
    # name: (model, cells); sizes in mm, like a printed part
    "ball": ({"root": {"type": "sphere", "params": {"radius": 10}}}, 48),
    "rounded_box": ({"root": {"type": "intersection", "inputs": [
        {"type": "box", "params": {"corner": [-12, -8, -6], "size": [24, 16, 12]}},
        {"type": "sphere", "params": {"radius": 14}}]}}, 48),
    "torus": ({"root": {"type": "torus", "params": {"major_radius": 10, "minor_radius": 3.5}}},
              56),
}


def run(cmd, **kw):
    t = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True, **kw)
    return p, time.perf_counter() - t


def read_stl(path):
    data = open(path, "rb").read()
    n = struct.unpack_from("<I", data, 80)[0]
    tris = []
    for i in range(n):
        v = struct.unpack_from("<12f", data, 84 + 50 * i)
        tris.append([tuple(v[3:6]), tuple(v[6:9]), tuple(v[9:12])])
    return tris


def write_stl(path, tris):
    with open(path, "wb") as f:
        f.write(b"broken on purpose".ljust(80, b" "))
        f.write(struct.pack("<I", len(tris)))
        for t in tris:
            f.write(struct.pack("<12fH", 0, 0, 0, *t[0], *t[1], *t[2], 0))


def flip(t):
    return [t[0], t[2], t[1]]


def centre(tris):
    n = 3 * len(tris)
    return [sum(p[a] for t in tris for p in t) / n for a in range(3)]


def breakers():
    """(kind, variant, function(tris, rng, shapes) -> broken tris, intended shape name)."""
    out = []

    def holes(k):
        def f(t, rng, _):
            drop = set(rng.sample(range(len(t)), k))
            return [x for i, x in enumerate(t) if i not in drop]
        return f

    def flips(share):
        def f(t, rng, _):
            return [flip(x) if rng.random() < share else x for x in t]
        return f

    def duplicates(k):
        def f(t, rng, _):
            return t + [list(t[i]) for i in rng.sample(range(len(t)), k)]
        return f

    def degenerate(k):
        def f(t, rng, _):
            extra = []
            for i in rng.sample(range(len(t)), k):
                a, b, _c = t[i]
                mid = tuple((a[d] + b[d]) / 2 for d in range(3))
                extra.append([a, mid, b] if rng.random() < 0.5 else [a, a, b])
            return t + extra
        return f

    def cracks(size):
        def f(t, rng, _):
            # every triangle keeps its own corners (STL does), some nudged apart
            return [[tuple(c + (rng.uniform(-size, size) if rng.random() < 0.3 else 0) for c in p)
                     for p in x] for x in t]
        return f

    def dent(depth):
        def f(t, rng, _):
            # the corners near one surface point pushed inward through the opposite side
            c = centre(t)
            a = t[rng.randrange(len(t))][0]
            r2 = 2.5 ** 2
            moved = {}
            for x in t:
                for p in x:
                    if sum((p[d] - a[d]) ** 2 for d in range(3)) < r2:
                        moved[p] = tuple(p[d] + depth * (c[d] - p[d]) for d in range(3))
            return [[moved.get(p, p) for p in x] for x in t]
        return f

    def fins(k):
        def f(t, rng, _):
            extra = []
            for i in rng.sample(range(len(t)), k):
                a, b, c = t[i]
                n = tuple(a[d] + (a[d] - c[d]) * 0.5 + 0.3 for d in range(3))
                extra.append([a, b, n])
            return t + extra
        return f

    def mixed(t, rng, shapes):
        return duplicates(20)(flips(0.1)(holes(6)(t, rng, shapes), rng, shapes), rng, shapes)

    for k in (1, 4, 12):
        out.append(("holes", "%d triangles removed" % k, holes(k)))
    for s in (0.02, 0.15, 0.5):
        out.append(("flipped triangles", "%d %%" % (100 * s), flips(s)))
    out.append(("inside-out", "every triangle", flips(1.01)))
    for k in (10, 200):
        out.append(("duplicate triangles", "%d" % k, duplicates(k)))
    for k in (10, 100):
        out.append(("degenerate triangles", "%d" % k, degenerate(k)))
    for s in (1e-5, 1e-3):
        out.append(("cracks (near-duplicate vertices)", "up to %g mm" % s, cracks(s)))
    for d in (1.2, 1.6):
        out.append(("dent through the surface", "%.0f %% across" % (100 * (d - 1)), dent(d)))
    for k in (1, 8):
        out.append(("non-manifold fins", "%d" % k, fins(k)))
    out.append(("mixed", "holes, flips, duplicates", mixed))
    return out


SHELL_OFFSETS = [(9, 2, 0), (6, 0, 0), (4, 4, 4), (12, 3, 1), (2, 0, 0), (10, -3, 5)]


def main(argv):
    frepcad = os.path.abspath(argv[1])
    markdown = None
    if "--markdown" in argv:
        markdown = argv[argv.index("--markdown") + 1]
        argv = argv[:argv.index("--markdown")]
    work = argv[2] if len(argv) > 2 else tempfile.mkdtemp(prefix="repair_comparison_")
    os.makedirs(work, exist_ok=True)
    admesh = shutil.which("admesh")
    shapes, cases = {}, []
    for name, (model, cells) in MODELS.items():
        mpath = os.path.join(work, name + ".json")
        json.dump(model, open(mpath, "w"))
        stl = os.path.join(work, name + ".stl")
        p, _ = run([frepcad, "export", mpath, "-o", stl, "--cells", str(cells), "--quiet"])
        if p.returncode:
            sys.exit("cannot export %s: %s" % (name, p.stderr))
        shapes[name] = read_stl(stl)
    # the small ball of the intersecting-shell cases
    small = {"root": {"type": "sphere", "params": {"radius": 8}}}
    json.dump(small, open(os.path.join(work, "ball_small.json"), "w"))
    run([frepcad, "export", os.path.join(work, "ball_small.json"), "-o",
         os.path.join(work, "ball_small.stl"), "--cells", "48", "--quiet"])
    shapes["ball_small"] = read_stl(os.path.join(work, "ball_small.stl"))

    rng = random.Random(2026)
    index = 0
    for shape in ("ball", "rounded_box", "torus"):
        for kind, variant, f in breakers():
            index += 1
            cases.append((kind, "%s, %s" % (shape, variant),
                          f(shapes[shape], rng, shapes), os.path.join(work, shape + ".stl")))
    for off in SHELL_OFFSETS:
        # the intended shape: the union of the two balls, exported from its FRep model
        model = {"root": {"type": "union", "inputs": [
            {"type": "sphere", "params": {"radius": 8}},
            {"type": "translate", "params": {"offset": list(off)},
             "inputs": [{"type": "sphere", "params": {"radius": 8}}]}]}}
        name = "union_%d_%d_%d" % off
        json.dump(model, open(os.path.join(work, name + ".json"), "w"))
        run([frepcad, "export", os.path.join(work, name + ".json"), "-o",
             os.path.join(work, name + ".stl"), "--cells", "64", "--quiet"])
        ball = shapes["ball_small"]
        moved = [[tuple(p[d] + off[d] for d in range(3)) for p in x] for x in ball]
        cases.append(("intersecting shells", "two balls %s apart" % (off,), ball + moved,
                      os.path.join(work, name + ".stl")))

    rows = []
    for i, (kind, what, tris, intended) in enumerate(cases):
        broken = os.path.join(work, "broken_%03d.stl" % i)
        write_stl(broken, tris)
        row = {"kind": kind, "what": what, "triangles": len(tris)}
        for tool in ("frepcad", "admesh"):
            out = os.path.join(work, "%s_%03d.stl" % (tool, i))
            if os.path.exists(out):
                os.remove(out)
            if tool == "frepcad":
                p, seconds = run([frepcad, "repair", broken, "-o", out, "--force", "--quiet"])
            elif admesh:
                p, seconds = run([admesh, "--write-binary-stl=" + out, broken])
            else:
                continue
            verdict = {"printable": False, "reasons": ["no output"]}
            deviation = None
            if os.path.exists(out):
                c, _ = run([frepcad, "check", out, "--json"])
                try:
                    verdict = json.loads(c.stdout)
                except ValueError:
                    verdict = {"printable": False, "reasons": [c.stderr.strip()]}
                d, _ = run([frepcad, "compare", out, intended, "--json"])
                try:
                    deviation = json.loads(d.stdout)["hausdorff"]
                except ValueError:
                    pass
            row[tool] = {"printable": bool(verdict.get("printable")), "seconds": seconds,
                         "deviation": deviation, "reasons": verdict.get("reasons", [])}
        rows.append(row)
        print("%3d %-34s %-38s frepcad %s admesh %s" % (
            i, kind, what[:38], "ok " if row["frepcad"]["printable"] else "NO ",
            ("ok " if row["admesh"]["printable"] else "NO ") if "admesh" in row else "-"),
            flush=True)

    lines = ["| defect | inputs | frepcad repair: printable | admesh: printable | "
             "frepcad: median / largest deviation (mm) | admesh: median / largest deviation "
             "(mm) | frepcad: median time (s) | admesh: median time (s) |",
             "|---|---|---|---|---|---|---|---|"]

    def median(xs):
        xs = sorted(xs)
        return xs[len(xs) // 2] if xs else float("nan")

    def fmt_dev(xs):
        xs = [x for x in xs if x is not None]
        return "%.3f / %.3f" % (median(xs), max(xs)) if xs else "-"

    kinds = []
    for r in rows:
        if r["kind"] not in kinds:
            kinds.append(r["kind"])
    totals = {"frepcad": 0, "admesh": 0}
    for kind in kinds + ["all"]:
        rs = [r for r in rows if kind in ("all", r["kind"])]
        cells = []
        for tool in ("frepcad", "admesh"):
            ok = sum(1 for r in rs if tool in r and r[tool]["printable"])
            cells.append("%d of %d" % (ok, len(rs)))
            if kind == "all":
                totals[tool] = ok
        devs = [fmt_dev([r[t]["deviation"] for r in rs if t in r and r[t]["printable"]])
                for t in ("frepcad", "admesh")]
        times = ["%.2f" % median([r[t]["seconds"] for r in rs if t in r])
                 for t in ("frepcad", "admesh")]
        name = "**all**" if kind == "all" else kind
        lines.append("| %s | %d | %s | %s | %s | %s | %s | %s |" % (
            name, len(rs), cells[0], cells[1], devs[0], devs[1], times[0], times[1]))
    table = "\n".join(lines)
    print()
    print(table)
    if markdown:
        with open(markdown, "w") as f:
            f.write(table + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
