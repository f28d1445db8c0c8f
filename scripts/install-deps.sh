#!/usr/bin/env bash
# Installs the Debian packages FRepCAD needs, only those missing. Idempotent and
# non-interactive; uses sudo when not root. Called by `make demo` and `make test`.
set -euo pipefail

packages=(
  build-essential cmake ninja-build ccache pkg-config
  libcgal-dev libgmp-dev libmpfr-dev libboost-dev libeigen3-dev
  libopenmesh-dev libtbb-dev nlohmann-json3-dev libnanoflann-dev libopenvdb-dev
  lib3mf-dev  # 3MF files (io/mesh_3mf.cpp)
  libminizip-dev  # the streamed 3MF package's zip (io/three_mf_stream.cpp)
  libocct-foundation-dev libocct-modeling-data-dev libocct-modeling-algorithms-dev
  libocct-data-exchange-dev  # OpenCASCADE: hspline surfaces, solids, STEP (hspline/occt/)
  libfontconfig-dev  # (OCCT 7.8's CMake files, on trixie, name it for the link)
  file dpkg-dev  # make package: CPack reads the libraries' dependencies with dpkg-shlibdeps
  admesh      # the repair comparison's reference (bench/repair_comparison.py)
  libgtest-dev libgmock-dev libbenchmark-dev
  freecad freecad-python3 python3-dev pybind11-dev python3-pytest
  python3-distributed  # Dask: brick jobs across processes and machines (frepcore.distributed)
  xvfb xauth libgl1-mesa-dri  # the GUI test: a display server and software OpenGL
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
