#!/usr/bin/env python3
"""frepcad repair on the cases a repair must not destroy: each accepted faithful to its input or
refused with its reason and figures.

Builds a corpus of meshes (scans with holes, open bowls and CAD sheets, fans, bent strips, thin
crossed panels, a thin panel rebuilt too coarse, many small pieces, crossing balls), repairs
each with `frepcad repair --json` and prints a Markdown table: pieces before and after, how far
the result lies from the input and the input from the result (outside its solid), the bound,
and the verdict with its first reason.

usage: repair_judgement.py FREPCAD [WORK_DIR] [--markdown OUT.md]
"""
import json
import math
import os
import subprocess
import sys
import tempfile


def write_obj(path, points, faces):
    with open(path, "w") as f:
        for p in points:
            f.write("v %.9g %.9g %.9g\n" % tuple(p))
        for t in faces:
            f.write("f %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1))


def read_obj(path):
    points, faces = [], []
    for line in open(path):
        w = line.split()
        if w and w[0] == "v":
            points.append(tuple(map(float, w[1:4])))
        elif w and w[0] == "f":
            faces.append(tuple(int(x.split("/")[0]) - 1 for x in w[1:4]))
    return points, faces


def box(lo, hi, n):
    """An axis-aligned box of n x n grid faces, outward, its face grids welded."""
    index, points, faces = {}, [], []

    def vertex(p):
        key = tuple(round(c, 9) for c in p)
        if key not in index:
            index[key] = len(points)
            points.append(p)
        return index[key]

    for axis in range(3):
        u, v = (axis + 1) % 3, (axis + 2) % 3
        for side in (0, 1):
            grid = {}
            for i in range(n + 1):
                for j in range(n + 1):
                    p = [0.0, 0.0, 0.0]
                    p[axis] = hi[axis] if side else lo[axis]
                    p[u] = lo[u] + (hi[u] - lo[u]) * i / n
                    p[v] = lo[v] + (hi[v] - lo[v]) * j / n
                    grid[i, j] = vertex(tuple(p))
            for i in range(n):
                for j in range(n):
                    a, b, c, d = grid[i, j], grid[i + 1, j], grid[i, j + 1], grid[i + 1, j + 1]
                    faces += [(a, b, c), (b, d, c)] if side else [(a, c, b), (b, c, d)]
    return points, faces


def joined(*meshes):
    points, faces = [], []
    for p, f in meshes:
        base = len(points)
        points += p
        faces += [tuple(base + i for i in t) for t in f]
    return points, faces


def moved(mesh, offset):
    return [tuple(c + o for c, o in zip(p, offset)) for p in mesh[0]], mesh[1]


def corpus(frepcad, work):
    """(name, what it is, mesh, extra options) for each case."""
    def ball(radius, cells):
        model = os.path.join(work, "ball%g.json" % radius)
        json.dump({"root": {"type": "sphere", "params": {"radius": radius}}}, open(model, "w"))
        out = os.path.join(work, "ball%g.obj" % radius)
        subprocess.run([frepcad, "export", model, "-o", out, "--cells", str(cells), "--quiet"],
                       check=True)
        return read_obj(out)

    ball10 = ball(10, 48)
    points, faces = ball10
    yield ("scan with holes", "a ball of radius 10 mm, 12 triangles missing",
           (points, [t for i, t in enumerate(faces) if i % 211 != 7]), [])
    bowl = (points, [t for t in faces if sum(points[v][2] for v in t) < 0])
    yield ("open bowl", "the ball's lower half", bowl, [])
    yield ("open bowl, bound 12 mm", "the same, --max-deviation 12", bowl,
           ["--max-deviation", "12"])
    sheet_points, sheet_faces = [], []
    for i in range(31):  # a quarter cylinder shell, radius 40 mm, 60 mm long, open
        a = math.pi / 2 * i / 30
        for z in (0.0, 60.0):
            sheet_points.append((40 * math.cos(a), 40 * math.sin(a), z))
    for i in range(30):
        sheet_faces += [(2 * i, 2 * i + 2, 2 * i + 1), (2 * i + 1, 2 * i + 2, 2 * i + 3)]
    yield ("curved CAD sheet", "a quarter cylinder, open",
           (sheet_points, sheet_faces), [])
    fan = [(0.0, 0.0, 0.0)] + [(5 * math.cos(2 * math.pi * i / 24),
                                 5 * math.sin(2 * math.pi * i / 24), 0.0) for i in range(24)]
    yield ("fan", "24 slivers round a point, flat", (fan, [(0, 1 + i, 1 + (i + 1) % 24)
                                                          for i in range(24)]), [])
    strip = []
    for i in range(7):
        x, z = (i, 0) if i < 4 else (3, i - 3)
        strip += [(x, 0, z), (x, 1, z)]
    yield ("bent strip", "12 triangles bent at a right angle",
           (strip, [t for i in range(6) for t in ((2 * i, 2 * i + 2, 2 * i + 1),
                                                  (2 * i + 1, 2 * i + 2, 2 * i + 3))]), [])
    squares = joined(*[moved(([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)],
                              [(0, 1, 2), (0, 2, 3)]), (3 * (i % 7), 3 * (i // 7), 0))
                       for i in range(47)])
    yield ("47 loose squares", "47 open pieces of two triangles", squares, [])
    panels = joined(box((-3, -3, -0.0125), (3, 3, 0.0125), 6),
                    box((-3, -0.0125, -3), (3, 0.0125, 3), 6))
    yield ("thin crossed panels", "two 6 x 6 x 0.025 panels crossing", panels, [])
    yield ("thin panel, coarse rebuild", "20 x 20 x 0.04, --rebuild always --voxel 2",
           box((-10, -10, -0.02), (10, 10, 0.02), 6), ["--rebuild", "always", "--voxel", "2"])
    small = ball(0.4, 12)
    bed = joined(*[moved((small[0], [t for k, t in enumerate(small[1]) if k != 5 * i]),
                         (i % 4, i // 4, 0)) for i in range(12)])
    yield ("12 balls with holes", "a print bed of 12 pieces, one hole each", bed, [])
    yield ("crossing balls", "two balls of radius 10 mm, 10 mm apart",
           joined(ball10, moved(ball10, (10, 2, 0))), [])


def main():
    args = sys.argv[1:]
    markdown = None
    if "--markdown" in args:
        i = args.index("--markdown")
        markdown = args[i + 1]
        del args[i:i + 2]
    frepcad = args[0]
    work = args[1] if len(args) > 1 else tempfile.mkdtemp(prefix="repair_judgement_")
    os.makedirs(work, exist_ok=True)
    rows = ["| case | input | pieces in / out | result to input | input to result | bound "
            "| verdict |", "|---|---|---|---|---|---|---|"]
    for n, (name, what, (points, faces), extra) in enumerate(corpus(frepcad, work)):
        src = os.path.join(work, "case_%02d.obj" % n)
        out = os.path.join(work, "case_%02d_repaired.stl" % n)
        write_obj(src, points, faces)
        if os.path.exists(out):
            os.remove(out)
        p = subprocess.run([frepcad, "repair", src, "-o", out, "--json"] + extra,
                           capture_output=True, text=True)
        if p.returncode not in (0, 1):
            verdict = "exit %d: %s" % (p.returncode, p.stderr.strip())
            rows.append("| %s | %s | - | - | - | - | %s |" % (name, what, verdict))
            continue
        r = json.loads(p.stdout)
        why = (r["departures"] + r["reasons"] + [""])[0] if r["triangles"] else r["actions"][-1]
        if p.returncode == 0:
            verdict = "accepted, written"
            verdict += "".join("; " + a for a in r["actions"] if "was not kept" in a)
        else:
            verdict = "refused, nothing written: " + why
        assert os.path.exists(out) == (p.returncode == 0), name
        dev = lambda key: "%.3g" % r[key] if r["triangles"] else "-"
        rows.append("| %s | %s, %d triangles | %d / %s | %s | %s | %.3g | %s |" % (
            name, what, len(faces), r["pieces_before"],
            r["pieces"] if r["triangles"] else 0, dev("result_to_input"),
            dev("input_to_result"), r["deviation_bound"], verdict))
    table = "\n".join(rows) + "\n"
    print(table)
    if markdown:
        open(markdown, "w").write(table)


if __name__ == "__main__":
    main()
