#!/bin/sh
# Checkpoint/restart end to end: an uninterrupted run and one continued from its
# last checkpoint (and one stopped by Ctrl-C and continued) end in bit-identical
# final states. Usage: restart_test.sh GRANULE SOURCE_DIR
set -eu
granule=$1
scene=$2/tests/scenes/restart.lua
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
compare() {  # final snapshots of two files must be bit-identical
  /usr/bin/python3 - "$1" "$2" <<'PY'
import sys, h5py, numpy as np
def last(path):
    f = h5py.File(path, "r")
    g = f["snapshots/%06d" % (f["snapshots"].attrs["count"] - 1)]
    return g.attrs["step"], {k: g[k][:] for k in ("id", "position", "velocity", "spin")}
sa, a = last(sys.argv[1]); sb, b = last(sys.argv[2])
assert sa == sb, f"final steps differ: {sa} vs {sb}"
for k in a:
    assert a[k].shape == b[k].shape and a[k].tobytes() == b[k].tobytes(), f"{k} differs"
print(f"identical at step {sa}")
PY
}
"$granule" run "$scene" -o whole.h5 --quiet > whole.txt
test -f restart_test.chk.h5
"$granule" run "$scene" --restart restart_test.chk.h5 -o resumed.h5 --quiet > resumed.txt
cmp whole.txt resumed.txt
compare whole.h5 resumed.h5
# --checkpoint names the file whatever the scene's sim:checkpoint says (as granule
# sweep gives each case its own); the restart from it is the same run.
rm -f restart_test.chk.h5
"$granule" run "$scene" --checkpoint own.chk.h5 -o own.h5 --quiet > own.txt
test -f own.chk.h5 || { echo "--checkpoint own.chk.h5 wrote no checkpoint there"; exit 1; }
test ! -f restart_test.chk.h5 || { echo "the scene's own checkpoint file was written despite --checkpoint"; exit 1; }
"$granule" run "$scene" --restart own.chk.h5 -o own_resumed.h5 --quiet > own_resumed.txt
cmp whole.txt own_resumed.txt
compare whole.h5 own_resumed.h5
# --checkpoint-every: wall-clock checkpoints for a scene that asks for none.
# (long enough, 120,000 steps, to outlast 0.2 s of wall time on a fast idle machine)
"$granule" run "$scene" -D checkpoint_every=100000000 -D stage2_steps=120000 --checkpoint timed.chk.h5 --checkpoint-every 0.2 \
  -o timed.h5 --quiet > /dev/null
test -f timed.chk.h5 || { echo "--checkpoint-every 0.2 wrote no checkpoint"; exit 1; }
if "$granule" run "$scene" --checkpoint-every 0 -o x.h5 --quiet 2> bad.txt; then
  echo "--checkpoint-every 0 was accepted"; exit 1
fi
grep -q "checkpoint-every expects seconds" bad.txt || { cat bad.txt; exit 1; }
# Ctrl-C: a checkpoint at the next chunk boundary, exit status 130, then continue.
rm -f restart_test.chk.h5
"$granule" run "$scene" -D checkpoint_every=1000000 -D stage2_steps=4000000 -o long.h5 --quiet > /dev/null &
pid=$!
# Signal once the run is stepping (its output file is open), not after a fixed
# time, which a loaded machine may spend loading the program.
tries=0
while [ ! -f long.h5 ] && [ $tries -lt 300 ]; do sleep 0.1; tries=$((tries + 1)); done
sleep 1
kill -INT $pid
status=0
wait $pid || status=$?
test "$status" -eq 130 || { echo "expected exit status 130 after Ctrl-C, got $status"; exit 1; }
test -f restart_test.chk.h5 || { echo "no checkpoint after Ctrl-C"; exit 1; }
echo "interrupted cleanly"
