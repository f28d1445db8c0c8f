#!/bin/bash
# The export of each reference model with and without simplification (--tolerance of a tenth
# of a cell), side by side in one run: triangles, meshing, simplifying and checking seconds,
# the whole export's wall time, and the STL's size. Figures for docs/performance.md.
#   bench/simplify_figures.sh [CELLS] [MODELS...]
set -euo pipefail
source "$(dirname "$0")/export_figures.sh"
figures_setup 128 "$@"
echo "| model, $cells cells | tolerance | triangles | meshing + simplifying s | of it simplifying s | check s | export wall s | STL MB |"
echo "|---|---|---|---|---|---|---|---|"
for m in $models; do
  model=$here/examples/$m.json
  # the cell: the longest side of the model's export box / cells
  cell=$(python3 -c "import json,sys; b=json.load(open(sys.argv[1]))['export']['bbox']; print(max(b[3]-b[0], b[4]-b[1], b[5]-b[2]) / int(sys.argv[2]))" "$model" "$cells")
  tol=$(python3 -c "print($cell / 10)")
  for t in none "$tol"; do
    args=()
    [ "$t" != none ] && args=(--tolerance "$t")
    start=$(date +%s.%N)
    text=$("$frepcad" export "$model" -o "$out/$m.stl" --cells "$cells" "${args[@]}")
    end=$(date +%s.%N)
    export_fields "$text"
    simp=$(sed -n 's/^simplified .* in \([0-9.e-]*\) s,.*/\1/p' <<<"$text")
    size=$(stat -c %s "$out/$m.stl")
    printf "| %s | %s | %s | %.2f | %s | %.2f | %.2f | %.1f |\n" "$m" "$t" "$tri" "$mesh" "${simp:--}" "$check" \
      "$(python3 -c "print($end - $start)")" "$(python3 -c "print($size / 1e6)")"
  done
done
