#!/bin/sh
# Runs every Mechanofusion study of docs/mechanofusion.md in its short version
# (a few chamber revolutions per case) one after the other, then draws the
# figures into docs/figures/. Usage, from the repository root after a build:
#   sh tools/mechanofusion_studies.sh [work-dir] [study ...]
# Each study's cases run in one process, one after another (one core); the
# whole set takes about half an hour of CPU. For the dissertation's run
# lengths drop -D short=true (hours).
set -e
root=$(cd "$(dirname "$0")/.." && pwd)
work=${1:-mechanofusion_studies}
shift 2>/dev/null || true
studies=${*:-"rpm scraper gap stiffness double loading slab"}
mkdir -p "$work"
granule=${GRANULE:-$root/build/granule}
for study in $studies; do
  extra=""
  case $study in
    scraper) extra="-D settle=0.03 -D measure=0.12" ;;
    slab) extra="-D settle_revolutions=1 -D measure_revolutions=1" ;;
    loading) extra="-D values=500,1000,1500" ;;
  esac
  echo "== $study" >&2
  # shellcheck disable=SC2086
  OMP_WAIT_POLICY=PASSIVE nice "$granule" run "$root/scenarios/mechanofusion_study.lua" -D study=$study \
    -D short=true $extra -D out="$work/mechanofusion_$study.h5" --quiet --threads 1 | tee "$work/$study.log"
  /usr/bin/python3 "$root/tools/plot_mechanofusion.py" study "$work/mechanofusion_$study.h5" -o "$work/figures" \
    | tee -a "$work/$study.log"
done
