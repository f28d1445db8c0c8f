#!/usr/bin/env bash
# frepcad command-line behaviour: exit codes and one-line messages for each bad-input class.
# usage: cli_test.sh FREPCAD SOURCE_DIR
set -u
frepcad=$1
src=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
passes=0

# expect CODE PATTERN -- command...: exit code and a pattern in stdout+stderr
expect() {
  local code=$1 pattern=$2
  shift 3
  local out rc
  out=$("$@" 2>&1)
  rc=$?
  if [ "$rc" -ne "$code" ] || ! grep -qE -- "$pattern" <<<"$out"; then
    echo "FAIL: $* -> exit $rc (want $code), output:"
    echo "$out" | head -20
    failures=$((failures + 1))
  else
    passes=$((passes + 1))
  fi
}

expect 0 "verdict: printable" -- "$frepcad" export "$src/examples/sphere.json" -o "$work/s.stl" --resolution 0.1
# one version number: the workbench's package.xml
expect 0 "^frepcad $(sed -n 's|.*<version>\(.*\)</version>.*|\1|p' "$src/Mod/FRep/package.xml")$" -- "$frepcad" --version
expect 0 "verdict: printable" -- "$frepcad" check "$work/s.stl"
expect 0 '"printable": true' -- "$frepcad" check "$work/s.stl" --json
# The strut-infilled bracket (octet struts inside a skin, two holes) exports printable.
expect 0 "verdict: printable" -- "$frepcad" export "$src/examples/strut_bracket.json" -o "$work/struts.stl" --resolution 0.25
# ... and as a 3MF beam lattice, read back by lib3mf; --beams wants a 3MF and a strut lattice
expect 0 "lib3mf reads [1-9][0-9]* beams back" -- "$frepcad" export "$src/examples/strut_bracket.json" -o "$work/struts.3mf" --beams --resolution 0.25
expect 2 "give OUT.3mf" -- "$frepcad" export "$src/examples/strut_bracket.json" -o "$work/struts2.stl" --beams
expect 2 "root must be the intersection of a strut_lattice or voronoi_foam and a part" -- "$frepcad" export "$src/examples/csg.json" -o "$work/csg_beams.3mf" --beams
expect 0 "wrote .*s.obj" -- "$frepcad" export "$src/examples/csg.json" -o "$work/s.obj" --resolution 0.1
expect 0 "wrote .*s.ply" -- "$frepcad" export "$src/examples/csg.json" -o "$work/s.ply" --format ply --resolution 0.1
expect 0 "verdict: printable" -- "$frepcad" check "$work/s.ply"
# --tolerance: simplified (far fewer triangles), checked, written; the options are checked
expect 0 "simplified [0-9]+ -> [0-9]+ triangles" -- "$frepcad" export "$src/examples/csg.json" -o "$work/t.stl" --resolution 0.1 --tolerance 0.01
expect 0 "verdict: printable" -- "$frepcad" check "$work/t.stl"
full=$("$frepcad" export "$src/examples/csg.json" -o "$work/full.stl" --resolution 0.1 --quiet; stat -c %s "$work/full.stl")
small=$(stat -c %s "$work/t.stl")
[ $((small * 4)) -lt "$full" ] || { echo "FAIL: --tolerance did not shrink the file ($small vs $full bytes)"; exit 1; }
expect 0 "simplified" -- "$frepcad" export "$src/examples/csg.json" -o "$work/t2.obj" --resolution 0.1 --tolerance 0.01 --no-sharp
expect 2 "--tolerance must be a distance > 0 \(model units\), got 0" -- "$frepcad" export "$src/examples/csg.json" -o "$work/x.stl" --tolerance 0
expect 0 "Hausdorff distance   [0-9.e-]+ \([0-9.e-]+ cells\)" -- "$frepcad" export "$src/examples/sphere.json" -o "$work/st.stl" --resolution 0.1 --stats
expect 0 "^ +largest at \([-0-9.e]+, [-0-9.e]+, [-0-9.e]+\)$" -- "$frepcad" export "$src/examples/sphere.json" -o "$work/st.stl" --resolution 0.1 --stats
expect 0 "crease length        [0-9.e-]+" -- "$frepcad" export "$src/examples/csg.json" -o "$work/st.stl" --resolution 0.1 --tolerance 0.01 --stats
expect 0 "wrote" -- "$frepcad" export "$src/examples/csg.json" -o "$work/ns.stl" --resolution 0.1 --no-sharp
# --straighten-creases: the twist's creases merged onto and flipped along, checked, written;
# the crease length comes nearer the exact 19.956
expect 0 "straightened creases: [1-9][0-9]* vertices merged onto them and [0-9]+ edges flipped along them" -- "$frepcad" export "$src/examples/twist.json" -o "$work/sc.stl" --cells 48 --straighten-creases
crease() { "$frepcad" export "$src/examples/twist.json" -o "$work/sc.stl" --cells 64 --stats "$@" | sed -n 's/^  crease length *\([0-9.]*\).*/\1/p'; }
plain=$(crease); straight=$(crease --straighten-creases)
awk -v a="$plain" -v b="$straight" 'BEGIN { exit !(a - 19.956 > 3 * (b - 19.956 < 0 ? 19.956 - b : b - 19.956)) }' ||
  { echo "FAIL: --straighten-creases did not bring the crease length nearer ($plain -> $straight)"; failures=$((failures + 1)); }
expect 2 "--straighten-creases needs --sharp-features \(they find the creases\): turn --sharp-features on or --straighten-creases off" -- "$frepcad" export "$src/examples/twist.json" -o "$work/x.stl" --straighten-creases --no-sharp-features
expect 2 "--straighten-creases applies to meshes, not to a .vdb level set" -- "$frepcad" export "$src/examples/twist.json" -o "$work/x.vdb" --straighten-creases
# a document's Polygonize features take the meshing flags given over their own properties
doc_triangles() { "$frepcad" export "$src/examples/twist.FCStd" -o "$work/doc.stl" --quiet "$@" && echo $((($(stat -c %s "$work/doc.stl") - 84) / 50)); }
plain=$(doc_triangles); straight=$(doc_triangles --straighten-creases)
if [ -z "$plain" ] || [ -z "$straight" ] || [ "$straight" -ge "$plain" ]; then
  echo "FAIL: --straighten-creases on a document made $straight triangles against $plain"
  failures=$((failures + 1))
fi
expect 2 "brick jobs cannot be combined with --straighten-creases yet" -- "$frepcad" export "$src/examples/twist.json" -o "$work/x.stl" --straighten-creases --bricks 8
# a ball and a fin 0.3 cell thick between two layers of grid points: printable, with a warning
echo '{"root": {"type": "union", "inputs": [{"type": "sphere", "params": {"radius": 0.5}},
  {"type": "box", "params": {"corner": [-0.015, 0.6, 0.6], "size": [0.03, 0.3, 0.3]}}]},
  "export": {"bbox": [-1, -1, -1, 1, 1, 1], "resolution": 0.1}}' >"$work/fin.json"
