#!/bin/sh
# A disk that fills during a run: the run ends with a message naming the file and
# saying the disk is full, a non-zero exit status that is not a signal's, and the
# output file still opens in h5py with every snapshot written before the failure,
# none with NaN. A checkpoint that no longer fits leaves the previous one in place,
# and says so. Needs a small tmpfs (root, as in CI); without one it is skipped.
# Usage: full_disk_test.sh GRANULE SOURCE_DIR
set -u
granule=$1
source=$2
work=$(mktemp -d)
disk=$work/disk
mkdir -p "$disk"
if ! mount -t tmpfs -o size=2m tmpfs "$disk" 2> "$work/mount.txt"; then
  echo "skipped: cannot mount tmpfs ($(tr '\n' ' ' < "$work/mount.txt"))"
  rm -rf "$work"
  exit 77
fi
trap 'umount "$disk"; rm -rf "$work"' EXIT
fail() {
  echo "FAILED: $*"
  for f in "$work"/*.txt; do echo "--- $f"; cat "$f"; done
  exit 1
}
# Exit status non-zero and below 128 (not a signal).
check_status() {
  [ "$1" -ne 0 ] || fail "$2: exit status 0 on a full disk"
  [ "$1" -lt 128 ] || fail "$2: exit status $1: the program died of a signal"
}
# The file opens; every snapshot it counts is complete and finite; at least $2 of them.
check_readable() {
  /usr/bin/python3 - "$1" "$2" <<'PY' || fail "$1 is not readable as it must be"
import sys, h5py, numpy as np
path, least = sys.argv[1], int(sys.argv[2])
with h5py.File(path, "r") as f:
    count = int(f["snapshots"].attrs["count"])
    assert count >= least, f"{count} snapshots, expected at least {least}"
    for k in range(count):
        g = f["snapshots/%06d" % k]
        n = len(g["id"])
        assert n > 0, f"snapshot {k} is empty"
        for name in ("position", "velocity", "spin", "radius"):
            a = g[name][:]
            assert len(a) == n and np.all(np.isfinite(a)), f"snapshot {k}: {name}"
    t = f["series/time"][:]
    assert np.all(np.isfinite(t)), "series time"
print(f"{path}: {count} snapshots readable")
PY
}

# 1. Snapshots until the disk is full (1500 particles, one every 0.2 ms).
status=0
"$granule" run "$source/scenarios/mechanofusion_demo.lua" -D duration=0.01 -D snapshot_every=2e-4 \
  -o "$disk/out.h5" --quiet > "$work/snapshots.txt" 2>&1 || status=$?
check_status $status snapshots
grep -q "out.h5" "$work/snapshots.txt" || fail "snapshots: the message does not name the file"
grep -q "no space left" "$work/snapshots.txt" || fail "snapshots: the message does not say the disk is full"
check_readable "$disk/out.h5" 1
rm -f "$disk"/*

# 2. Checkpoints: the first fits, a later one does not (the old one and the new must fit
# together while the new is written); the first stays, readable, and the run says so.
"$granule" run "$source/tests/scenes/restart.lua" -D checkpoint="$work/probe.chk.h5" \
  -D stage2_steps=1000 -o "$work/probe.h5" --quiet > /dev/null 2>&1 || fail "checkpoint probe run"
size=$(stat -c %s "$work/probe.chk.h5")
free=$(df -B1 --output=avail "$disk" | tail -1)
filler=$((free - size * 3 / 2))
[ "$filler" -gt 0 ] || fail "a checkpoint of $size bytes does not fit twice in the test disk"
head -c "$filler" /dev/zero > "$disk/filler" 2> /dev/null
status=0
"$granule" run "$source/tests/scenes/restart.lua" -D checkpoint="$disk/run.chk.h5" \
  -D checkpoint_every=1000 -o "$work/run.h5" --quiet > "$work/checkpoint.txt" 2>&1 || status=$?
check_status $status checkpoint
grep -q "run.chk.h5" "$work/checkpoint.txt" || fail "checkpoint: the message does not name the file"
grep -q "no space left" "$work/checkpoint.txt" || fail "checkpoint: the message does not say the disk is full"
grep -q "previous checkpoint .*run.chk.h5 is kept" "$work/checkpoint.txt" ||
  fail "checkpoint: the message does not say the previous checkpoint is kept"
[ ! -e "$disk/run.chk.h5.tmp" ] || fail "checkpoint: the half-written run.chk.h5.tmp was left behind"
step=$(/usr/bin/python3 -c 'import sys, h5py; print(int(h5py.File(sys.argv[1], "r")["checkpoint/integers/meta"][2]))' "$disk/run.chk.h5") ||
  fail "checkpoint: the previous checkpoint is not readable"
[ "$step" -eq 1000 ] || fail "checkpoint: the kept checkpoint is at step $step, expected 1000"
rm -f "$disk/filler"
# The same -D values: a restart continues the run that wrote the checkpoint.
"$granule" run "$source/tests/scenes/restart.lua" -D checkpoint="$disk/run.chk.h5" \
  -D checkpoint_every=1000 --restart "$disk/run.chk.h5" -o "$work/again.h5" --quiet \
  > "$work/restart.txt" 2>&1 || fail "the kept checkpoint does not restart"
echo "the message:"; head -1 "$work/checkpoint.txt"
echo "full disk handled cleanly"
