#!/usr/bin/env bash
# make bench: runs the Google Benchmark suite and writes the results to build/bench-results.json
# (figures are recorded in docs/performance.md).
set -euo pipefail
build=${1:-build}
out="$build/bench-results.json"
"$build/bin/frepcad_bench" --benchmark_out="$out" --benchmark_out_format=json \
  --benchmark_repetitions=1 "${@:2}"
echo "results written to $out"
