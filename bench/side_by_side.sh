#!/bin/bash
# Side-by-side timing of two builds on this shared, noisy machine: rounds alternate the two,
# so a drift in the machine's speed hits both alike. Prints one line per round and build,
# then for each benchmark the ratio of the best rounds and of the medians.
#   bench/side_by_side.sh BEFORE_BIN_DIR AFTER_BIN_DIR FILTER [ROUNDS]
# e.g. git worktree add /tmp/before 7878b01 (build its frepcad_bench with this bench source),
#   bench/side_by_side.sh /tmp/before/build/bin build/bin 'InstancerAcross|AcrossHelix' 4
set -euo pipefail
before="$1" after="$2" filter="$3" rounds="${4:-4}"
for dir in "$before" "$after"; do
  [ -x "$dir/frepcad_bench" ] || { echo "side_by_side.sh: no frepcad_bench in $dir" >&2; exit 2; }
done
results=$(mktemp)
trap 'rm -f "$results"' EXIT
for r in $(seq 1 "$rounds"); do
  for side in before after; do
    dir=$before
    [ "$side" = after ] && dir=$after
    "$dir/frepcad_bench" --benchmark_filter="$filter" --benchmark_repetitions=3 \
      --benchmark_report_aggregates_only=true 2>/dev/null |
      awk -v r="$r" -v s="$side" '/_median/ {sub("/real_time_median", "", $1); print r, s, $1, $2}' |
      tee -a "$results"
  done
done
python3 - "$results" <<'PY'
import collections, statistics, sys
runs = collections.defaultdict(lambda: {"before": [], "after": []})
for line in open(sys.argv[1]):
    _, side, name, ms = line.split()
    runs[name][side].append(float(ms))
print("| benchmark | before | after | best / best | median / median |")
print("|---|---|---|---|---|")
for name, t in runs.items():
    b, a = t["before"], t["after"]
    if not b or not a:
        continue
    print("| %s | %s | %s | %.2fx | %.2fx |" % (
        name, ", ".join("%g" % x for x in b), ", ".join("%g" % x for x in a),
        min(b) / min(a), statistics.median(b) / statistics.median(a)))
PY
