#!/usr/bin/env bash
# make demo: exports the reference examples to checked STL files in out/ and prints the
# reports: two JSON models, then a FreeCAD document made with the workbench, with one of its
# spreadsheet cells overridden from the command line (FreeCAD runs headless).
set -euo pipefail
build=${1:-build}
mkdir -p out
for model in sphere csg; do
  echo "== frepcad export examples/$model.json -o out/$model.stl"
  "$build/bin/frepcad" export "examples/$model.json" -o "out/$model.stl"
  echo
done
doc_args=(examples/csg_spreadsheet.FCStd --set Parameters.Hole=0.35 --set PartMesh.Cells=128
          -o out/csg_spreadsheet.stl)
echo "== frepcad export ${doc_args[*]}"
"$build/bin/frepcad" export "${doc_args[@]}"
echo
echo "Meshes written to out/sphere.stl, out/csg.stl and out/csg_spreadsheet.stl (holes of"
echo "radius 0.35 instead of the document's 0.5); open them in any slicer or viewer."
echo "Open examples/csg_spreadsheet.FCStd in FreeCAD (FRep workbench) to edit the model."