expect 0 "warning: solid thinner than a cell \(0.1\) passes between the grid's points at 9 grid edges" -- "$frepcad" export "$work/fin.json" -o "$work/fin.stl"
expect 0 "for example at \([-0-9.e]+, 0.65, 0.65\)" -- "$frepcad" export "$work/fin.json" -o "$work/fin.stl"
expect 0 "thinner than a cell  grid edges crossed between two grid points: 9 solid, 0 gaps \(no surface near\), 0 tips" -- "$frepcad" export "$work/fin.json" -o "$work/fin.stl" --stats
# refined: the fin is meshed at half a cell, a second piece of the printable mesh
expect 0 "cubes round parts thinner than a cell meshed again at half a cell" -- "$frepcad" export "$work/fin.json" -o "$work/fin.stl" --refine-thin-parts
expect 0 "components +2" -- "$frepcad" export "$work/fin.json" -o "$work/fin.stl" --refine-thin-parts --stats
# a fin between the half-cell grid's points: two levels of refinement mesh it at a quarter cell
echo '{"root": {"type": "union", "inputs": [{"type": "sphere", "params": {"radius": 0.5}},
  {"type": "box", "params": {"corner": [0.01, 0.6, 0.6], "size": [0.03, 0.3, 0.3]}}]},
  "export": {"bbox": [-1, -1, -1, 1, 1, 1], "resolution": 0.1}}' >"$work/fin4.json"
expect 0 "components +1" -- "$frepcad" export "$work/fin4.json" -o "$work/fin4.stl" --refine-thin-parts --stats
expect 0 "smaller cubes meshed again below that, down to a cell / 4" -- "$frepcad" export "$work/fin4.json" -o "$work/fin4.stl" --refine-thin-parts --refine-levels 2
expect 0 "components +2" -- "$frepcad" export "$work/fin4.json" -o "$work/fin4.stl" --refine-thin-parts --refine-levels 2 --stats
expect 2 "brick jobs cannot be combined with --refine yet" -- "$frepcad" export "$src/examples/twist.json" -o "$work/x.stl" --refine-tips --bricks 8
expect 2 "--refine-levels 2 applies to a refinement: set --refine to thin-parts or tips, or --refine-levels to 1" -- "$frepcad" export "$work/fin4.json" -o "$work/x.stl" --refine-levels 2
expect 2 "--refine-levels must be a whole number from 1 to 3, got 4" -- "$frepcad" export "$work/fin4.json" -o "$work/x.stl" --refine tips --refine-levels 4
expect 2 "--refine must be off, thin-parts or tips, got 'all'" -- "$frepcad" export "$work/fin4.json" -o "$work/x.stl" --refine all
# the older spellings are the same settings: the same mesh byte for byte
"$frepcad" export "$work/fin4.json" -o "$work/r1.stl" --refine thin-parts --refine-levels 2 >/dev/null
"$frepcad" export "$work/fin4.json" -o "$work/r2.stl" --refine-thin-parts --refine-levels 2 >/dev/null
cmp -s "$work/r1.stl" "$work/r2.stl" || { echo "FAIL: --refine-thin-parts is not --refine thin-parts"; failures=$((failures + 1)); }
expect 0 "wrote" -- "$frepcad" export "$src/examples/csg.json" -o "$work/tetra.stl" --resolution 0.1 --mesher tetra
# flat vertices dropped by default: printable, fewer triangles than with --keep-flat-vertices,
# and the same mesh as with --fewer-triangles (the default, still accepted)
full=$("$frepcad" export "$src/examples/csg.json" -o "$work/full.stl" --cells 64 --keep-flat-vertices | sed -n 's/^meshed .*: \([0-9]*\) triangles.*/\1/p')
fewer=$("$frepcad" export "$src/examples/csg.json" -o "$work/fewer.stl" --cells 64 | sed -n 's/^meshed .*: \([0-9]*\) triangles.*/\1/p')
if [ -z "$full" ] || [ -z "$fewer" ] || [ "$fewer" -ge "$full" ]; then
  echo "FAIL: the default made $fewer triangles against $full with --keep-flat-vertices"
  failures=$((failures + 1))
fi
"$frepcad" export "$src/examples/csg.json" -o "$work/fewer2.stl" --cells 64 --fewer-triangles >/dev/null
cmp -s "$work/fewer.stl" "$work/fewer2.stl" || { echo "FAIL: --fewer-triangles is not the default mesh"; failures=$((failures + 1)); }
expect 0 "verdict: printable" -- "$frepcad" check "$work/fewer.stl"
"$frepcad" export "$src/examples/csg.json" -o "$work/full2.stl" --cells 64 --no-drop-flat-vertices >/dev/null
cmp -s "$work/full.stl" "$work/full2.stl" || { echo "FAIL: --keep-flat-vertices is not --no-drop-flat-vertices"; failures=$((failures + 1)); }
"$frepcad" export "$src/examples/csg.json" -o "$work/ns2.stl" --resolution 0.1 --no-sharp-features >/dev/null
cmp -s "$work/ns.stl" "$work/ns2.stl" || { echo "FAIL: --no-sharp is not --no-sharp-features"; failures=$((failures + 1)); }
expect 2 "--drop-flat-vertices applies to meshes, not to a .vdb level set" -- "$frepcad" export "$src/examples/csg.json" -o "$work/x.vdb" --fewer-triangles
expect 2 "--drop-flat-vertices applies to meshes, not to a .vdb level set" -- "$frepcad" export "$src/examples/csg.json" -o "$work/x.vdb" --keep-flat-vertices
expect 2 "unknown option '--sharp-features=no'" -- "$frepcad" export "$src/examples/csg.json" -o "$work/x.stl" --sharp-features=no
expect 0 "--\[no-\]sharp-features" -- "$frepcad" export --help
[ "$(stat -c %s "$work/ns.stl")" -lt "$(stat -c %s "$work/tetra.stl")" ] || { echo "FAIL: --mesher tetra did not make more triangles"; failures=$((failures + 1)); }
expect 2 "--mesher must be cubes or tetra, got 'dual'" -- "$frepcad" export "$src/examples/csg.json" -o "$work/x.stl" --mesher dual
expect 0 "wrote" -- "$frepcad" export "$src/examples/sphere.json" -o "$work/a.stl" --format stl-ascii --resolution 0.2 --bbox -2 -2 -2 2 2 2
head -c 5 "$work/a.stl" | grep -q solid || { echo "FAIL: stl-ascii not ASCII"; failures=$((failures + 1)); }
expect 0 "radius : real = 1 \[length\]" -- "$frepcad" info sphere
expect 0 '"type": "blend_union"' -- "$frepcad" info --json
expect 0 "^# Node reference" -- "$frepcad" info --markdown

