#!/usr/bin/env bash
# Installs what is missing (Debian 12, as root), builds Granule in Release and
#   run  -> runs the default scene (scenarios/mechanofusion_demo.lua)
#   test -> runs the whole test suite through ctest
# Usage: tools/bootstrap.sh run|test
set -euo pipefail
cd "$(dirname "$0")/.."
mode=${1:-}
if [[ "$mode" != run && "$mode" != test ]]; then
  echo "usage: tools/bootstrap.sh run|test" >&2
  exit 2
fi

packages=(cmake g++ make pkg-config liblua5.4-dev libeigen3-dev libhdf5-dev catch2 libfmt-dev
          libreadline-dev zlib1g-dev python3-h5py python3-matplotlib python3-numpy
          openmpi-bin libopenmpi-dev  # MPI: `granule sweep` under mpirun (optional at build time)
          libassimp-dev  # mesh walls: STL and OBJ files
          paraview python3-paraview xvfb xauth)  # the tests that open our output in ParaView, headless
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "installing: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j "$jobs"

if [[ "$mode" == run ]]; then
  ./build/granule run scenarios/mechanofusion_demo.lua
else
  cd build
  ctest --output-on-failure -j "$jobs"
fi
