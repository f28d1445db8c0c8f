#!/usr/bin/env bash
# make demo: exports the reference examples to checked STL files in out/ and prints the reports.
set -euo pipefail
build=${1:-build}
mkdir -p out
for model in sphere csg; do
  echo "== frepcad export examples/$model.json -o out/$model.stl"
  "$build/bin/frepcad" export "examples/$model.json" -o "out/$model.stl"
  echo
done
echo "Meshes written to out/sphere.stl and out/csg.stl; open them in any slicer or viewer."
