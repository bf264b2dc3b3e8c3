#!/bin/sh
# The Mechanofusion studies at full length (docs/mechanofusion.md, "Full-length
# studies"): each study is one `granule sweep` of scenarios/mechanofusion.lua
# over its parameter and the seeds, every case `SETTLE` s of settling and then
# `MEASURE` s with every diagnostic attached, sampled every EVERY steps (40:
# once per contact duration, n of Eq. 4.1; each collision's peak and every
# collision count come from the contact events, which are exact at any
# EVERY). Under mpirun the cases share the
# ranks; every case writes a checkpoint every CHECKPOINT s of wall time, so a
# study stopped at any point (Ctrl-C, a lost machine, the end of a session) is
# continued by running the same command again: finished cases are kept,
# unfinished ones go on from their checkpoints. Then
#   /usr/bin/python3 tools/mechanofusion_ensembles.py tables WORK
#   /usr/bin/python3 tools/mechanofusion_ensembles.py figures
# make the tables under docs/data/ and the figures from them.
#
# usage, from the repository root after a build:
#   sh tools/mechanofusion_long.sh WORK [study ...]
# studies: rpm coating gap stiffness scraper loading double slab (default: all, in
# that order); coating is the 2000 rpm base case measured for COATING_MEASURE (2.6) s,
# long enough to reach full coverage under every reading of 4.7.
# environment: RANKS (2), SEEDS (1,2,3), SETTLE (0.2), MEASURE (1), EVERY (40),
#              CHECKPOINT (600), COATING_MEASURE (2.6), GRANULE (build/granule)
set -e
root=$(cd "$(dirname "$0")/.." && pwd)
work=${1:?usage: sh tools/mechanofusion_long.sh WORK [study ...]}
shift
studies=${*:-"rpm coating gap stiffness scraper loading double slab"}
granule=${GRANULE:-$root/build/granule}
ranks=${RANKS:-2}
seeds=${SEEDS:-1,2,3}
settle=${SETTLE:-0.2}
measure=${MEASURE:-1}
checkpoint=${CHECKPOINT:-600}
every=${EVERY:-40}
launch=""
if [ "$ranks" -gt 1 ]; then
  launch="mpirun --allow-run-as-root --oversubscribe --mca btl self,vader -np $ranks"
fi
mkdir -p "$work"
# Ctrl-C or SIGTERM to this script ends it after the running sweep has stopped its cases.
trap 'exit 130' INT
trap 'exit 143' TERM
for study in $studies; do
  length=$measure
  case $study in
    rpm) axes="-D rpm=500,1000,2000,3000,4000" ;;
    coating) axes="-D rpm=2000"; length=${COATING_MEASURE:-2.6} ;;
    scraper) axes="-D scraper=true,false" ;;
    gap) axes="-D gap=1.0e-3,1.6e-3,2.4e-3,3.2e-3" ;;
    stiffness) axes="-D k_load=2000,5000,20000,50000" ;;
    # 1500 particles at these speeds are the rpm study's cases (mechanofusion_ensembles.py borrows them).
    loading) axes="-D rpm=1000,2000,4000 -D particles=500,1000,2000" ;;
    double) axes="-D size_scale=1,2" ;;
    # The 2D cases are the rpm study's 2000 rpm ones (mechanofusion_ensembles.py borrows them).
    slab) axes="-D dimension=3" ;;
    *) echo "unknown study '$study' (rpm coating gap stiffness scraper loading double slab)" >&2; exit 2 ;;
  esac
  echo "== $study" >&2
  # The seed varies slowest: every value of a study has its first seed before any has a second.
  # shellcheck disable=SC2086
  OMP_WAIT_POLICY=PASSIVE $launch "$granule" sweep "$root/scenarios/mechanofusion.lua" -D seed=$seeds $axes \
    -D settle=$settle -D duration=$length -D every=$every -o "$work/$study" --threads 1 --checkpoint-every $checkpoint -q \
    || status=$?
  # Under mpirun the exit status is mpirun's (1 for a rank stopped by a signal):
  # the summary's "interrupted" cases tell a stop from a failure.
  if [ "${status:-0}" -ne 0 ] && grep -q ',interrupted,' "$work/$study/mechanofusion.sweep.csv" 2>/dev/null; then
    status=143
  fi
  if [ "${status:-0}" -ge 128 ]; then
    # Stopped by a signal: the running cases wrote their checkpoints; go no further.
    echo "$study: stopped (status $status); run the same command again to continue" >&2
    exit "$status"
  elif [ "${status:-0}" -ne 0 ]; then
    echo "$study: some cases failed (their logs say why); rerun the same command to retry them" >&2
  fi
  status=0
done
