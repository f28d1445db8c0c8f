#!/bin/bash
# Mesher v2 side by side in one run: each reference model exported by marching tetrahedra
# (--mesher tetra), by cubes without sharp features (--no-sharp-features) and by cubes with them (the
# default): triangles, meshing and check seconds, the whole export's wall time and peak
# memory (bytes per triangle), and the Hausdorff distance to the exact surface in cells
# (a second run with --stats; STATS=0 skips it: it meshes at half the cell). Figures for
# docs/performance.md.
#   bench/mesher_figures.sh [CELLS] [MODELS...]
set -euo pipefail
source "$(dirname "$0")/export_figures.sh"
figures_setup 256 "$@"
echo "| model, $cells cells | mesher | triangles | meshing s | check s | export wall s | peak MB | bytes / triangle | Hausdorff cells | crease length |"
echo "|---|---|---|---|---|---|---|---|---|---|"
for m in $models; do
  model=$here/examples/$m.json
  for mode in tetra no-sharp cubes; do
    case $mode in
      tetra) args=(--mesher tetra) ;;
      no-sharp) args=(--no-sharp-features) ;;
      cubes) args=() ;;
    esac
    text=$( { /usr/bin/time -f "TIME %e %M" "$frepcad" export "$model" -o "$out/$m.stl" --cells "$cells" "${args[@]}"; } 2>&1)
    export_fields "$text"
    read -r wall kb < <(sed -n 's/^TIME \([0-9.]*\) \([0-9]*\)/\1 \2/p' <<<"$text")
    stats=""
    [ "${STATS:-1}" = 1 ] && stats=$("$frepcad" export "$model" -o "$out/$m.stl" --cells "$cells" "${args[@]}" --stats)
    hd=$(sed -n 's/^  Hausdorff distance .*(\([0-9.e-]*\) cells)/\1/p' <<<"$stats")
    crease=$(sed -n 's/^  crease length *\([0-9.e-]*\) .*/\1/p' <<<"$stats")
    printf "| %s | %s | %s | %.3f | %.3f | %.2f | %.0f | %.0f | %s | %s |\n" "$m" "$mode" "$tri" "$mesh" "$check" \
      "$wall" "$(python3 -c "print($kb / 1024)")" "$(python3 -c "print($kb * 1024 / $tri)")" "${hd:--}" "${crease:--}"
  done
done
