# What a run stopped by a full disk or a file size limit must leave, for the
# tests that stop one (full_disk_test.sh, file_size_limit_test.sh): sourced with
# $work set to the test's folder, whose *.txt files a failure prints.
fail() {
  echo "FAILED: $*"
  for f in "$work"/*.txt; do echo "--- $f"; cat "$f"; done
  exit 1
}
# Exit status non-zero and below 128 (not a signal).
check_status() {
  [ "$1" -ne 0 ] || fail "$2: exit status 0 where the output could not be written"
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
