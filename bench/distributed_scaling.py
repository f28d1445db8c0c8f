"""Brick jobs on Dask: scaling on this machine and a simulated large cluster.

Usage (from the repository root, after `make build`):
    PYTHONPATH=build/python /usr/bin/python3 bench/distributed_scaling.py MODEL CELLS \
        [--bricks 8,64] [--workers 1,2] [--format stl|3mf] [--out build/distributed-scaling.json]

For each worker count and job count: the wall time of export_distributed on a LocalCluster
(cluster start excluded), each job's seconds and peak memory, the merge, check and write
seconds and this process's peak memory. From the 64-job run's measured job times it computes
the schedule on 8 to 64 workers (longest job first onto the least loaded worker): the meshing
wall time a cluster of that size would take, plus the merge, check and write measured here.
"""

import argparse
import heapq
import json
import os
import subprocess
import sys
import tempfile
import time

import frepcore
import frepcore.distributed as fd


def schedule(times, workers):
    """Makespan of the job times on `workers` identical workers, longest job first."""
    loads = [0.0] * workers
    heapq.heapify(loads)
    for t in sorted(times, reverse=True):
        heapq.heappush(loads, heapq.heappop(loads) + t)
    return max(loads)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("model")
    ap.add_argument("cells", type=int)
    ap.add_argument("--bricks", default="8,64")
    ap.add_argument("--workers", default="1,2")
    ap.add_argument("--format", default="stl", choices=["stl", "3mf"],
                    help="the output written (both stream as the merge goes)")
    ap.add_argument("--out", default="build/distributed-scaling.json")
    ap.add_argument("--frepcad", default="build/bin/frepcad")
    a = ap.parse_args()
    from distributed import Client

    frepcore.use_one_job_memory_policy()  # as frepcad export --bricks does
    shape, _ = frepcore.load(a.model)
    frepcad = a.frepcad
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "part." + a.format)
        # one process first, as its own process (its peak would count in this one's)
        t = time.time()
        run = subprocess.run(["/usr/bin/time", "-f", "%M", frepcad, "export", a.model, "-o", out,
                              "--cells", str(a.cells), "--quiet"],
                             capture_output=True, text=True)
        rows.append({"workers": 0, "bricks": 0, "wall": time.time() - t,
                     "peak_mb": int(run.stderr.split()[-1]) / 1024.0,
                     "refused": run.stderr.strip().splitlines()[0] if run.returncode else None})
        print("one process (frepcad export): %.2f s, peak %.0f MB%s"
              % (rows[-1]["wall"], rows[-1]["peak_mb"],
                 ", refused: " + rows[-1]["refused"] if run.returncode else ""), flush=True)
        for workers in [int(w) for w in a.workers.split(",")]:
            cluster = fd.local_cluster(workers)
            client = Client(cluster)
            for bricks in [int(b) for b in a.bricks.split(",")]:
                t = time.time()
                r = fd.export_distributed(shape, out, bricks, client=client, cells=a.cells,
                                          threads_per_job=max(1, os.cpu_count() // workers))
                wall = time.time() - t
                jobs = r["jobs"]
                row = {"workers": workers, "bricks": bricks, "wall": wall,
                       "triangles": r["triangles"], "seconds": r["seconds"],
                       "job_seconds": [j["seconds"] for j in jobs],
                       "job_triangles": [j["triangles"] for j in jobs],
                       "worker_peak_mb": max(j["peak_mb"] for j in jobs),
                       "driver_peak_mb": fd.peak_memory_mb()}
                rows.append(row)
                print("%d workers, %d jobs: %.2f s wall (jobs sum %.2f s, longest %.2f s; "
                      "merge %.2f, check %.2f, write %.2f s); worker peak %.0f MB, merge "
                      "process %.0f MB" % (workers, bricks, wall, sum(row["job_seconds"]),
                                           max(row["job_seconds"]), r["seconds"][1],
                                           r["seconds"][2], r["seconds"][3],
                                           row["worker_peak_mb"], row["driver_peak_mb"]),
                      flush=True)
            client.close()
            cluster.close()
    # the simulated cluster from the one-worker run with the most jobs
    base = max((r for r in rows if r["workers"] == 1), key=lambda r: r["bricks"], default=None)
    simulated = []
    if base:
        after = base["seconds"][1] + base["seconds"][2] + base["seconds"][3]
        for w in (1, 2, 8, 16, 32, 64):
            m = schedule(base["job_seconds"], w)
            simulated.append({"workers": w, "meshing": m, "export": m + after})
            print("simulated %2d workers: meshing %.2f s, export %.2f s (merge, check and "
                  "write %.2f s here)" % (w, m, m + after, after))
    with open(a.out, "w") as f:
        json.dump({"model": a.model, "cells": a.cells, "format": a.format, "runs": rows, "simulated": simulated},
                  f, indent=1)
    print("wrote", a.out)


if __name__ == "__main__":
    sys.exit(main())