# bad input: exit 2, one clear line
expect 2 "unknown node type 'spere'" -- "$frepcad" info spere
expect 2 "cannot open the model file" -- "$frepcad" export "$work/none.json" -o "$work/x.stl"
echo '{"root": {"type": "sphere", "params": {"radius": -1}}, "export": {"bbox": [-1,-1,-1,1,1,1]}}' >"$work/bad.json"
expect 2 "root \(sphere\): parameter 'radius' -1 is out of range; allowed: \(0, inf\)" -- "$frepcad" export "$work/bad.json" -o "$work/x.stl"
echo '{"root": {"type": "halfspace"}}' >"$work/nobox.json"
expect 2 "the solid is unbounded towards .*--bbox" -- "$frepcad" export "$work/nobox.json" -o "$work/x.stl"
# no box given: the solid's own box (a unit sphere, padded by 1.5 cells of 1/128 of it)
echo '{"root": {"type": "sphere"}}' >"$work/autobox.json"
expect 0 "grid 133x133x133" -- "$frepcad" export "$work/autobox.json" -o "$work/auto.stl"
echo '{"root": {"type": "formula", "params": {"formula": "r - hypot(x, y, z) + sinn(x)"}}}' >"$work/formula.json"
expect 2 "parameter 'formula' column 22: unknown function 'sinn'" -- "$frepcad" export "$work/formula.json" -o "$work/x.stl"
expect 2 "not valid JSON" -- "$frepcad" export "$work/s.stl" -o "$work/x.stl"
expect 2 "unknown mesh file type '.step'" -- "$frepcad" export "$src/examples/sphere.json" -o "$work/x.step"
expect 2 "unknown format 'vrml'" -- "$frepcad" export "$src/examples/sphere.json" -o "$work/x.stl" --format vrml
expect 2 "--resolution expects a number" -- "$frepcad" export "$src/examples/sphere.json" -o "$work/x.stl" --resolution fine
expect 2 "larger cell size" -- "$frepcad" export "$src/examples/sphere.json" -o "$work/x.stl" --resolution 1e-7
# the memory guard: refused before any work, with the cell size that would fit
expect 2 "GB is available: use a cell size of at least .*--bricks 64" -- "$frepcad" export "$src/examples/sphere.json" -o "$work/x.stl" --resolution 3e-4
expect 2 "unknown command 'exprt'" -- "$frepcad" exprt
expect 2 "cannot open a mesh file" -- "$frepcad" check "$work/none.stl"
echo "not a mesh" >"$work/junk.stl"
expect 2 "not an STL file" -- "$frepcad" check "$work/junk.stl"

