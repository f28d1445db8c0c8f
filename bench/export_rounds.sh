#!/bin/bash
# Two builds of frepcad side by side in one run: each reference model exported at CELLS
# cells by the build before (BEFORE, a frepcad binary) and by this one, alternating, ROUNDS
# times; prints each build's export wall seconds (the fastest and the slowest round), its
# meshing and check seconds and its peak memory in the fastest round, and the bytes per
# triangle of that peak. This machine is shared and noisy: compare the two columns of one
# run, not runs of different days. Figures for docs/performance.md.
#   BEFORE=/path/to/old/frepcad bench/export_rounds.sh [CELLS] [MODELS...]   (ROUNDS=3)
set -euo pipefail
source "$(dirname "$0")/export_figures.sh"
figures_setup 256 "$@"
before=${BEFORE:?BEFORE=/path/to/the/other/frepcad}
rounds=${ROUNDS:-3}
echo "| model, $cells cells | build | triangles | export wall s (fastest - slowest of $rounds) | meshing s | check s | peak MB | bytes / triangle |"
echo "|---|---|---|---|---|---|---|---|"
for m in $models; do
  declare -A best=() worst=() row=()
  for ((r = 0; r < rounds; ++r)); do
    for build in before after; do
      bin=$frepcad
      [ "$build" = before ] && bin=$before
      text=$( { /usr/bin/time -f "TIME %e %M" "$bin" export "$here/examples/$m.json" -o "$out/$m.stl" --cells "$cells"; } 2>&1)
      export_fields "$text"
      read -r wall kb < <(sed -n 's/^TIME \([0-9.]*\) \([0-9]*\)/\1 \2/p' <<<"$text")
      if [ -z "${best[$build]:-}" ] || python3 -c "import sys; sys.exit(0 if $wall < ${best[$build]} else 1)"; then
        best[$build]=$wall
        row[$build]=$(printf "%s | %.3f | %.3f | %.0f | %.0f" "$tri" "$mesh" "$check" \
          "$(python3 -c "print($kb / 1024)")" "$(python3 -c "print($kb * 1024 / $tri)")")
      fi
      if [ -z "${worst[$build]:-}" ] || python3 -c "import sys; sys.exit(0 if $wall > ${worst[$build]} else 1)"; then
        worst[$build]=$wall
      fi
    done
  done
  for build in before after; do
    IFS='|' read -r tri rest <<<"${row[$build]}"
    echo "| $m | $build | ${tri% } | ${best[$build]} - ${worst[$build]} |${rest} |"
  done
  unset best worst row
done
