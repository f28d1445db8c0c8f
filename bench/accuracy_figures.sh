#!/bin/bash
# The meshing's accuracy goals in one run: each reference model exported at 128, 256 and
# 512 cells with --stats (the default mesher), the gyroid again with --refine tips
# --refine-levels 2 and the twist with --straighten-creases: the check's verdict, the
# Hausdorff distance to the exact surface in cells (goal 0.5), the volume (the sphere's
# error against 4/3 pi; goal 0.1 % at 256 cells), the crease length (the twist's against
# 19.956; goal 0.5 % at 512 cells), meshing seconds, triangles and the export's peak memory.
# Figures for docs/performance.md.
#   bench/accuracy_figures.sh [MODELS...]        (CELLS="128 256" to choose the cell counts)
set -euo pipefail
source "$(dirname "$0")/export_figures.sh"
figures_setup 256 256 "$@"
echo "| model | options | cells | verdict | Hausdorff cells | volume | crease length | meshing s | triangles | peak MB |"
echo "|---|---|---|---|---|---|---|---|---|---|"
row() {  # model cells label args...
  local m=$1 n=$2 label=$3
  shift 3
  local text
  text=$( { /usr/bin/time -f "TIME %e %M" "$frepcad" export "$here/examples/$m.json" -o "$out/$m.stl" \
            --cells "$n" --stats "$@"; } 2>&1) || true
  export_fields "$text"
  local kb verdict hd vol crease extra=""
  kb=$(sed -n 's/^TIME [0-9.]* \([0-9]*\)/\1/p' <<<"$text")
  verdict=$(sed -n 's/^verdict: \(.*\)/\1/p' <<<"$text")
  hd=$(sed -n 's/^  Hausdorff distance .*(\([0-9.e-]*\) cells)/\1/p' <<<"$text")
  vol=$(sed -n 's/^  volume  *\([0-9.e-]*\)$/\1/p' <<<"$text" | tail -1)
  crease=$(sed -n 's/^  crease length *\([0-9.e-]*\) .*/\1/p' <<<"$text")
  case $m in
    sphere) extra=" ($(python3 -c "import math; print('%+.4f %%' % (100 * ($vol / (4 / 3 * math.pi) - 1)))"))" ;;
  esac
  local cextra=""
  [ "$m" = twist ] && [ -n "$crease" ] && cextra=" ($(python3 -c "print('%+.2f %%' % (100 * ($crease / 19.956 - 1)))"))"
  printf "| %s | %s | %s | %s | %.3f | %s%s | %s%s | %.2f | %s | %.0f |\n" "$m" "$label" "$n" "${verdict:--}" \
    "${hd:-nan}" "${vol:--}" "$extra" "${crease:--}" "$cextra" "${mesh:-0}" "${tri:--}" \
    "$(python3 -c "print(${kb:-0} / 1024)")"
}
for m in $models; do
  for n in ${CELLS:-128 256 512}; do
    row "$m" "$n" default
    case $m in
      gyroid) row "$m" "$n" "--refine tips --refine-levels 2" --refine tips --refine-levels 2 ;;
      twist) row "$m" "$n" "--straighten-creases" --straighten-creases ;;
    esac
  done
done
