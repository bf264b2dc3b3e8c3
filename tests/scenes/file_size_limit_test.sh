#!/bin/bash
# A file size limit (ulimit -f) reached during a run: the run ends with a message
# naming the file and the limit, a non-zero exit status that is not a signal's
# (the kernel's SIGXFSZ would kill it unannounced), the output still opens in h5py
# with its snapshots and the reason recorded, and a checkpoint that would pass the
# limit leaves no half-written file. bash: its ulimit -f counts KiB.
# Usage: file_size_limit_test.sh GRANULE SOURCE_DIR
set -u
granule=$1
source=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
. "$(dirname "$0")/failed_run_checks.sh"

# 1. Snapshots until the output reaches a 1500 KiB limit (1500 particles, one every 0.2 ms).
status=0
(ulimit -f 1500; exec "$granule" run "$source/scenarios/mechanofusion_demo.lua" -D duration=0.01 \
  -D snapshot_every=2e-4 -o "$work/out.h5" --quiet) > "$work/snapshots.txt" 2>&1 || status=$?
check_status $status snapshots
grep -q "out.h5" "$work/snapshots.txt" || fail "snapshots: the message does not name the file"
grep -q "file size limit (1500 KiB" "$work/snapshots.txt" ||
  fail "snapshots: the message does not name the file size limit"
check_readable "$work/out.h5" 1
/usr/bin/python3 - "$work/out.h5" <<'PY' || fail "out.h5 does not record the failure"
import sys, h5py
with h5py.File(sys.argv[1], "r") as f:
    failure = f.attrs["failure"]
    failure = failure.decode() if isinstance(failure, bytes) else str(failure)
    assert "file size limit" in failure, failure
print(f"{sys.argv[1]}: the failure recorded")
PY

# 2. A checkpoint larger than the limit (4000 spheres; the output, without snapshots,
# stays small): refused by name, no .tmp left behind.
cat > "$work/many.lua" <<'LUA'
local sim = simulation { dimension = 3 }
sim:material { name = "glass", density = 2500 }
sim:contact { "glass", "glass", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:fill { region = { box = { lo = { 0, 0, 0 }, hi = { 0.04, 0.04, 0.04 } } }, count = 4000,
           radius = 8e-4, material = "glass", seed = 3, overlap = false }
sim:output { snapshot_every = 0 }
sim:run { steps = 200000 }
LUA
status=0
(ulimit -f 1000; exec "$granule" run "$work/many.lua" -o "$work/small.h5" \
  --checkpoint "$work/run.chk.h5" --checkpoint-every 0.05 --quiet) > "$work/checkpoint.txt" 2>&1 ||
  status=$?
check_status $status checkpoint
grep -q "run.chk.h5" "$work/checkpoint.txt" || fail "checkpoint: the message does not name the file"
grep -q "file size limit (1000 KiB" "$work/checkpoint.txt" ||
  fail "checkpoint: the message does not name the file size limit"
[ ! -e "$work/run.chk.h5.tmp" ] || fail "checkpoint: the half-written run.chk.h5.tmp was left behind"
echo "the messages:"; head -1 "$work/snapshots.txt"; head -1 "$work/checkpoint.txt"
echo "file size limit handled cleanly"