# not printable: exit 1, nothing written unless --force
echo '{"root": {"type": "sphere", "params": {"center": [9, 9, 9]}}, "export": {"bbox": [-1,-1,-1,1,1,1], "resolution": 0.1}}' >"$work/empty.json"
expect 1 "refusing to write" -- "$frepcad" export "$work/empty.json" -o "$work/empty.stl"
[ ! -e "$work/empty.stl" ] || { echo "FAIL: refused export left a file"; failures=$((failures + 1)); }
# an empty solid without a box (no point inside: the bounds search finds nothing) is the same
# verdict, and so is an instancer of one
# the infilled PartDesign bracket: its one visible solid, the infill, exports printable
expect 0 "wrote .*bracket.3mf from .*bracket.FCStd \(BracketInfill\)" -- "$frepcad" export "$src/examples/bracket.FCStd" -o "$work/bracket.3mf" --cells 64
# the hspline examples: a limb attached to a torus (a mesh, written as it is) and a ring folded
# by an envelope (an hspline solid, tessellated): each one closed surface, printable
expect 0 "wrote .*limb.stl from .*attachment.FCStd \(BodyWithLimb\)" -- "$frepcad" export "$src/examples/attachment.FCStd" -o "$work/limb.stl"
expect 0 "wrote .*folded.stl from .*envelope.FCStd \(FoldedRing\)" -- "$frepcad" export "$src/examples/envelope.FCStd" -o "$work/folded.stl"
# HyperFun programs export like models (docs/hyperfun.md); a mistake names its line and column
expect 0 "verdict: printable" -- "$frepcad" export "$src/examples/mount.hf" -o "$work/mount.stl" --cells 48
# the test programs (tests/test_hyperfun.cpp checks their values): each exports printable;
# those whose extent the interval search cannot prove are meshed in HyperFun's -10..10 box
for program in "$src"/tests/data/hyperfun/*.hf; do
  expect 0 "verdict: printable" -- "$frepcad" export "$program" -o "$work/program.stl" --cells 40
done
expect 0 "meshing the box -10 -10 -10 10 10 10 \(HyperFun's" -- "$frepcad" export "$src/tests/data/hyperfun/quadrics.hf" -o "$work/program.stl" --cells 40
printf 'my_model(x[3], a[1])\n{\n  my_model = hfSphere(x, 2);\n}\n' >"$work/bad.hf"
expect 2 "bad.hf:3:14: hfsphere takes 3 arguments, not 2" -- "$frepcad" export "$work/bad.hf" -o "$work/bad.stl"
[ ! -e "$work/bad.stl" ] || { echo "FAIL: a refused program wrote a file"; failures=$((failures + 1)); }
echo '{"frepcad": 1, "root": {"type": "intersection", "inputs": [{"type": "sphere"}, {"type": "sphere", "params": {"center": [9, 0, 0]}}]}}' >"$work/none_inside.json"
expect 1 "none_inside.json: the solid is empty: no point is inside, nothing to print" -- "$frepcad" export "$work/none_inside.json" -o "$work/empty.stl"
echo '{"frepcad": 1, "root": {"type": "instancer", "inputs": [{"type": "intersection", "inputs": [{"type": "sphere"}, {"type": "sphere", "params": {"center": [9, 0, 0]}}]}]}}' >"$work/empty_copies.json"
expect 1 "the solid is empty" -- "$frepcad" export "$work/empty_copies.json" -o "$work/empty.stl"
[ ! -e "$work/empty.stl" ] || { echo "FAIL: an empty solid's export left a file"; failures=$((failures + 1)); }
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\n' >"$work/open.obj"
expect 1 "3 border edges" -- "$frepcad" check "$work/open.obj"
ls -a "$work" | grep -q 'frep-tmp-' && { echo "FAIL: temporary file left"; failures=$((failures + 1)); }

# one set of options, --help on every command, one set of exit codes
expect 0 "usage: frepcad export INPUT -o OUT" -- "$frepcad" export --help
expect 0 "130 cancelled" -- "$frepcad" export -h
expect 0 "usage: frepcad check MESH" -- "$frepcad" check --help
expect 0 "usage: frepcad info" -- "$frepcad" info --help
expect 0 "grid 17x17x17" -- "$frepcad" export "$src/examples/sphere.json" -o "$work/c.stl" --cells 16
expect 2 "give --resolution or --cells, not both" -- "$frepcad" export "$src/examples/sphere.json" -o "$work/x.stl" --cells 16 --resolution 0.1
expect 2 "--cells must be a whole number from 1 to" -- "$frepcad" export "$src/examples/sphere.json" -o "$work/x.stl" --cells 0
expect 2 "--object and --set apply to FreeCAD documents" -- "$frepcad" export "$src/examples/sphere.json" -o "$work/x.stl" --set A.B=1
# output names that must not be replaced
ln -s "$work/s.stl" "$work/link.stl"
expect 2 "is a symbolic link" -- "$frepcad" export "$src/examples/sphere.json" -o "$work/link.stl" --cells 8
mkdir -p "$work/folder.stl"
expect 2 "is a folder" -- "$frepcad" export "$src/examples/sphere.json" -o "$work/folder.stl" --cells 8
cp "$src/examples/sphere.json" "$work/self.json"
expect 2 "is the input itself" -- "$frepcad" export "$work/self.json" -o "$work/self.json" --format stl --cells 8
# a name near the 255-byte limit: the temporary name must not be longer
long="$work/$(printf 'n%.0s' $(seq 1 250)).stl"
expect 0 "wrote" -- "$frepcad" export "$src/examples/sphere.json" -o "$long" --cells 8
# the written file gets the umask's mode, not mkstemp's private 0600
(umask 022 && "$frepcad" export "$src/examples/sphere.json" -o "$work/mode.stl" --cells 8 --quiet)
[ "$(stat -c %a "$work/mode.stl")" = 644 ] || { echo "FAIL: mode $(stat -c %a "$work/mode.stl"), want 644"; failures=$((failures + 1)); }
# a failing export leaves an existing output untouched
cp "$work/s.stl" "$work/keep.stl"
expect 1 "refusing to write" -- "$frepcad" export "$work/empty.json" -o "$work/keep.stl"
cmp -s "$work/s.stl" "$work/keep.stl" || { echo "FAIL: refused export changed the existing file"; failures=$((failures + 1)); }

# Ctrl-C (SIGINT) and SIGTERM during an export: exit 130, nothing written, no temporary file
for sig in INT TERM; do
  rm -f "$work/big.stl"
  "$frepcad" export "$src/examples/gyroid.json" -o "$work/big.stl" --cells 400 --quiet &
  pid=$!
  sleep 1.5
  kill -s "$sig" "$pid"
  rc=0
  wait "$pid" || rc=$?
  if [ "$rc" -ne 130 ] || [ -e "$work/big.stl" ] || ls -a "$work" | grep -q 'frep-tmp-'; then
    echo "FAIL: SIG$sig: exit $rc (want 130), output or temporary file left"; failures=$((failures + 1))
  else
    passes=$((passes + 1))
  fi
done

# Volumes: a model as an OpenVDB level set, read back by a model (relative names from the
# model's folder, wherever frepcad runs), a mesh file as an exact solid, clear refusals.
expect 0 "wrote .*csg.vdb: grid 'surface' \(float, level set" -- "$frepcad" export "$src/examples/csg.json" -o "$work/csg.vdb" --cells 64
"$frepcad" export "$src/examples/sphere.json" -o "$work/ball.stl" --cells 48 --quiet
mkdir -p "$work/sub"
cat > "$work/vol.json" <<'JSON'
{"root": {"type": "union", "inputs": [{"type": "vdb_grid", "params": {"path": "csg.vdb"}},
  {"type": "translate", "params": {"offset": [3, 0, 0]},
   "inputs": [{"type": "mesh_sdf", "params": {"path": "ball.stl"}}]}]}}
JSON
pushd "$work/sub" >/dev/null
expect 0 "verdict: printable" -- "$frepcad" export ../vol.json -o "$work/vol.stl" --cells 96
popd >/dev/null
expect 0 "grid 'surface' \(float, level set, [0-9,]+ active voxels" -- "$frepcad" info "$work/csg.vdb"
expect 0 '"grid_class": "level set"' -- "$frepcad" info "$work/csg.vdb" --json
# a .vdb whose compressed leaf data is damaged (a fuzz case): OpenVDB's reader overruns its
# buffer and aborts; frepcad reads each file in a child first and says so in one line
expect 2 "damaged_leaf.vdb: (the OpenVDB file is damaged|not a readable OpenVDB file|the OpenVDB file ends)" -- "$frepcad" info "$src/tests/data/damaged_leaf.vdb"
expect 2 "damaged_leaf.vdb: (the OpenVDB file is damaged|not a readable OpenVDB file|the OpenVDB file ends)" -- "$frepcad" deform "$src/tests/data/damaged_leaf.vdb" --lattice "$src/examples/lattices/bend.json" -o "$work/bent.vdb"
[ ! -e "$work/bent.vdb" ] || { echo "FAIL: a failed deform wrote a file"; failures=$((failures + 1)); }
expect 0 "fog volume" -- "$frepcad" export "$src/examples/csg.json" -o "$work/fog.vdb" --cells 32 --fog
expect 2 "--fog applies to a .vdb output only" -- "$frepcad" export "$src/examples/csg.json" -o "$work/fog.stl" --fog
expect 2 "--tolerance applies to meshes, not to a .vdb level set" -- "$frepcad" export "$src/examples/csg.json" -o "$work/x.vdb" --tolerance 0.1
expect 2 "--format and --stats apply to meshes" -- "$frepcad" export "$src/examples/csg.json" -o "$work/x.vdb" --stats
sed 's/ball.stl/nothing.stl/' "$work/vol.json" > "$work/missing.json"
expect 2 "nothing.stl: cannot open the mesh file" -- "$frepcad" export "$work/missing.json" -o "$work/m.stl"
printf 'not a volume' > "$work/bad.vdb"
sed 's/csg.vdb/bad.vdb/' "$work/vol.json" > "$work/bad.json"
expect 2 "bad.vdb: not an OpenVDB file \(no OpenVDB magic number" -- "$frepcad" export "$work/bad.json" -o "$work/b.stl"
expect 2 "bad.vdb: not an OpenVDB file" -- "$frepcad" info "$work/bad.vdb"
head -c 30 "$work/csg.vdb" > "$work/cut.VDB"
expect 2 "cut.VDB: the OpenVDB file ends inside its header \(30 of at least 57 bytes\)" -- "$frepcad" info "$work/cut.VDB"
expect 2 "info takes one node type or .vdb file; got 'sphere' and 'box'" -- "$frepcad" info sphere box
[ ! -e "$work/m.stl" ] && [ ! -e "$work/b.stl" ] && [ ! -e "$work/x.vdb" ] || { echo "FAIL: a refused export left a file"; failures=$((failures + 1)); }

# OFF: checked, repaired and read by mesh_sdf like the other mesh files; strict readers
"$frepcad" export "$src/examples/sphere.json" -o "$work/ball.obj" --cells 24 --quiet
awk '$1 == "v" {v[++nv] = $2 " " $3 " " $4} $1 == "f" {split($2, a, "/"); split($3, b, "/"); split($4, c, "/");
     f[++nf] = "3 " a[1] - 1 " " b[1] - 1 " " c[1] - 1}
     END {print "OFF"; print nv, nf, 0; for (i = 1; i <= nv; i++) print v[i]; for (i = 1; i <= nf; i++) print f[i]}' \
  "$work/ball.obj" > "$work/ball.off"
expect 0 "verdict: printable" -- "$frepcad" check "$work/ball.off"
expect 2 "--material pla and --density 2 both give the density; give one" -- "$frepcad" check "$work/ball.off" --print --material pla --density 2
expect 0 "nothing to repair: the mesh is printable" -- "$frepcad" repair "$work/ball.off" -o "$work/ball-repaired.stl"
sed 's/ball.stl/ball.off/' "$work/vol.json" > "$work/off.json"
expect 0 "verdict: printable" -- "$frepcad" export "$work/off.json" -o "$work/off.stl" --cells 64
head -n 4 "$work/ball.off" > "$work/points.off"
expect 2 "points.off:2: OFF header claims" -- "$frepcad" check "$work/points.off"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\n' > "$work/cloud.obj"
expect 2 "cloud.obj: no faces \(3 vertices\)" -- "$frepcad" check "$work/cloud.obj"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1.9 2.9 3.9\n' > "$work/frac.obj"
expect 2 "frac.obj:4: '1.9' is not a whole number" -- "$frepcad" repair "$work/frac.obj" -o "$work/frac.stl"
mkdir -p "$work/scans.atos"
expect 2 "scans.atos/o: the file name has no extension; read: .stl, .obj, .ply, .off" -- "$frepcad" check "$work/scans.atos/o"
head -n -1 "$work/ball.off" > "$work/open.off"
sed -i "2s/.*/$(sed -n 2p "$work/ball.off" | awk '{print $1, $2 - 1, 0}')/" "$work/open.off"
expect 1 "volume +none \(the surface is open\)" -- "$frepcad" check "$work/open.off"
expect 1 '"volume": null' -- "$frepcad" check "$work/open.off" --json

