#!/bin/sh
# Do two builds compute the same thing, bit for bit? Runs a set of scenes with
# each (2D and 3D, walls that turn and move, a periodic axis, diagnostics with
# contact events, the batched and the pruned pair loops on one and two
# threads, every contact model family) and compares every dataset and
# attribute of their outputs (tests/scenes/compare_runs.py). For refactors
# that must not change results.
#   tools/bench/same_results.sh OLD_GRANULE NEW_GRANULE [WORK_DIR]
# Names every scene that differs and then exits 1. About 5 CPU minutes.
set -eu
old=$(realpath "$1")
new=$(realpath "$2")
work=$(realpath -m "${3:-same_results_work}")
here=$(cd "$(dirname "$0")/../.." && pwd)
mkdir -p "$work"
compare() { /usr/bin/python3 "$here/tests/scenes/compare_runs.py" "$1" "$2"; }
# run NAME ARGS...: the scene with both builds, outputs compared.
run() {
  name=$1
  shift
  for build in old new; do
    eval "bin=\$$build"
    "$bin" run "$@" -o "$work/$name.$build.h5" -q > "$work/$name.$build.log"
  done
  if compare "$work/$name.old.h5" "$work/$name.new.h5" > "$work/$name.compare" 2>&1; then
    echo "same: $name"
  else
    echo "DIFFERENT: $name ($(tail -1 "$work/$name.compare"))"
    differ=$((differ + 1))
  fi
}
differ=0
mf="$here/scenarios/mechanofusion.lua"
run mechanofusion_2d "$mf" -D settle=0.004 -D duration=0.008 -D every=20
run mechanofusion_2d_t2 "$mf" -D settle=0.004 -D duration=0.004 -D every=20 --threads 2
run mechanofusion_3d "$mf" -D dimension=3 -D settle=0.001 -D duration=0.001 -D every=20 --threads 2
run binary_walton_braun "$here/scenarios/binary_impact.lua" -D model=walton_braun
run binary_hertz "$here/scenarios/binary_impact.lua" -D model=hertz_mindlin -D young=1e9 -D poisson=0.3
run adhesive_jkr "$here/scenarios/adhesive_restitution.lua" -D count=3
# The shaken box: a state settled by the old build, then steps from it with
# each (the batched, pruned pair loop; two threads share the candidates).
box="$here/tools/bench/box3d_compare.lua"
if [ ! -f "$work/box_state.h5" ]; then
  "$old" run "$box" -D per_side=28 -D layers=20 -D settle=0.004 -D save="$work/box_state.h5" -q > /dev/null
fi
mkdir -p "$work/old" "$work/new"
for threads in 1 2; do
  for build in old new; do
    eval "bin=\$$build"
    # The same file name for both: the scene records it among its parameters.
    (cd "$work/$build" && "$bin" run "$box" -D per_side=28 -D layers=20 -D state=../box_state.h5 \
      -D steps=400 -D out=box_t$threads.h5 --threads $threads -q > /dev/null)
  done
  if compare "$work/old/box_t$threads.h5" "$work/new/box_t$threads.h5" > "$work/box.compare" 2>&1; then
    echo "same: box_3d threads=$threads"
  else
    echo "DIFFERENT: box_3d threads=$threads ($(tail -1 "$work/box.compare"))"
    differ=$((differ + 1))
  fi
done
if [ $differ -gt 0 ]; then
  echo "$differ scenes differ"
  exit 1
fi
echo "all scenes the same"
