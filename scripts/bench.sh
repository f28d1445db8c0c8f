#!/usr/bin/env bash
# make bench: the Google Benchmark suite of libcore (results in build/bench-results.json), the
# export's phases (build/bench-phases.md) and
# the workbench's recompute latency in FreeCAD (build/bench-workbench.json). Figures are
# recorded in docs/performance.md. Extra arguments go to the Google Benchmark binary.
set -euo pipefail
build=${1:-build}
. "$build/frep-env.sh"  # FREP_PYTHON: the Python FreeCAD runs
out="$build/bench-results.json"
"$build/bin/frepcad_bench" --benchmark_out="$out" --benchmark_out_format=json \
  --benchmark_repetitions=1 "${@:2}"
echo "results written to $out"
# Where the default export's time goes, phase by phase, on 1 and 2 threads, and its serial
# share (bench/phase_times.cpp): build/bench-phases.md.
"$build/bin/frepcad_phases" --cells 512 --rounds 2 csg helix gyroid > "$build/bench-phases.md"
echo "phases written to $build/bench-phases.md"

home="$(realpath "$build")/freecad-home"
bash scripts/install-workbench.sh "$home" >/dev/null
FREECAD_USER_HOME="$home" FREPCORE_PATH="$(realpath "$build")/python" \
  "$FREP_PYTHON" bench/workbench_latency.py "$build/bench-workbench.json" 2>&1 \
  | grep -v '^ *#\|^$\|^FreeCAD\|^©\|wouldn.t be possible'

# How fast an hspline drag updates the document: build/bench-hspline.json.
FREECAD_USER_HOME="$home" FREPCORE_PATH="$(realpath "$build")/python" \
  "$FREP_PYTHON" bench/hspline_latency.py "$build/bench-hspline.json" 2>&1 \
  | grep -v '^ *#\|^$\|^FreeCAD\|^©\|wouldn.t be possible'

# The same in the GUI (under Xvfb with software OpenGL: an upper bound for a real display).
FREP_BENCH_OUT="$(realpath "$build")/bench-workbench-gui.json" \
  bash scripts/run-freecad-gui.sh "$build" bench/workbench_latency_gui.FCMacro \
  "$build/bench-workbench-gui.log"
grep "csg," "$build/bench-workbench-gui.log"

# The hspline drag in the GUI, with the 3D view taking and drawing the new face.
FREP_BENCH_OUT="$(realpath "$build")/bench-hspline-gui.json" \
  bash scripts/run-freecad-gui.sh "$build" bench/hspline_latency_gui.FCMacro \
  "$build/bench-hspline-gui.log"
grep "^hspline" "$build/bench-hspline-gui.log"
