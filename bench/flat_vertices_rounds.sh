#!/usr/bin/env bash
# Side by side, one build: frepcad export of the five reference models at 256 cells with the
# flat vertices kept (--no-drop-flat-vertices) and dropped (the default), alternated, three rounds.
# Prints per run: model, mode, triangles, meshing s, check s, export wall s, peak KB
# (docs/performance.md, "Flat vertices").
set -u
cd "$(dirname "$0")/.."
out_file=$(mktemp --suffix=.stl)
trap 'rm -f "$out_file"' EXIT
for m in sphere csg twist helix gyroid; do
  for r in 1 2 3; do
    for f in --no-drop-flat-vertices ""; do
      out=$({ /usr/bin/time -f "TIME %e %M" build/bin/frepcad export "examples/$m.json" -o "$out_file" --cells 256 $f; } 2>&1)
      tri=$(echo "$out" | sed -n 's/^meshed .*: \([0-9]*\) triangles, grid [0-9x]*, \([0-9.e-]*\) s (check \([0-9.e-]*\) s).*/\1 \2 \3/p')
      t=$(echo "$out" | sed -n 's/^TIME //p')
      echo "$m ${f:-default} $tri $t"
    done
  done
done
