#!/bin/sh
# Strong and weak scaling of the distributed step (docs/parallel.md): the lattice
# box of tools/bench/distributed_scaling.cpp over RANKS (default "1 2 4"; on a
# bigger machine e.g. RANKS="1 2 4 8 16 32"), strong at PER_SIDE^3 spheres in all
# (default 30: 27,000), weak at WEAK_SIDE^3 per rank (default 22: 10,648), STEPS
# steps each (default 400). Writes a Markdown table to stdout.
# usage, from the repository root: cmake --build build --target distributed_scaling
#   sh tools/bench/distributed_scaling.sh > scaling.md
set -e
root=$(cd "$(dirname "$0")/../.." && pwd)
bin=${BIN:-$root/build/distributed_scaling}
ranks=${RANKS:-"1 2 4"}
per_side=${PER_SIDE:-30}
weak_side=${WEAK_SIDE:-22}
steps=${STEPS:-400}
echo "| mode | ranks | spheres | per rank | particle-steps/s | efficiency | compute s | ghost forward s | waiting s | rebuilds s (count) | ghosts per owned | migrations | one-rank overhead |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for mode in strong weak; do
  side=$per_side
  [ "$mode" = weak ] && side=$weak_side
  base=""
  for n in $ranks; do
    line=$(OMP_NUM_THREADS=1 mpirun --allow-run-as-root --oversubscribe --mca btl self,vader -np "$n" \
      "$bin" "$mode" "$side" "$steps" | grep '^mode')
    # shellcheck disable=SC2086
    set -- $line
    rate=${14}
    [ -z "$base" ] && base=$rate
    # strong: speed-up over ranks; weak: rate per rank over the one-rank rate
    eff=$(awk -v r="$rate" -v b="$base" -v n="$n" -v m="$mode" 'BEGIN { printf "%.2f", r / (b * n) }')
    over=""
    [ "$n" = 1 ] && over=$(awk -v o="${34}" 'BEGIN { printf "%+.1f %%", 100 * o }')
    echo "| $mode | $n | $6 | $8 | $rate | $eff | ${16} | ${18} | ${20} | ${28} (${30}) | ${22} | ${24} | $over |"
  done
done
