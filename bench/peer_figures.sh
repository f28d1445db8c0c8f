#!/bin/bash
# The whole default export (mesh, CGAL check, STL write) beside the dense OpenVDB route's
# meshing alone (every grid point evaluated, tools::volumeToMesh), per reference model, at
# CELLS cells (default "256 512") and THREADS threads (default "1 2"), in one run of
# frepcad_bench (bench/bench_peers.cpp), the two routes alternating model by model. Prints the
# markdown table of docs/performance.md: times, their ratio (goal <= 0.5), triangles.
#   bench/peer_figures.sh [MODELS...]      (BUILD=build, CELLS, THREADS, REPS=3)
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
bench="${BUILD:-$here/build}/bin/frepcad_bench"
models="${*:-sphere csg twist helix gyroid}"
cells="${CELLS:-256 512}" threads="${THREADS:-1 2}"
json=$(mktemp)
trap 'rm -f "$json"' EXIT
alt() { tr ' ' '\n' <<<"$1" | grep -v '^$' | paste -sd'|'; }
filter="BM_(Export|OpenVdbRoute)/($(alt "$models"))/($(alt "$cells"))/($(alt "$threads"))/real_time$"
"$bench" --benchmark_filter="$filter" --benchmark_repetitions="${REPS:-3}" \
  --benchmark_enable_random_interleaving=true --benchmark_report_aggregates_only=true \
  --benchmark_out="$json" --benchmark_out_format=json >/dev/null 2>&1
python3 - "$json" <<'PY'
import json, sys
rows = {}
for b in json.load(open(sys.argv[1]))["benchmarks"]:
    if b.get("run_type") == "aggregate" and b.get("aggregate_name") != "median":
        continue  # (the median of the repetitions; a single run as it is)
    name, model, cells, threads = b["run_name"].split("/")[:4]  # BM_Export/csg/256/2
    route = name[len("BM_"):]
    rows.setdefault((model, int(cells), int(threads)), {})[route] = b
print("| model | cells | threads | export s (mesh / check) | OpenVDB route s | ratio (goal 0.5) | triangles (OpenVDB's) | verdict |")
print("|---|---|---|---|---|---|---|---|")
order = ["sphere", "csg", "twist", "helix", "gyroid"]
for key in sorted(rows, key=lambda k: (order.index(k[0]) if k[0] in order else 9, k[1], k[2])):
    r = rows[key]
    if "Export" not in r or "OpenVdbRoute" not in r:
        continue
    e, v = r["Export"], r["OpenVdbRoute"]
    es, vs = e["real_time"] / 1000.0, v["real_time"] / 1000.0
    print("| %s | %d | %d | %.3f (%.3f / %.3f) | %.3f | %.2fx | %s (%s) | %s |" % (
        key[0], key[1], key[2], es, e["mesh_s"], e["check_s"], vs, es / vs,
        format(int(e["triangles"]), ","), format(int(v["triangles"]), ","),
        "printable" if e["printable"] == 1 else "REFUSED"))
PY
