#!/usr/bin/env bash
# make bench: the Google Benchmark suite of libcore (results in build/bench-results.json) and
# the workbench's recompute latency in FreeCAD (build/bench-workbench.json). Figures are
# recorded in docs/performance.md. Extra arguments go to the Google Benchmark binary.
set -euo pipefail
build=${1:-build}
out="$build/bench-results.json"
"$build/bin/frepcad_bench" --benchmark_out="$out" --benchmark_out_format=json \
  --benchmark_repetitions=1 "${@:2}"
echo "results written to $out"

home="$(realpath "$build")/freecad-home"
bash scripts/install-workbench.sh "$home" >/dev/null
FREECAD_USER_HOME="$home" FREPCORE_PATH="$(realpath "$build")/python" \
  /usr/bin/python3.11 bench/workbench_latency.py "$build/bench-workbench.json" 2>&1 \
  | grep -v '^ *#\|^$\|^FreeCAD\|^©\|wouldn.t be possible'

# The same in the GUI (under Xvfb with software OpenGL: an upper bound for a real display).
FREECAD_USER_HOME="$home" FREPCORE_PATH="$(realpath "$build")/python" \
  FREP_SOURCE_DIR="$(pwd)" FREP_BENCH_OUT="$(realpath "$build")/bench-workbench-gui.json" \
  QTWEBENGINE_DISABLE_SANDBOX=1 timeout 600 xvfb-run -a -s "-screen 0 1280x1024x24" \
  freecad bench/workbench_latency_gui.FCMacro 2>&1 \
  | grep -v '^ *#\|^$\|^FreeCAD\|^©\|wouldn.t be possible\|Addon Manager\|command_buffer'
