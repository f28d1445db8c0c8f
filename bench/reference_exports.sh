#!/bin/bash
# The reference exports a refactoring must leave byte for byte as they were: the five
# reference models at 256 cells with the default options, and six more with options (creases
# straightened, tips refined two levels, a tolerance, flat vertices kept without sharp
# features, marching tetrahedra, thin parts refined). Prints each file's MD5; run it with the
# build before (FREPCAD=/path/to/old/frepcad) and after, and diff the two lists.
#   bench/reference_exports.sh [OUT_DIR]
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
frepcad=${FREPCAD:-$here/build/bin/frepcad}
out=${1:-$(mktemp -d)}
mkdir -p "$out"
export_() { "$frepcad" export "$here/examples/$1.json" -o "$out/$2" --quiet "${@:3}" 2>/dev/null; }
for m in sphere csg twist helix gyroid; do export_ "$m" "$m.stl" --cells 256; done
export_ twist twist_straightened.stl --cells 128 --straighten-creases
export_ gyroid gyroid_tips.stl --cells 64 --refine tips --refine-levels 2
export_ csg csg_tolerance.stl --cells 128 --tolerance 0.05
export_ helix helix_flat_kept.obj --cells 96 --no-drop-flat-vertices --no-sharp-features
export_ sphere sphere_tetra.stl --cells 64 --mesher tetra
export_ csg csg_thin.ply --cells 100 --refine thin-parts
(cd "$out" && md5sum -- *)
