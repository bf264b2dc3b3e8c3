#!/bin/sh
# Gathered writes against parallel HDF5 for the snapshots of a scene spread
# over MPI ranks (tools/bench/snapshot_write.cpp; docs/parallel.md, "Files").
# Builds the bench twice with mpicxx, against Debian's serial HDF5
# (libhdf5-dev) and its parallel one (libhdf5-openmpi-dev: apt-get install
# libhdf5-openmpi-dev; without it only the gathered writes are timed), then
# times SNAPSHOTS snapshots (default 10) of SPHERES spheres (default "10000
# 100000 1000000") on RANKS ranks (default "1 2") into DIR (default a fresh
# folder under $TMPDIR). Writes a Markdown table to stdout.
#   sh tools/bench/snapshot_write.sh > snapshot_write.md
set -e
root=$(cd "$(dirname "$0")/../.." && pwd)
work=$(mktemp -d "${TMPDIR:-/tmp}/snapshot_write.XXXXXX")
trap 'rm -rf "$work"' EXIT
dir=${DIR:-$work}
lib=/usr/lib/$(dpkg-architecture -qDEB_HOST_MULTIARCH 2>/dev/null || echo x86_64-linux-gnu)/hdf5
mpicxx -O2 -std=c++17 -I/usr/include/hdf5/serial "$root/tools/bench/snapshot_write.cpp" \
  -o "$work/serial" -L"$lib/serial" -lhdf5
parallel=""
if [ -f /usr/include/hdf5/openmpi/hdf5.h ]; then
  mpicxx -O2 -std=c++17 -DSNAPSHOT_PARALLEL_HDF5 -I/usr/include/hdf5/openmpi \
    "$root/tools/bench/snapshot_write.cpp" -o "$work/parallel" -L"$lib/openmpi" -lhdf5
  parallel=yes
else
  echo "(libhdf5-openmpi-dev is not installed: parallel HDF5 not timed)" >&2
fi
snapshots=${SNAPSHOTS:-10}
echo "| spheres | ranks | mode | s per snapshot | MB/s |"
echo "|---|---|---|---|---|"
for n in ${SPHERES:-10000 100000 1000000}; do
  for r in ${RANKS:-1 2}; do
    for mode in every root parallel; do
      bin=$work/serial
      if [ "$mode" = parallel ]; then
        [ -n "$parallel" ] || continue
        bin=$work/parallel
      fi
      line=$(mpirun --allow-run-as-root --oversubscribe --mca btl self,vader -np "$r" \
        "$bin" "$mode" "$n" "$snapshots" "$dir" | grep '^mode')
      # shellcheck disable=SC2086
      set -- $line
      echo "| $n | $r | $mode | ${10} | ${12} |"
      rm -f "$dir"/*.h5
    done
  done
done
