#!/usr/bin/env bash
# make test-trixie: the whole `make test` on Debian trixie with FreeCAD 1.0, in a debootstrap
# root on this (bookworm) machine. Runs as root (sudo otherwise).
#
#   1. a bare trixie root (debootstrap, once; CACHE/trixie-bare.tar)
#   2. the build root: the bare one with the project's Debian packages, installed by the same
#      scripts/install-deps.sh (CACHE/root, kept; the script installs what is missing)
#   3. a clean copy of the working tree (tracked and untracked files git does not ignore, no
#      build folder) in /src inside it, then `make test` and `make package` there
#   4. the package installed into a clean copy of the bare root (tests/package/run.sh)
#
# Every line from inside the root is prefixed "[trixie]", so a failure says where it came
# from. CACHE is TRIXIE_CACHE or BUILD_DIR/trixie; ccache's files stay there between runs.
# Usage: tests/trixie/run.sh [BUILD_DIR]     (TRIXIE_STEPS="test package" by default)
set -euo pipefail
if [ "$(id -u)" -ne 0 ]; then exec sudo -E bash "$0" "$@"; fi
src="$(cd "$(dirname "$0")/../.." && pwd)"
build="$(realpath -m "${1:-$src/build}")"
cache="$(realpath -m "${TRIXIE_CACHE:-$build/trixie}")"
steps="${TRIXIE_STEPS:-test package}"
. "$src/scripts/debian-root.sh"

root="$cache/root"
trap 'root_unmount "$root"' EXIT
started=$SECONDS
prefix() { sed -u "s/^/[trixie] /"; }

mkdir -p "$cache"
root_bare "$cache" trixie
if [ ! -f "$root/.frepcad-root" ]; then
  echo "test-trixie: a new build root in $root"
  root_unpack "$cache/trixie-bare.tar" "$root"
  touch "$root/.frepcad-root"
fi

# The working tree as a clean clone would have it, with uncommitted changes.
echo "test-trixie: copying the working tree into $root/src"
root_remove "$root/src"
mkdir -p "$root/src"
(cd "$src" && git ls-files -z --cached --others --exclude-standard \
   | xargs -0 -r sh -c 'for f; do [ -e "$f" ] && printf "%s\0" "$f"; done' sh \
   | tar --null -T - -cf -) | tar -C "$root/src" -xf -

inside() {
  root_enter "$root" env CCACHE_DIR=/var/cache/frepcad-ccache CCACHE_MAXSIZE=3G \
    DEBIAN_FRONTEND=noninteractive bash -c "cd /src && $1"
}

rc=0
echo "test-trixie: installing the project's packages (scripts/install-deps.sh)"
t=$SECONDS
inside "bash scripts/install-deps.sh" 2>&1 | prefix || rc=$?
echo "test-trixie: packages ready in $((SECONDS - t)) s"
if [ "$rc" -ne 0 ]; then echo "test-trixie: FAILED on trixie: install-deps.sh"; exit "$rc"; fi

summary=""
if [[ " $steps " == *" test "* ]]; then
  t=$SECONDS
  inside "make test" 2>&1 | tee "$cache/make-test.log" | prefix || rc=$?
  summary="$(grep -E "tests passed, [0-9]+ tests? failed" "$cache/make-test.log" | tail -1 || true)"
  echo "test-trixie: make test on trixie took $((SECONDS - t)) s"
  if [ "$rc" -ne 0 ]; then echo "test-trixie: FAILED on trixie (FreeCAD 1.0): make test"; fi
fi

if [ "$rc" -eq 0 ] && [[ " $steps " == *" package "* ]]; then
  t=$SECONDS
  rm -f "$cache"/frepcad_*.deb
  inside "make package" 2>&1 | prefix || rc=$?
  if [ "$rc" -eq 0 ]; then
    cp "$root"/src/build/frepcad_*.deb "$cache/"
    bash "$src/tests/package/run.sh" "$cache" trixie "$cache"/frepcad_*.deb 2>&1 | prefix || rc=$?
  fi
  echo "test-trixie: package built and tested in $((SECONDS - t)) s"
  if [ "$rc" -ne 0 ]; then echo "test-trixie: FAILED on trixie (FreeCAD 1.0): the package"; fi
fi

echo "test-trixie: $((SECONDS - started)) s in all; $([ "$rc" -eq 0 ] && echo passed || echo FAILED) on trixie (FreeCAD 1.0)"
# ctest's own summary from trixie, last (CI reads the closing line)
[ -n "$summary" ] && echo "$summary"
exit "$rc"
