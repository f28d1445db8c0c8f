#!/usr/bin/env python3
"""Fuzz test of frepcad: random mutations of the example models (JSON and HyperFun), of small
meshes (STL, OBJ, PLY, OFF, 3MF) and of an OpenVDB file, each run through `frepcad export`, `check`,
`check --print`, `repair`, `compare`, `deform` or `info`.

Asserts for every case: no signal (no crash), exit status 0, 1 or 2 only, at most a few lines
on stderr and none of a library's own exception text, no file or temporary file left in the
output folder beyond the output itself, and an existing output file untouched when the
command fails.

usage: fuzz_cli.py FREPCAD SOURCE_DIR CASES [SEED]     (make test: 2,000 cases; make fuzz: more)
"""
import concurrent.futures
import json
import math
import os
import random
import shutil
import subprocess
import sys
import tempfile

TOKENS = ["NaN", "Infinity", "-Infinity", "1e999", "-1e999", "-1", "0", "1e-320", "1e308",
          '"x"', "[]", "{}", "null", "true", '"ref"', "\xff\xfe", '{"type": "sphere"}',
          '{"ref": "a"}', ",", ":", "[", "{", '"', "\\u0000", '"frepcad": 99', '"exprot": 1',
          "9" * 400, "[[[[[[[[[[", "-0", "0.0000000000000000000000001"]
# HyperFun words and shapes a mutation inserts into a .hf program
HF_TOKENS = ["hfSphere(x, c, 1)", "hfBlock(", "while 1 = 1 loop ", "endloop;", "if ", " then ",
             "endif;", " | ", " \\ ", "~", "x[", "a[1]", "array q[1000000];", "(((((", "^",
             "--", "my_model", "hfNoiseG(x, 1, 1, 1)", "x[0]", "x[4]", "1e999", "/ 0", "@"]
STATUS = {}  # exit status -> cases, to show the cases reach past the parser
LIBRARY_TEXT = ("json.exception", "terminate called", "Traceback", "what():", "basic_string",
                "std::", "Segmentation", "Aborted", "\x1b[")


def mutate_text(rng, text, tokens=TOKENS):
    data = bytearray(text.encode("utf-8", "surrogateescape"))
    for _ in range(rng.randint(1, 3)):
        kind = rng.randrange(7)
        if not data:
            data = bytearray(b"{}")
        at = rng.randrange(len(data))
        if kind == 0:  # flip a byte
            data[at] = rng.randrange(256)
        elif kind == 1:  # delete a span
            del data[at:at + rng.randint(1, 40)]
        elif kind == 2:  # duplicate a span
            span = data[at:at + rng.randint(1, 200)]
            data[at:at] = span
        elif kind == 3:  # insert a token
            data[at:at] = rng.choice(tokens).encode("utf-8", "surrogateescape")
        elif kind == 4:  # truncate
            del data[at:]
        elif kind == 5:  # replace a number
            digits = [i for i, c in enumerate(data) if chr(c).isdigit()]
            if digits:
                i = rng.choice(digits)
                data[i:i + 1] = rng.choice(["1e308", "-1e308", "0", "-5", "1e-300", "NaN",
                                            "123456789"]).encode()
        else:  # structural: a value replaced in parsed JSON
            try:
                doc = json.loads(bytes(data))
                paths = []

                def walk(v, path):
                    paths.append(path)
                    if isinstance(v, dict):
                        for k in v:
                            walk(v[k], path + [k])
                    elif isinstance(v, list):
                        for i, x in enumerate(v):
                            walk(x, path + [i])
                walk(doc, [])
                path = rng.choice(paths[1:] or [[]])
                target = doc
                for p in path[:-1]:
                    target = target[p]
                if path:
                    target[path[-1]] = rng.choice(
                        [None, True, -1, 0, 1e308, -1e-308, "sphere", "x", [], {}, [1, 2, 3],
                         [[0, 0, 0]] * 3, {"type": "union"}, {"ref": "nothing"}, 10 ** 30])
                data = bytearray(json.dumps(doc).encode())
            except (ValueError, RecursionError):
                pass
    return bytes(data)


def mutate_mesh(rng, data):
    data = bytearray(data)
    kind = rng.randrange(5)
    if kind == 0 and len(data) > 84:  # a binary STL's triangle count lies
        data[80:84] = rng.randrange(2 ** 32).to_bytes(4, "little")
    elif kind == 1:
        del data[rng.randrange(len(data)):]
    elif kind == 2:
        for _ in range(rng.randint(1, 20)):
            data[rng.randrange(len(data))] = rng.randrange(256)
    elif kind == 3:
        at = rng.randrange(len(data))
        data[at:at] = rng.choice([b"\nf 1 2 99999\n", b"\nv nan nan nan\n", b"element x 99\n",
                                  b"facet normal\n", b"\x00" * 50, b"endsolid\n", b"-1 -1 -1\n",
                                  b"\nf 1.9 2.9 3.9\n", b"1abc", b"\nf 0 1 2\n",
                                  b"property int128 x\n", b"\n99999999 99999999 0\n",
                                  b"\n5 0 1 2\n", b" one "])
    else:
        at = rng.randrange(len(data))
        data[at:at + 8] = b""
    return bytes(data)


