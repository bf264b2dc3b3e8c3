"""Reads what tests/scenes/late_wall.lua wrote: the platen added at step 50 and
moving at -0.1 m/s is in /walls as it stood at the snapshot of step 100, not
where a wall-clock flush found it."""
import sys

import h5py

path, printed = sys.argv[1], float(sys.argv[2])
y = h5py.File(path, "r")["walls/top"].attrs["point"][1]
print("written", repr(y), "at the snapshot", repr(printed), "expected", 0.01 - 0.1 * 50 * 1e-5)
assert abs(printed - (0.01 - 0.1 * 50 * 1e-5)) < 1e-12, printed
assert y == printed, (y, printed)
print("late wall ok")
