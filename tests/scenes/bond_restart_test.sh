#!/bin/sh
# Parallel bonds through `granule run --restart`: the run continued from the last
# checkpoint prints the same line (bond counts, a position to 17 digits) and
# ends in a bit-identical snapshot. Usage: bond_restart_test.sh GRANULE SOURCE_DIR
set -eu
granule=$1
scene=$2/tests/scenes/bond_restart.lua
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
"$granule" run "$scene" -o whole.h5 --quiet > whole.txt
test -f bond_restart.chk.h5
"$granule" run "$scene" --restart bond_restart.chk.h5 -o resumed.h5 --quiet > resumed.txt
cmp whole.txt resumed.txt
/usr/bin/python3 - whole.h5 resumed.h5 > check.txt <<'PY'
import sys, h5py
def last(path):
    f = h5py.File(path, "r")
    g = f["snapshots/%06d" % (f["snapshots"].attrs["count"] - 1)]
    return g.attrs["step"], {k: g[k][:] for k in ("id", "position", "velocity", "spin")}
sa, a = last(sys.argv[1]); sb, b = last(sys.argv[2])
assert sa == sb, f"final steps differ: {sa} vs {sb}"
for k in a:
    assert a[k].tobytes() == b[k].tobytes(), f"{k} differs"
# The bonds in the last snapshots: the same, and as many broken as the scene printed.
def bonds(path):
    f = h5py.File(path, "r")
    g = f["snapshots/%06d/bonds" % (f["snapshots"].attrs["count"] - 1)]
    return {k: g[k][:] for k in ("a", "b", "broken")}
ba, bb = bonds(sys.argv[1]), bonds(sys.argv[2])
for k in ba:
    assert ba[k].tobytes() == bb[k].tobytes(), f"bonds/{k} differs"
assert (ba["a"] < ba["b"]).all()
print("snapshot bonds: %d, broken=%d" % (len(ba["a"]), ba["broken"].sum()))
PY
cat whole.txt
grep -q "broken=[1-9]" whole.txt || { echo "no bond broke: the test would not see broken flags"; exit 1; }
broken=$(sed -n 's/.* broken=\([0-9]*\) .*/\1/p' whole.txt)
grep -q "snapshot bonds: .*, broken=$broken\$" check.txt || { cat check.txt; echo "the snapshot's bonds differ from sim:bond_counts"; exit 1; }
echo "bonds restart bit-identical"