def seeds(frepcad, src, work):
    models = []
    for folder in (os.path.join(src, "examples"), os.path.join(src, "examples", "showcase")):
        for name in sorted(os.listdir(folder)):
            if name.endswith(".json") or name.endswith(".hf"):
                with open(os.path.join(folder, name), encoding="utf-8") as f:
                    models.append((os.path.splitext(name)[1], f.read()))
    meshes = []
    for fmt, ext in (("stl", ".stl"), ("stl-ascii", ".stl"), ("obj", ".obj"), ("ply", ".ply")):
        path = os.path.join(work, "seed" + ext)
        subprocess.run([frepcad, "export", os.path.join(src, "examples", "sphere.json"), "-o",
                        path, "--cells", "4", "--format", fmt, "--quiet"], check=True)
        with open(path, "rb") as f:
            meshes.append((ext, f.read()))
        os.remove(path)
    meshes.append((".off", off_of_obj(dict(meshes)[".obj"])))
    for fmt, ext, cells in (("3mf", ".3mf", "4"), ("vdb", ".vdb", "6")):
        path = os.path.join(work, "seed" + ext)
        cmd = [frepcad, "export", os.path.join(src, "examples", "sphere.json"), "-o", path,
               "--cells", cells, "--quiet"]
        subprocess.run(cmd + (["--format", fmt] if fmt != "vdb" else []), check=True)
        with open(path, "rb") as f:
            meshes.append((ext, f.read()))
    # compare takes the unchanged seed as its other mesh
    for ext, data in meshes:
        with open(os.path.join(work, "seed" + ext), "wb") as f:
            f.write(data)
    return models, meshes


def off_of_obj(obj):
    """The OBJ seed as OFF text (frepcad reads OFF but does not write it)."""
    points, faces = [], []
    for line in obj.decode().splitlines():
        words = line.split()
        if words and words[0] == "v":
            points.append(" ".join(words[1:4]))
        elif words and words[0] == "f":
            faces.append([int(w.split("/")[0]) - 1 for w in words[1:]])
    lines = ["OFF", "%d %d 0" % (len(points), len(faces))] + points
    lines += ["%d %s" % (len(f), " ".join(map(str, f))) for f in faces]
    return ("\n".join(lines) + "\n").encode()


def judge_repair(frepcad, inp, out):
    """What repair wrote, it promised printable and faithful to its input: the check must
    agree, with no more pieces than the input's and the result's surface within 2 % of the
    input's diagonal of the input's (measured by compare, independently of the repair)."""
    def run_json(*cmd):
        c = subprocess.run([frepcad] + list(cmd) + ["--json"], capture_output=True, timeout=60)
        return c.returncode, json.loads(c.stdout.decode("utf-8")) if c.stdout else None
    rc, result = run_json("check", out)
    if rc != 0:
        return ["repair wrote a mesh the check refuses"]
    _, before = run_json("check", inp)
    problems = []
    if result["components"] > before["components"]:
        problems.append("repair wrote %d pieces from %d" % (result["components"],
                                                           before["components"]))
    lo, hi = before["bbox"][:3], before["bbox"][3:]
    diagonal = math.sqrt(sum((b - a) ** 2 for a, b in zip(lo, hi)))
    _, apart = run_json("compare", inp, out)
    if apart["b_to_a"] > 0.02 * diagonal * (1 + 1e-6):
        problems.append("repair wrote surface %g from the input's (bound %g)"
                        % (apart["b_to_a"], 0.02 * diagonal))
    return problems


SIZED_NODES = (("blobby", "centers"), ("soft_objects", "centers"), ("metaballs", "centers"),
               ("convolution", "centers"), ("convolution_segments", "points"),
               ("sweep", "points"))


def sized_model(rng):
    """A model whose work grows with a list's length: 10 to 300,000 points, spread or piled."""
    kind, param = rng.choice(SIZED_NODES)
    count = int(10 ** rng.uniform(1, 5.5))
    spread = rng.choice((0.0, 1.0, 10.0, 1000.0))
    points = [[round(rng.uniform(-spread, spread), 4) for _ in range(3)] for _ in range(count)]
    return json.dumps({"root": {"type": kind, "params": {param: points}}}).encode()


def keep_case(case, index):
    """A failed case's folder copied where it outlives the run; returns where."""
    keepdir = os.path.join(tempfile.gettempdir(), "frep-fuzz-failure-%d" % index)
    shutil.rmtree(keepdir, ignore_errors=True)
    shutil.copytree(case, keepdir)
    return keepdir