# deform: a lattice file applied to a mesh (checked) and to a .vdb (every grid); the ffd node
expect 0 "verdict: printable" -- "$frepcad" export "$src/examples/bent_bar.json" -o "$work/bent.stl" --resolution 0.05
printf '{"root": {"type": "box", "params": {"corner": [-1.2, -0.25, -0.25], "size": [2.4, 0.5, 0.5]}}}' > "$work/bar.json"
"$frepcad" export "$work/bar.json" -o "$work/bar.stl" --cells 48 --quiet
"$frepcad" export "$work/bar.json" -o "$work/bar.vdb" --cells 48 --quiet
expect 0 "verdict: printable" -- "$frepcad" deform "$work/bar.stl" --lattice "$src/examples/lattices/bend.json" -o "$work/bent-mesh.obj"
expect 0 "grid 'surface' \(float, level set" -- "$frepcad" deform "$work/bar.vdb" --lattice "$src/examples/lattices/bend.json" -o "$work/bent.vdb"
printf '{"root": {"type": "vdb_grid", "params": {"path": "bent.vdb"}}}' > "$work/vdb-bent.json"
expect 0 "verdict: printable" -- "$frepcad" export "$work/vdb-bent.json" -o "$work/vb.stl" --cells 64
expect 2 "a mesh deforms into a mesh" -- "$frepcad" deform "$work/bar.stl" --lattice "$src/examples/lattices/bend.json" -o "$work/x.vdb"
expect 2 "--interpolation, --keep-vectors, --no-rebuild and --splat apply to .vdb files" -- "$frepcad" deform "$work/bar.stl" --lattice "$src/examples/lattices/bend.json" -o "$work/x.stl" --splat
expect 2 "deform needs --lattice" -- "$frepcad" deform "$work/bar.stl" -o "$work/x.stl"
expect 2 '"format" must be "frepcad-lattice"' -- "$frepcad" deform "$work/bar.stl" --lattice "$work/bar.json" -o "$work/x.stl"
python3 -c 'import json, sys; l = json.load(open(sys.argv[1])); l["divisions"][0] = 0; json.dump(l, open(sys.argv[2], "w"))' "$src/examples/lattices/bend.json" "$work/zero.json"
expect 2 '"divisions" must be three integers from 1 to 64' -- "$frepcad" deform "$work/bar.stl" --lattice "$work/zero.json" -o "$work/x.stl"
python3 -c 'import sys; print("[" * 100000 + "]" * 100000)' > "$work/deep.json"
expect 2 "nested deeper than a lattice file can be" -- "$frepcad" deform "$work/bar.stl" --lattice "$work/deep.json" -o "$work/x.stl"
python3 - "$src/examples/lattices/bend.json" "$work/folded.json" <<'PY'
import json, sys
lat = json.load(open(sys.argv[1]))
for p in lat["points"][4:8]:
    p[0] += 3.0  # the second plane far past the third: the map turns inside out
json.dump(lat, open(sys.argv[2], "w"))
PY
expect 2 "folds over itself in cell \(" -- "$frepcad" deform "$work/bar.stl" --lattice "$work/folded.json" -o "$work/x.stl"
[ ! -e "$work/x.stl" ] && [ ! -e "$work/x.vdb" ] || { echo "FAIL: a refused deform left a file"; failures=$((failures + 1)); }

# 3MF: export, check, units; refused options
expect 0 "wrote .*s.3mf \(3mf\)" -- "$frepcad" export "$src/examples/csg.json" -o "$work/s.3mf" --resolution 0.1 --units cm
expect 0 "verdict: printable" -- "$frepcad" check "$work/s.3mf"
unzip -p "$work/s.3mf" 3D/3dmodel.model 2>/dev/null | grep -q 'unit="centimeter"' || python3 -c 'import sys, zipfile; sys.exit(0 if b"unit=\"centimeter\"" in zipfile.ZipFile(sys.argv[1]).read("3D/3dmodel.model") else 1)' "$work/s.3mf" || { echo "FAIL: --units cm not in the 3MF"; failures=$((failures + 1)); }
expect 2 "--units applies to a 3MF output only" -- "$frepcad" export "$src/examples/csg.json" -o "$work/x.stl" --units cm
expect 2 "unknown unit 'furlong'" -- "$frepcad" export "$src/examples/csg.json" -o "$work/x.3mf" --units furlong
echo "not a zip" >"$work/bad.3mf"
expect 2 "bad.3mf: not a 3MF package" -- "$frepcad" check "$work/bad.3mf"

