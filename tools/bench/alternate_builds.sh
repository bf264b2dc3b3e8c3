#!/bin/sh
# Two builds timed against each other on one scene, in turn (new, old, new,
# old, ...), so that a drift of the shared host's speed falls on both: prints
# each pair's wall-time ratio new/old and their median. Each build runs the
# scene with the Lua library of its own tree when OLD_LUA / NEW_LUA name one.
#   tools/bench/alternate_builds.sh OLD_GRANULE NEW_GRANULE PAIRS -- ARGS...
# e.g. the 2D base case from a settled state (tools/bench/mechanofusion_compare.lua):
#   tools/bench/alternate_builds.sh old/granule build/granule 9 -- run \
#     tools/bench/mechanofusion_compare.lua -D state=mf_state.h5 -D steps=100000 --threads 1 -q
set -eu
[ $# -ge 4 ] && [ "$4" = "--" ] || { echo "usage: $0 OLD NEW PAIRS -- ARGS..." >&2; exit 2; }
old=$1 new=$2 pairs=$3
shift 4
seconds() {  # seconds() LUA_DIR BINARY ARGS...: wall seconds of one run
  lua_dir=$1
  shift
  start=$(date +%s.%N)
  if [ -n "$lua_dir" ]; then GRANULE_LUA_PATH=$lua_dir "$@" > /dev/null 2>&1; else "$@" > /dev/null 2>&1; fi
  end=$(date +%s.%N)
  awk -v a="$start" -v b="$end" 'BEGIN { print b - a }'
}
seconds "${NEW_LUA:-}" "$new" "$@" > /dev/null  # warm-up (page cache, huge pages)
ratios=""
i=1
while [ $i -le "$pairs" ]; do
  t_new=$(seconds "${NEW_LUA:-}" "$new" "$@")
  t_old=$(seconds "${OLD_LUA:-}" "$old" "$@")
  ratio=$(awk -v a="$t_new" -v b="$t_old" 'BEGIN { print a / b }')
  printf "pair %d: new %.3f s, old %.3f s, ratio %.4f\n" $i "$t_new" "$t_old" "$ratio"
  ratios="$ratios $ratio"
  i=$((i + 1))
done
median=$(printf "%s\n" $ratios | sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }')
printf "median ratio new/old over %d pairs: %.4f\n" "$pairs" "$median"
