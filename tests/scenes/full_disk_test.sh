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
. "$(dirname "$0")/failed_run_checks.sh"

# 1. Snapshots until the disk is full (1500 particles, one every 0.2 ms).
status=0
"$granule" run "$source/scenarios/mechanofusion_demo.lua" -D duration=0.01 -D snapshot_every=2e-4 \
  -o "$disk/out.h5" --quiet > "$work/snapshots.txt" 2>&1 || status=$?
check_status $status snapshots
grep -q "out.h5" "$work/snapshots.txt" || fail "snapshots: the message does not name the file"
grep -q "no space left" "$work/snapshots.txt" || fail "snapshots: the message does not say the disk is full"
check_readable "$disk/out.h5" 1
rm -f "$disk"/*

# 1b. A series of 90 columns appended every step, no snapshots: each flush extends 90
# chunked datasets at once. Every dataset of the file must read back whole afterwards
# (a flush the disk cut short left chunk indices pointing past the file's end).
cat > "$work/series.lua" <<'LUA'
local sim = simulation { dimension = 2 }
sim:material { name = "glass", density = 2500 }
sim:material { name = "steel", density = 0 }
sim:contact { "glass", "glass", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:contact { "glass", "steel", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 0.012, material = "steel", angular_velocity = 5 }
sim:fill { region = { circle = { center = { 0, 0 }, radius = 0.012 } }, count = 200, radius = 4e-4,
           material = "glass", seed = 3, overlap = false }
sim:output { series_every = 1e-6, snapshot_every = 0 }
local columns, row = {}, {}
for i = 1, 90 do columns[i] = "c" .. i end
sim:series("big", columns)
sim:every { steps = 1, function(s) for i = 1, 90 do row[i] = s:time() * i end s:append("big", row) end }
sim:run { steps = 300000 }
LUA
# The disk fills at another point of a flush for each free space; a build that
# lets HDF5 start a flush it cannot finish fails at some of these (on this VM at
# 1000-1080 KiB free). Some must have written rows before the disk filled.
written=0
for leave in $(seq 960 40 1960); do
  rm -f "$disk"/*
  free=$(df -B1 --output=avail "$disk" | tail -1)
  head -c $((free - leave * 1024)) /dev/zero > "$disk/filler" 2> /dev/null
  status=0
  "$granule" run "$work/series.lua" -o "$disk/series.h5" --quiet > "$work/series.txt" 2>&1 || status=$?
  check_status $status "series ($leave KiB free)"
  grep -q "no space left" "$work/series.txt" ||
    fail "series ($leave KiB free): the message does not say the disk is full"
  /usr/bin/python3 - "$disk/series.h5" "$leave" <<'PY' || fail "series ($leave KiB free): the file does not read back whole"
import sys, h5py, numpy as np
with h5py.File(sys.argv[1], "r") as f:
    datasets = []
    f.visititems(lambda name, o: datasets.append(name) if isinstance(o, h5py.Dataset) else None)
    lengths = set()
    for name in datasets:
        a = f[name][...]
        if name.startswith("big/"):
            assert np.all(np.isfinite(a)), name
            lengths.add(len(a))
    assert len(lengths) <= 1, f"series columns of unequal length: {lengths}"
    rows = lengths.pop() if lengths else 0
print(f"{sys.argv[2]} KiB free: {len(datasets)} datasets read back whole, {rows} rows")
PY
  if /usr/bin/python3 -c 'import sys, h5py; f = h5py.File(sys.argv[1], "r"); sys.exit(0 if "big" in f and len(f["big/c1"]) > 0 else 1)' "$disk/series.h5" 2> /dev/null; then
    written=$((written + 1))
  fi
done
[ "$written" -gt 0 ] || fail "series: no free space let a row be written before the disk filled"
echo "series: rows written before the disk filled at $written of the free spaces"
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