# repair: holes and an inside-out copy mended, the input untouched, the result printable
"$frepcad" export "$src/examples/sphere.json" -o "$work/ball.obj" --resolution 0.1 --quiet
python3 - "$work/ball.obj" "$work/holes.obj" "$work/inside.obj" <<'PY'
import sys
lines = open(sys.argv[1]).read().splitlines()
faces = [l for l in lines if l.startswith("f ")]
rest = [l for l in lines if not l.startswith("f ")]
open(sys.argv[2], "w").write("\n".join(rest + [f for i, f in enumerate(faces) if i % 97 != 5]) + "\n")
flip = lambda f: " ".join([f.split()[0]] + f.split()[1:][::-1])
open(sys.argv[3], "w").write("\n".join(rest + [flip(f) for f in faces]) + "\n")
PY
before=$(md5sum <"$work/holes.obj")
expect 1 "border edges" -- "$frepcad" check "$work/holes.obj"
expect 0 "filled [0-9]+ holes" -- "$frepcad" repair "$work/holes.obj" -o "$work/fixed.stl"
expect 0 "verdict: printable" -- "$frepcad" check "$work/fixed.stl"
[ "$(md5sum <"$work/holes.obj")" = "$before" ] || { echo "FAIL: repair changed its input"; failures=$((failures + 1)); }
expect 0 "oriented every shell" -- "$frepcad" repair "$work/inside.obj" -o "$work/out.3mf"
expect 0 "verdict: printable" -- "$frepcad" check "$work/out.3mf"
expect 0 '"printable": true' -- "$frepcad" repair "$work/inside.obj" -o "$work/out2.ply" --json
# a flat sheet cannot become a solid: exit 1, the reasons, nothing written unless --force
printf 'solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid s\n' >"$work/sheet.stl"
expect 1 "encloses no volume" -- "$frepcad" repair "$work/sheet.stl" -o "$work/sheet_fixed.stl"
[ ! -e "$work/sheet_fixed.stl" ] || { echo "FAIL: a failed repair wrote a file"; failures=$((failures + 1)); }
expect 1 "could not be made printable" -- "$frepcad" repair "$work/holes.obj" -o "$work/open.stl" --no-fill
[ ! -e "$work/open.stl" ] || { echo "FAIL: a failed repair wrote a file"; failures=$((failures + 1)); }
expect 1 "written although still not printable" -- "$frepcad" repair "$work/holes.obj" -o "$work/open_forced.stl" --no-fill --force
[ -e "$work/open_forced.stl" ] || { echo "FAIL: --force wrote nothing"; failures=$((failures + 1)); }
expect 2 "unknown rebuild policy 'sometimes'" -- "$frepcad" repair "$work/holes.obj" -o "$work/x.stl" --rebuild sometimes
expect 2 "repair needs -o OUT" -- "$frepcad" repair "$work/holes.obj"
expect 2 "--voxel must be a size > 0" -- "$frepcad" repair "$work/holes.obj" -o "$work/x.stl" --voxel 0
expect 2 "--max-deviation must be a distance > 0, got 'nan'" -- "$frepcad" repair "$work/holes.obj" -o "$work/x.stl" --max-deviation nan
# an open bowl (the ball's lower half): its cap would be invented surface a radius from the
# input, so the repair is refused with the figures and writes nothing, unless the bound
# given covers the cap
python3 - "$work/ball.obj" "$work/bowl.obj" <<'PY'
import sys
lines = open(sys.argv[1]).read().splitlines()
v = [tuple(map(float, l.split()[1:4])) for l in lines if l.startswith("v ")]
faces = [l for l in lines if l.startswith("f ")]
low = [f for f in faces if sum(v[int(w.split("/")[0]) - 1][2] for w in f.split()[1:]) < 0]
open(sys.argv[2], "w").write("\n".join([l for l in lines if not l.startswith("f ")] + low) + "\n")
PY
expect 1 "surface invented there" -- "$frepcad" repair "$work/bowl.obj" -o "$work/bowl.stl"
expect 1 "not faithful to the input .* nothing written \(--max-deviation or --allow-pieces accept it\)" -- "$frepcad" repair "$work/bowl.obj" -o "$work/bowl.stl"
[ ! -e "$work/bowl.stl" ] || { echo "FAIL: an unfaithful repair wrote a file"; failures=$((failures + 1)); }
expect 1 '"accepted": false' -- "$frepcad" repair "$work/bowl.obj" -o "$work/bowl.stl" --json
expect 0 "wrote .*bowl.stl" -- "$frepcad" repair "$work/bowl.obj" -o "$work/bowl.stl" --max-deviation 1.5
# a rebuild far beyond the memory is refused at once, naming a voxel that fits
start=$(date +%s)
expect 2 "the rebuild at voxel size 1e-05 covers about [0-9]+ million voxels of surface, needing about [0-9]+ GB.*: use a voxel size of at least" -- "$frepcad" repair "$work/ball.obj" -o "$work/x.stl" --voxel 1e-5 --rebuild always
[ $(($(date +%s) - start)) -lt 10 ] || { echo "FAIL: the too-large rebuild took $(($(date +%s) - start)) s to refuse"; failures=$((failures + 1)); }
expect 0 "Hausdorff distance   (0|[0-9.]+e-1[0-9])$" -- "$frepcad" compare "$work/ball.obj" "$work/ball.obj"

# bounded work on small hostile inputs: each refused or finished within 10 s with one clear line
python3 - "$work" <<'PY'
import math, struct, sys
def stl(path, tris):
    with open(path, "wb") as f:
        f.write(b" " * 80 + struct.pack("<I", len(tris)))
        for t in tris:
            f.write(struct.pack("<12fH", 0, 0, 0, *t[0], *t[1], *t[2], 0))
c = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
quads = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
cube = [t for q in quads for t in ((c[q[0]], c[q[1]], c[q[2]]), (c[q[0]], c[q[2]], c[q[3]]))]
stl(sys.argv[1] + "/cubes.stl", cube * 20000)              # one cube 20,000 times over
stl(sys.argv[1] + "/point.stl", [((0.5, 0.5, 0.5),) * 3] * 300000)  # triangles on one point
n = 30000                                                   # a closed bicone of 60,000 slivers
ring = [(math.cos(2 * math.pi * i / n), math.sin(2 * math.pi * i / n), 0) for i in range(n)]
stl(sys.argv[1] + "/bicone.stl", [t for i in range(n) for t in (
    ((0, 0, 1), ring[i], ring[(i + 1) % n]), ((0, 0, -1), ring[(i + 1) % n], ring[i]))])
import random
r = random.Random(1)                                        # 30,000 random crossing triangles
stl(sys.argv[1] + "/random.stl", [tuple(tuple(r.random() for _ in range(3)) for _ in range(3))
                                  for _ in range(30000)])
with open(sys.argv[1] + "/bigface.obj", "w") as f:          # one polygon of 200,000 corners
    f.writelines("v %f %f 0\n" % (math.cos(i * 3e-5), math.sin(i * 3e-5)) for i in range(200000))
    f.write("f " + " ".join(str(i + 1) for i in range(200000)) + "\n")
import json
spread = lambda n: [[r.uniform(-10, 10) for _ in range(3)] for _ in range(n)]
for name, kind, param in (("conv", "convolution", "centers"), ("sweep", "sweep", "points")):
    json.dump({"root": {"type": kind, "params": {param: spread(100000)}}},
              open(sys.argv[1] + "/%s100k.json" % name, "w"))
d = 64                                                      # the largest lattice, gently bent
json.dump({"format": "frepcad-lattice", "version": 1, "rest_min": [-1.2] * 3,
           "rest_max": [1.2] * 3, "divisions": [d] * 3,
           "points": [[-1.2 + 2.4 * i / d, -1.2 + 2.4 * j / d + 0.01 * math.sin(i), -1.2 + 2.4 * k / d]
                      for i in range(d + 1) for j in range(d + 1) for k in range(d + 1)]},
          open(sys.argv[1] + "/lattice64.json", "w"))
stl(sys.argv[1] + "/cube.stl", cube)
inner = [tuple((1 + x, 1 + y, 1 + z) for x, y, z in reversed(t)) for t in cube]  # turned in
stl(sys.argv[1] + "/hollow.stl", [tuple((3 * x, 3 * y, 3 * z) for x, y, z in t) for t in cube] + inner)
import zipfile                                              # components: 10 levels of 10
objects = ['<object id="1" type="model"><mesh><vertices><vertex x="0" y="0" z="0"/>'
           '<vertex x="1" y="0" z="0"/><vertex x="0" y="1" z="0"/></vertices><triangles>'
           '<triangle v1="0" v2="1" v3="2"/></triangles></mesh></object>']
for level in range(2, 12):
    objects.append('<object id="%d" type="model"><components>%s</components></object>' % (
        level, '<component objectid="%d"/>' % (level - 1) * 10))
def package(name, resources, item):
  with zipfile.ZipFile(sys.argv[1] + "/" + name, "w") as z:
    z.writestr("[Content_Types].xml", '<?xml version="1.0" encoding="UTF-8"?><Types xmlns='
               '"http://schemas.openxmlformats.org/package/2006/content-types"><Default '
               'Extension="rels" ContentType="application/vnd.openxmlformats-package.'
               'relationships+xml"/><Default Extension="model" ContentType="application/'
               'vnd.ms-package.3dmanufacturing-3dmodel+xml"/></Types>')
    z.writestr("_rels/.rels", '<?xml version="1.0" encoding="UTF-8"?><Relationships xmlns='
               '"http://schemas.openxmlformats.org/package/2006/relationships"><Relationship '
               'Target="/3D/3dmodel.model" Id="rel0" Type="http://schemas.microsoft.com/3dmanu'
               'facturing/2013/01/3dmodel"/></Relationships>')
    z.writestr("3D/3dmodel.model", '<?xml version="1.0" encoding="UTF-8"?><model unit="millimeter"'
               ' xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02"><resources>%s'
               '</resources><build><item objectid="%d"/></build></model>' % (resources, item))
