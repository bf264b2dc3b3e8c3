#!/bin/sh
# The angle of repose against rolling friction: scenarios/repose_rolling.lua at
# three values of mu_r and SEEDS fill seeds each, one run at a time under nice,
# then tools/plot_repose.py draws docs/figures/repose_rolling.png from the
# printed angles (mean and standard error over the seeds).
#   tools/repose_study.sh [GRANULE] [SEEDS]
set -eu
granule=${1:-build/granule}
seeds=${2:-3}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
: > "$out/angles.txt"
for mu in 0 0.1 0.3; do
  s=1
  while [ "$s" -le "$seeds" ]; do
    nice "$granule" run scenarios/repose_rolling.lua --quiet -D rolling_friction=$mu -D seed=$s \
      -o "$out/run.h5" | grep '^repose_rolling:' | tee -a "$out/angles.txt"
    s=$((s + 1))
  done
done
/usr/bin/python3 tools/plot_repose.py "$out/angles.txt" docs/figures/repose_rolling.png
