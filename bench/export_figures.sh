# Sourced by bench/*_figures.sh: the common set-up and the reading of `frepcad export`'s output.
#   figures_setup DEFAULT_CELLS [CELLS] [MODELS...]
#     sets here, frepcad (FREPCAD overrides), cells, models and out (a temporary folder,
#     removed when the script exits)
#   export_fields TEXT
#     sets tri, mesh and check (triangles, meshing and check seconds) from the "meshed" line

figures_setup() {
  here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
  frepcad=${FREPCAD:-$here/build/bin/frepcad}
  cells=${2:-$1}
  shift 2 || shift $#
  models=${*:-sphere csg twist helix gyroid}
  out=$(mktemp -d)
  trap 'rm -rf "$out"' EXIT
}

export_fields() {
  tri=$(sed -n 's/^meshed .*: \([0-9]*\) triangles.*/\1/p' <<<"$1")
  mesh=$(sed -n 's/^meshed .*, \([0-9.e-]*\) s (check \([0-9.e-]*\) s)/\1/p' <<<"$1")
  check=$(sed -n 's/^meshed .*, \([0-9.e-]*\) s (check \([0-9.e-]*\) s)/\2/p' <<<"$1")
}
