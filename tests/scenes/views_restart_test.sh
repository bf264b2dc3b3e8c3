#!/bin/sh
# A scene whose Lua diagnostic reads sim:arrays(), restarted from its last checkpoint: the
# final state and every row of its /profile series bit-identical to the uninterrupted run's.
# Usage: views_restart_test.sh GRANULE SOURCE_DIR
set -eu
granule=$1
scene=$2/tests/scenes/views_restart.lua
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
"$granule" run "$scene" -o whole.h5 --quiet > whole.txt
test -f views_restart.chk.h5
"$granule" run "$scene" --restart views_restart.chk.h5 -o resumed.h5 --quiet > resumed.txt
cmp whole.txt resumed.txt
/usr/bin/python3 - whole.h5 resumed.h5 views_restart.chk.h5 <<'PY'
import sys, h5py
a, b, c = (h5py.File(p, "r") for p in sys.argv[1:4])
step = int(c["checkpoint/integers/meta"][2])
last = lambda f: f["snapshots/%06d" % (f["snapshots"].attrs["count"] - 1)]
sa, sb = last(a), last(b)
assert sa.attrs["step"] == sb.attrs["step"] > step, (sa.attrs["step"], sb.attrs["step"], step)
for k in ("id", "position", "velocity", "spin"):
    assert sa[k][:].tobytes() == sb[k][:].tobytes(), f"final {k} differs"
for col in a["profile"].attrs["columns"]:
    x, y = a["profile"][col][:], b["profile"][col][:]
    assert x.shape == y.shape and x.tobytes() == y.tobytes(), f"/profile/{col} differs"
t = a["profile"]["time"][:]
print(f"views restart identical: checkpoint at step {step}, {len(t)} profile rows")
PY
