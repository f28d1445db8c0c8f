#!/bin/bash
# The table docs/performance.md opens with: each reference model exported at CELLS cells (256
# by default) with the default options, as a user runs it: the whole export's wall seconds
# (mesh, CGAL check, write), its meshing and check seconds, the triangles, the process's peak
# memory and that per triangle, and the verdict. One run on one machine: compare its rows,
# not runs of different days.
#   bench/current_figures.sh [MODELS...]        (CELLS=512 for another size)
set -euo pipefail
source "$(dirname "$0")/export_figures.sh"
figures_setup 256 "${CELLS:-256}" "$@"
echo "| model | cells | export s | meshing s | check s | triangles | peak MB | bytes / triangle | verdict |"
echo "|---|---|---|---|---|---|---|---|---|"
for m in $models; do
  text=$( { /usr/bin/time -f "TIME %e %M" "$frepcad" export "$here/examples/$m.json" \
            -o "$out/$m.stl" --cells "$cells"; } 2>&1) || true
  export_fields "$text"
  wall=$(sed -n 's/^TIME \([0-9.]*\) [0-9]*/\1/p' <<<"$text")
  kb=$(sed -n 's/^TIME [0-9.]* \([0-9]*\)/\1/p' <<<"$text")
  verdict=$(sed -n 's/^verdict: \(.*\)/\1/p' <<<"$text")
  printf "| %s | %s | %s | %.3f | %.3f | %s | %.0f | %.0f | %s |\n" "$m" "$cells" "${wall:--}" \
    "${mesh:-0}" "${check:-0}" "${tri:--}" "$(python3 -c "print(${kb:-0} / 1024)")" \
    "$(python3 -c "print(${kb:-0} * 1024 / max(1, ${tri:-0}))")" "${verdict:--}"
done
