#!/bin/sh
# What spreading a scene script over MPI ranks costs (docs/parallel.md): the
# lattice box of tools/bench/spread_scene.lua (PER_SIDE^3 spheres, default 30:
# 27,000; STEPS steps, default 400) run by one process in canonical order and
# under mpirun on each of RANKS (default "1 2"), with no hook, with a snapshot
# every SNAP steps (default 100) and with a stats callback every CALL steps
# (default 10). Each case's steps/s is STEPS over its wall time less that of
# the same command with 0 steps (start-up, the Lua lattice, mpirun). Checks
# that every case ends with the same kinetic energy bits. Writes a Markdown
# table to stdout.
#   sh tools/bench/spread_scene.sh > spread.md
set -e
root=$(cd "$(dirname "$0")/../.." && pwd)
granule=${GRANULE:-$root/build/granule}
scene=$root/tools/bench/spread_scene.lua
ranks=${RANKS:-"1 2"}
side=${PER_SIDE:-30}
steps=${STEPS:-400}
snap=${SNAP:-100}
call=${CALL:-10}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
seconds() {  # the wall time of a command, its output kept in last.txt
  start=$(date +%s.%N)
  "$@" > last.txt
  end=$(date +%s.%N)
  awk -v a="$start" -v b="$end" 'BEGIN { printf "%.2f", b - a }'
}
run_case() {  # runner steps extra...: the wall time
  runner=$1 n_steps=$2
  shift 2
  if [ "$runner" = plain ]; then
    seconds env OMP_NUM_THREADS=1 "$granule" run "$scene" -D per_side=$side -D steps=$n_steps "$@" -o out.h5 --quiet
  else
    seconds env OMP_NUM_THREADS=1 $mpi -np "$runner" "$granule" run "$scene" -D per_side=$side -D steps=$n_steps "$@" -o out.h5 --quiet
  fi
}
echo "| hooks | runner | seconds | of which setup (0 steps) | steps/s | kinetic energy (hex) |"
echo "|---|---|---|---|---|---|"
mpi="mpirun --allow-run-as-root --oversubscribe --mca btl self,vader"
reference=""
for hooks in none snapshot callback; do
  case $hooks in
    none) extra="-D snapshot_every=0" ;;
    snapshot) extra="-D snapshot_every=$snap" ;;
    callback) extra="-D callback_every=$call" ;;
  esac
  for runner in plain $ranks; do
    setup=$(run_case "$runner" 0 $extra)
    t=$(run_case "$runner" "$steps" $extra)
    energy=$(sed -n 's/.*kinetic_energy=\([^ ]*\).*/\1/p' last.txt)
    [ -z "$reference" ] && reference=$energy
    [ "$energy" = "$reference" ] || { echo "kinetic energy differs: $energy vs $reference" >&2; exit 1; }
    rate=$(awk -v t="$t" -v s="$setup" -v n="$steps" 'BEGIN { d = t - s; if (d > 0) printf "%.0f", n / d; else print "-" }')
    label=$runner
    [ "$runner" != plain ] && label="mpirun -np $runner"
    echo "| $hooks | $label | $t | $setup | $rate | $energy |"
  done
done