package("fan.3mf", "".join(objects), 11)
tetra = ('<object id="1" type="model"><mesh><vertices><vertex x="0" y="0" z="0"/><vertex x="%s" '
         'y="0" z="0"/><vertex x="0" y="1" z="0"/><vertex x="0" y="0" z="1"/></vertices><triangles>'
         '<triangle v1="0" v2="2" v3="1"/><triangle v1="0" v2="1" v3="3"/><triangle v1="0" v2="3" '
         'v3="2"/><triangle v1="1" v2="2" v3="%s"/></triangles></mesh></object>')
package("tetra.3mf", tetra % ("1.0E0", "3"), 1)            # numbers read strictly
package("word.3mf", tetra % ("one", "3"), 1)
package("fraction.3mf", tetra % ("1", "3.9"), 1)
PY
within10() {  # within10 CODE PATTERN -- command...: expect, and in under 10 s
  local start=$(date +%s.%N)
  expect "$@"
  local took=$(echo "$(date +%s.%N) - $start" | bc)
  awk -v t="$took" 'BEGIN { exit !(t < 10) }' || { echo "FAIL: took ${took} s: ${*:4}"; failures=$((failures + 1)); }
}
within10 0 "wrote .*cubes-repaired.stl" -- "$frepcad" repair "$work/cubes.stl" -o "$work/cubes-repaired.stl"
within10 0 "^  triangles            12$" -- "$frepcad" check "$work/cubes-repaired.stl"
within10 0 "Hausdorff distance" -- "$frepcad" compare "$work/point.stl" "$work/cubes.stl"
within10 2 "too crowded to test for self-intersections" -- "$frepcad" check "$work/bicone.stl"
within10 2 "a face of 200000 corners; at most 10000 are read" -- "$frepcad" check "$work/bigface.obj"
within10 1 "thinnest wall        not measured \(the mesh is not printable" -- "$frepcad" check "$work/random.stl" --print
within10 2 "fan.3mf: the build holds 10000000000 triangles once its components are expanded" -- "$frepcad" check "$work/fan.3mf"
expect 0 "verdict: printable" -- "$frepcad" check "$work/tetra.3mf"
expect 2 "word.3mf: vertex 1 of object 1 has x=\"one\"; a 3MF coordinate is a number" -- "$frepcad" repair "$work/word.3mf" -o "$work/x.stl"
expect 2 "fraction.3mf: triangle 3 of object 1 has v3=\"3.9\"; a 3MF vertex index is a whole number" -- "$frepcad" check "$work/fraction.3mf"
within10 2 "parameter 'centers' gives 100000 centres; at most 10000 are allowed" -- "$frepcad" export "$work/conv100k.json" -o "$work/x.stl"
within10 2 "parameter 'points' has 100000 points; at most 10001 are allowed" -- "$frepcad" export "$work/sweep100k.json" -o "$work/x.stl"
within10 2 "mesher: at cell size .* the mesh would have about [0-9]+ million triangles" -- "$frepcad" export "$src/examples/sphere.json" -o "$work/x.stl" --cells 65000
within10 0 "wrote .*cube-bent.stl" -- "$frepcad" deform "$work/cube.stl" --lattice "$work/lattice64.json" -o "$work/cube-bent.stl"
within10 2 "deform: 720000 vertices inside the lattice, each summing its 274625 control points" -- "$frepcad" deform "$work/cubes.stl" --lattice "$work/lattice64.json" -o "$work/x.stl"
[ ! -e "$work/x.stl" ] || { echo "FAIL: a refused command wrote a file"; failures=$((failures + 1)); }

# copies of an unbounded solid: every copy everywhere, clipped by the export box
printf '{"root": {"type": "instancer", "params": {"positions": [[0, 0, 0], [0.5, 0, 0]], "rotations": [[0, 0, 0], [0, 0, 45]]}, "inputs": [{"type": "gyroid"}]}}' >"$work/copies.json"
within10 0 "wrote .*copies.stl" -- "$frepcad" export "$work/copies.json" -o "$work/copies.stl" --bbox -2 -2 -2 2 2 2
expect 2 "the solid is unbounded towards -x, \+x, -y, \+y, -z, \+z; give a bounding box" -- "$frepcad" export "$work/copies.json" -o "$work/x.stl"

# a value of 100,000 characters is quoted shortened, its length said
python3 -c "import json; json.dump({'root': {'type': 'sphere'}, 'k' * 100000: 1}, open('$work/longkey.json', 'w'))"
expect 2 "unknown key \"kkkkkkkkkk+\.\.\. \(100003 characters\) \.\.\.k\"; a model file has" -- "$frepcad" export "$work/longkey.json" -o "$work/x.stl"
[ "$("$frepcad" export "$work/longkey.json" -o "$work/x.stl" 2>&1 | wc -c)" -lt 400 ] || { echo "FAIL: a long key was echoed whole"; failures=$((failures + 1)); }

# the printability report
expect 0 "cavities             1 enclosed, volume 1 \(resin and powder printers cannot empty them" -- "$frepcad" check "$work/hollow.stl" --print
expect 0 '"cavity_volume": (0\.99999|1\.0)' -- "$frepcad" check "$work/hollow.stl" --print --json
expect 0 "cavities             none" -- "$frepcad" check "$work/cube.stl" --print
# an infill's sealed chambers: each listed with where it drains; holes there drain them all
printf '{"root": {"type": "infill", "params": {"wall": 1, "cell": 6, "thickness": 0.8}, "inputs": [{"type": "box", "params": {"corner": [0, 0, 0], "size": [30, 20, 12]}}]}}' >"$work/infill.json"
"$frepcad" export "$work/infill.json" -o "$work/infill.stl" --cells 150 >/dev/null 2>&1
expect 0 "cavity 1           volume [0-9.]+, drain at \[[0-9.]+, [0-9.]+, 1\]" -- "$frepcad" check "$work/infill.stl" --print
python3 -c "
import json, subprocess, sys
report = json.loads(subprocess.run(sys.argv[1:4] + ['--print', '--json'], capture_output=True).stdout)
model = json.load(open(sys.argv[4]))
model['root']['params']['drain_holes'] = [c['drain_at'] for c in report['print']['cavity_list']]
json.dump(model, open(sys.argv[4].replace('.json', '_drained.json'), 'w'))
" "$frepcad" check "$work/infill.stl" "$work/infill.json"
expect 0 "verdict: printable" -- "$frepcad" export "$work/infill_drained.json" -o "$work/drained.stl" --cells 150
expect 0 "cavities             none" -- "$frepcad" check "$work/drained.stl" --print
expect 0 "thinnest wall        1\.9" -- "$frepcad" check "$work/s.stl" --print --material pla
expect 0 "mass                 [0-9.]+ g" -- "$frepcad" check "$work/s.stl" --print --material pla
expect 1 "triangles where the wall is thinner than 5" -- "$frepcad" check "$work/s.stl" --print --min-wall 5
expect 0 '"overhang_area": [0-9.e-]+' -- "$frepcad" check "$work/s.stl" --print --json --up -y
expect 2 "unknown material 'cheese'" -- "$frepcad" check "$work/s.stl" --print --material cheese
expect 2 "apply with --print" -- "$frepcad" check "$work/s.stl" --min-wall 1