def run_case(frepcad, src, work, index, kind, payload, ext, keep):
    case = os.path.join(work, "case%d" % index)
    os.makedirs(os.path.join(case, "out"))
    inp = os.path.join(case, "in" + ext)
    with open(inp, "wb") as f:
        f.write(payload)
    out = os.path.join(case, "out", "part.vdb" if ext == ".vdb" else "part.stl")
    before = None
    if keep:
        before = b"solid keep\nendsolid keep\n"
        with open(out, "wb") as f:
            f.write(before)
    if kind == "export":
        cmd = [frepcad, "export", inp, "-o", out, "--cells", "12", "--quiet"]
    elif kind == "repair":
        cmd = [frepcad, "repair", inp, "-o", out, "--quiet", "--voxel", "0.1"]
    elif kind == "print":
        cmd = [frepcad, "check", inp, "--json", "--print", "--min-wall", "0.1", "--material",
               "resin"]
    elif kind == "compare":
        cmd = [frepcad, "compare", inp, os.path.join(work, "seed" + ext), "--json"]
    elif kind == "deform":
        cmd = [frepcad, "deform", inp, "--lattice",
               os.path.join(src, "examples", "lattices", "bend.json"), "-o", out, "--quiet"]
    elif kind == "info":
        cmd = [frepcad, "info", inp]
    else:
        cmd = [frepcad, "check", inp, "--json"]
    try:
        p = subprocess.run(cmd, capture_output=True, timeout=60)
    except subprocess.TimeoutExpired:
        return "hung (60 s), kept in %s: %s" % (keep_case(case, index), " ".join(cmd))
    problems = []
    err = p.stderr.decode("utf-8", "replace")
    if p.returncode < 0:
        problems.append("killed by signal %d" % -p.returncode)
    elif p.returncode not in (0, 1, 2):
        problems.append("exit status %d" % p.returncode)
    if len(err.strip().splitlines()) > 4:
        problems.append("more than 4 lines on stderr")
    if len(err) > 4000:
        problems.append("%d characters on stderr (a value echoed whole?)" % len(err))
    for text in LIBRARY_TEXT:
        if text in err:
            problems.append("library text %r on stderr" % text)
    left = sorted(os.listdir(os.path.join(case, "out")))
    if any("tmp" in n for n in left) or len(left) > 1:
        problems.append("files left: %s" % left)
    if kind == "export" and p.returncode != 0 and keep:
        with open(out, "rb") as f:
            if f.read() != before:
                problems.append("an existing output was changed by a failed export")
    if kind == "repair" and p.returncode == 0:
        problems += judge_repair(frepcad, inp, out)
    if kind in ("repair", "deform") and p.returncode != 0 and os.path.exists(out):
        problems.append("a failed %s wrote a file" % kind)
    if kind in ("check", "print") and p.returncode in (0, 1):
        try:
            report = json.loads(p.stdout.decode("utf-8"))
            if not report["closed"] and report["volume"] is not None:
                problems.append("check gave a volume for an open surface")
        except ValueError:
            problems.append("check --json printed invalid JSON")
    STATUS[p.returncode] = STATUS.get(p.returncode, 0) + 1
    if problems:
        return "case %d (%s, kept in %s): %s\n  %s" % (index, " ".join(cmd),
                                                       keep_case(case, index),
                                                       "; ".join(problems), err[-500:])
    shutil.rmtree(case)
    return None


def main(argv):
    if len(argv) not in (4, 5):
        print(__doc__)
        return 2
    frepcad, src, cases = argv[1], argv[2], int(argv[3])
    seed = int(argv[4]) if len(argv) == 5 else 20261201
    rng = random.Random(seed)
    work = tempfile.mkdtemp(prefix="frep-fuzz-")
    try:
        models, meshes = seeds(frepcad, src, work)
        jobs = []
        for i in range(cases):
            if rng.random() < 0.01:
                jobs.append((i, "export", sized_model(rng), ".json", False))
            elif rng.random() < 0.7:
                ext, text = rng.choice(models)
                tokens = HF_TOKENS if ext == ".hf" else TOKENS
                jobs.append((i, "export", mutate_text(rng, text, tokens), ext,
                             rng.random() < 0.5))
            else:
                ext, data = rng.choice(meshes)
                if ext == ".vdb":
                    kind = rng.choice(("info", "info", "deform"))
                else:
                    kind = rng.choices(("check", "print", "repair", "compare", "deform"),
                                       (45, 20, 15, 10, 10))[0]
                jobs.append((i, kind, mutate_mesh(rng, data), ext, False))
        failures = []
        with concurrent.futures.ThreadPoolExecutor(max_workers=os.cpu_count() or 2) as pool:
            for result in pool.map(lambda j: run_case(frepcad, src, work, *j), jobs):
                if result:
                    failures.append(result)
                    print("FAIL", result, flush=True)
        print("fuzz: %d cases from seed %d; exit statuses %s" % (cases, seed, dict(sorted(STATUS.items()))))
        print("%d passed, %d failed" % (cases - len(failures), len(failures)))
        return 1 if failures else 0
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main(sys.argv))
