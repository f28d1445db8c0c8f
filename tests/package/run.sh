#!/usr/bin/env bash
# The Debian package on its own: installed with apt into a clean copy of a bare root of its
# distribution (no source tree, no build folder, only what the package declares), then
# FreeCAD headless loads the workbench from the system Mod folder, builds and exports the csg
# example with it, and the installed frepcad exports the saved document and checks the mesh
# printable. Runs as root.
# Usage: tests/package/run.sh CACHE SUITE PACKAGE.deb    (make test-package, make test-trixie)
#   CACHE holds SUITE-bare.tar (scripts/debian-root.sh) and, when there, root/ (the build
#   root, whose downloaded .debs are reused instead of fetched again).
set -euo pipefail
if [ "$(id -u)" -ne 0 ]; then exec sudo -E bash "$0" "$@"; fi
cache="$(realpath -m "$1")"; suite="$2"; deb="$(realpath "$3")"
here="$(cd "$(dirname "$0")" && pwd)"
. "$here/../../scripts/debian-root.sh"
root="$cache/package-root"
trap 'root_unmount "$root"' EXIT
root_bare "$cache" "$suite"
root_unpack "$cache/$suite-bare.tar" "$root"
# Packages already downloaded are not fetched again: the build root's (test-trixie), or this
# machine's own when the root is of its release.
archives=""
[ -d "$cache/root/var/cache/apt/archives" ] && archives="$cache/root/var/cache/apt/archives"
if [ -z "$archives" ] && [ "$(. /etc/os-release && echo "$VERSION_CODENAME")" = "$suite" ]; then
  archives=/var/cache/apt/archives
fi
if [ -n "$archives" ]; then
  cp -l "$archives"/*.deb "$root/var/cache/apt/archives/" 2>/dev/null \
    || cp "$archives"/*.deb "$root/var/cache/apt/archives/" 2>/dev/null || true
fi
mkdir -p "$root/tmp/frepcad-test"
cp "$deb" "$root/tmp/"
cp "$here/check_installed.py" "$here/installed_test.sh" "$root/tmp/frepcad-test/"
echo "package test: apt-get install ./$(basename "$deb") into a clean $suite root"
root_enter "$root" env DEBIAN_FRONTEND=noninteractive bash -c \
  "apt-get update -qq && apt-get install -y -qq --no-install-recommends /tmp/$(basename "$deb") \
   >/tmp/apt.log 2>&1 || { tail -30 /tmp/apt.log; exit 1; }"
root_enter "$root" bash /tmp/frepcad-test/installed_test.sh
