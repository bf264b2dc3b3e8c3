#!/bin/sh
# LAMMPS from Debian 12's own source package (the version /usr/bin/lmp is
# built from), compiled for this CPU (-O3 -march=native, as Granule is), with
# the packages the comparison decks use (GRANULAR) and MPI, for
#   /usr/bin/python3 tools/bench/compare.py ... --lammps-native DIR/build/lmp
# (docs/performance.md, "How each LAMMPS deck was chosen"). The source comes
# from Debian's archive through a private apt list: the system's apt set-up
# is left as it is. About 3 minutes on 2 cores.
#   tools/bench/build_lammps_native.sh [DIR]     (default: bench_work/lammps-native)
set -eu
dir=${1:-bench_work/lammps-native}
mkdir -p "$dir/lists/partial"
cd "$dir"
echo "deb-src [signed-by=/usr/share/keyrings/debian-archive-keyring.gpg] http://deb.debian.org/debian bookworm main" > sources.list
set -- -o Dir::Etc::SourceList="$PWD/sources.list" -o Dir::Etc::SourceParts=/dev/null \
  -o Dir::State::Lists="$PWD/lists"
apt-get "$@" -qq update
[ -d src ] || { apt-get "$@" -qq source --download-only lammps && dpkg-source -x --no-check lammps_*.dsc src; }
cmake -S src/cmake -B build -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS="-O3 -march=native" \
  -DPKG_GRANULAR=on -DBUILD_MPI=on -DBUILD_OMP=off -DWITH_JPEG=off -DWITH_PNG=off \
  -DWITH_FFMPEG=off -DWITH_GZIP=off > cmake.log
cmake --build build -j "$(nproc)" --target lmp > build.log
echo "built $PWD/build/lmp"
