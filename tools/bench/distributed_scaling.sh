#!/bin/sh
# Strong and weak scaling of the distributed step (docs/parallel.md): the scene of
# tools/bench/distributed_scaling.cpp (SCENE=shear, the default: a periodic shear
# cell in its steady state after WARMUP steps, default 10000; SCENE=burst: the
# bursting lattice box, a transient) over RANKS (default "1 2 4"; on a bigger
# machine e.g. RANKS="1 2 4 8 16 32"), strong at PER_SIDE^3 spheres in all
# (default 30: 27,000), weak at WEAK_SIDE^3 per rank (default 22: 10,648), STEPS
# timed steps each (default 4000), each run REPEAT times (default 3). Writes a
# Markdown table to stdout: the median run of each row, the range of the rates,
# and the efficiency from the medians.
# usage, from the repository root: cmake --build build --target distributed_scaling
#   sh tools/bench/distributed_scaling.sh > scaling.md
set -e
root=$(cd "$(dirname "$0")/../.." && pwd)
bin=${BIN:-$root/build/distributed_scaling}
ranks=${RANKS:-"1 2 4"}
per_side=${PER_SIDE:-30}
weak_side=${WEAK_SIDE:-22}
steps=${STEPS:-4000}
repeat=${REPEAT:-3}
export SCENE=${SCENE:-shear} WARMUP=${WARMUP:-10000}
# The scene's settings that are set travel to every rank.
pass=""
for v in SCENE WARMUP SPACING WALL_SPEED REBALANCE_THRESHOLD PLAIN; do
  eval "[ -n \"\${$v+set}\" ]" && pass="$pass -x $v"
done
echo "scene $SCENE, $WARMUP warm-up steps, $steps timed steps, median of $repeat runs"
echo
echo "| mode | ranks | spheres | per rank | particle-steps/s (range) | efficiency | compute s | ghost forward s | waiting s | rebuilds s (count) | ghosts per owned | migrations | contacts per sphere | one-rank overhead |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for mode in strong weak; do
  side=$per_side
  [ "$mode" = weak ] && side=$weak_side
  base=""
  for n in $ranks; do
    runs=""
    i=0
    while [ "$i" -lt "$repeat" ]; do
      line=$(OMP_NUM_THREADS=1 mpirun --allow-run-as-root --oversubscribe --mca btl self,vader \
        $pass -np "$n" \
        "$bin" "$mode" "$side" "$steps" | grep '^mode')
      runs="$runs$line
"
      i=$((i + 1))
    done
    # The median run by rate (field 14), and the range of the rates.
    sorted=$(printf '%s' "$runs" | sort -g -k14,14)
    line=$(printf '%s\n' "$sorted" | sed -n "$(((repeat + 1) / 2))p")
    low=$(printf '%s\n' "$sorted" | head -n 1 | awk '{print $14}')
    high=$(printf '%s\n' "$sorted" | tail -n 1 | awk '{print $14}')
    # shellcheck disable=SC2086
    set -- $line
    rate=${14}
    [ -z "$base" ] && base=$rate
    # strong: speed-up over the ranks; weak: rate per rank over the one-rank rate
    eff=$(awk -v r="$rate" -v b="$base" -v n="$n" 'BEGIN { printf "%.2f", r / (b * n) }')
    over=""
    [ "$n" = 1 ] && [ "${37}" = overhead ] && over=$(awk -v o="${38}" 'BEGIN { printf "%+.1f %%", 100 * o }')
    echo "| $mode | $n | $6 | $8 | $rate ($low-$high) | $eff | ${16} | ${18} | ${20} | ${28} (${30}) | ${22} | ${24} | ${32} | $over |"
  done
done