# hsplines: made, refined, edited, unrefined and exported (STEP solid, checked STL, .hs)
expect 0 "wrote .*t.hs \(1 levels, 80 CVs\)" -- "$frepcad" hspline new torus -o "$work/t.hs"
expect 0 "level 1: grid 20 x 16, 63 CVs, 3 movable" -- sh -c "\"$frepcad\" hspline refine \"$work/t.hs\" -o \"$work/t1.hs\" --level 0 --cv 2 2 --cv 3 2 && \"$frepcad\" hspline info \"$work/t1.hs\""
expect 0 "wrote .*t2.hs" -- "$frepcad" hspline move "$work/t1.hs" -o "$work/t2.hs" --cv 1 7 6 --by 0 0 2
expect 2 "CV \(level 1, i 4, j 4\) is fixed" -- "$frepcad" hspline move "$work/t1.hs" -o "$work/x.hs" --cv 1 4 4 --by 0 0 2
# another verb's option is refused, not ignored; numbers in messages as given
expect 2 "hspline unrefine does not take --level; its options: -o --output" -- "$frepcad" hspline unrefine "$work/t1.hs" -o "$work/x.hs" --level 1
expect 2 "a tolerance of 1e-09 needs [0-9]+ triangles" -- "$frepcad" hspline export "$work/t.hs" -o "$work/x.stl" --tolerance 1e-9
expect 2 "--level must be a whole number, got 0.5$" -- "$frepcad" hspline refine "$work/t.hs" -o "$work/x.hs" --level 0.5 --all
[ ! -e "$work/x.hs" ] || { echo "FAIL: a refused move wrote a file"; failures=$((failures + 1)); }
expect 0 "wrote .*t.step: a solid" -- "$frepcad" hspline export "$work/t2.hs" -o "$work/t.step"
expect 0 "verdict: printable" -- "$frepcad" hspline export "$work/t2.hs" -o "$work/t.stl" --tolerance 0.02
expect 0 "verdict: printable" -- "$frepcad" check "$work/t.stl"
expect 0 "1 with an offset" -- "$frepcad" hspline info "$work/t2.hs"
expect 0 "unrefine removed 63 CVs" -- sh -c "\"$frepcad\" hspline zero \"$work/t2.hs\" -o \"$work/t3.hs\" --level 1 --quiet && \"$frepcad\" hspline unrefine \"$work/t3.hs\" -o \"$work/t4.hs\""
cmp -s "$work/t.hs" "$work/t4.hs" || { echo "FAIL: zero offsets + unrefine did not give back the torus"; failures=$((failures + 1)); }
expect 1 "an open hspline is a sheet" -- sh -c "\"$frepcad\" hspline new plane -o \"$work/p.hs\" --quiet && \"$frepcad\" hspline export \"$work/p.hs\" -o \"$work/p.stl\""
[ ! -e "$work/p.stl" ] || { echo "FAIL: a sheet was written as an STL without --force"; failures=$((failures + 1)); }
# a strut lattice in a shell along an hspline: the model, its beams, what is refused
expect 0 "follows it within" -- sh -c "\"$frepcad\" hspline new plane -o \"$work/pl.hs\" --size 30 20 --quiet && \"$frepcad\" hspline move \"$work/pl.hs\" -o \"$work/pl2.hs\" --cv 0 3 3 --by 0 0 4 --quiet && \"$frepcad\" hspline lattice \"$work/pl2.hs\" -o \"$work/shell.json\" --thickness 3 --cell 3"
expect 0 "lib3mf reads [0-9]+ beams back" -- "$frepcad" export "$work/shell.json" -o "$work/shell.3mf" --beams --resolution 0.5
# --straight: the ffd keeps the struts straight, one beam a strut (fewer than the chains above)
expect 0 "follows it within" -- "$frepcad" hspline lattice "$work/pl2.hs" -o "$work/straight.json" --thickness 3 --cell 3 --straight
beams() { "$frepcad" export "$1" -o "$work/beams.3mf" --beams --resolution 0.5 | sed -n 's/.*wrote.*: \([0-9]*\) beams on.*/\1/p'; }
curved_beams=$(beams "$work/shell.json"); straight_beams=$(beams "$work/straight.json")
if grep -q '"struts": "straight"' "$work/straight.json" && [ -n "$straight_beams" ] && [ "$straight_beams" -gt 0 ] && [ "$straight_beams" -le "$curved_beams" ]; then
  passes=$((passes + 1))
else
  echo "FAIL: hspline lattice --straight: straight $straight_beams beams, curved $curved_beams"; failures=$((failures + 1))
fi
expect 2 "hspline lattice needs --thickness T" -- "$frepcad" hspline lattice "$work/pl2.hs" -o "$work/x.json"
expect 2 "30 divisions along the surface; allowed 1 to 24" -- "$frepcad" hspline lattice "$work/pl2.hs" -o "$work/x.json" --thickness 3 --divisions 30 30
[ ! -e "$work/x.json" ] || { echo "FAIL: a refused hspline lattice left x.json"; failures=$((failures + 1)); }
# round a closed surface whole cells make a turn: the cell along it divides its length
out=$("$frepcad" hspline new cylinder -o "$work/cyl.hs" --quiet && "$frepcad" hspline lattice "$work/cyl.hs" -o "$work/cyl.json" --thickness 3)
if python3 -c "import re,sys; m=re.search(r'cells of ([0-9.]+) x .* \(([0-9.]+) x', sys.argv[1]); c,l=float(m.group(1)),float(m.group(2)); sys.exit(not (abs(c-1.5)<0.1 and abs(l/c-round(l/c))<1e-6))" "$out"; then
  passes=$((passes + 1))
else
  echo "FAIL: a closed hspline's cells do not make whole turns: $out"; failures=$((failures + 1))
fi
printf 'hspline 2\n' > "$work/bad.hs"
expect 2 "bad.hs, line 1: version 2 is not known" -- "$frepcad" hspline info "$work/bad.hs"
expect 2 "unknown hspline verb 'grow'" -- "$frepcad" hspline grow "$work/t.hs"
expect 2 "hspline refine needs --level L" -- "$frepcad" hspline refine "$work/t.hs" -o "$work/x.hs" --cv 1 1

# The OpenVDB and OpenCASCADE module is loaded only when asked for: frepcad alone (a copy
# without libfrepcad_heavy.so beside it) still meshes, checks and writes a plain model, and a
# command that needs the module says where it looked.
mkdir -p "$work/alone" && cp "$frepcad" "$work/alone/frepcad"
expect 0 "verdict: printable" -- "$work/alone/frepcad" export "$src/examples/csg.json" -o "$work/alone.stl" --resolution 0.1
expect 2 "cannot load frepcad's OpenVDB and OpenCASCADE module \\(libfrepcad_heavy.so is neither in .*alone" -- "$work/alone/frepcad" hspline info "$work/t.hs"
expect 0 "wrote .*l.vdb" -- "$frepcad" export "$src/examples/csg.json" -o "$work/l.vdb" --resolution 0.1

echo "$passes passed, $failures failed"
[ "$failures" -eq 0 ]
