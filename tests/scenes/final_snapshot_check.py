"""Reads what tests/scenes/final_snapshot.lua wrote: the last snapshot holds the
final state (the particle removed at the last step gone), and the XDMF index
lists one grid per time (the final state's, not the step's first snapshot)."""
import re
import sys

import h5py

h5, xmf = sys.argv[1], sys.argv[2]
s = h5py.File(h5, "r")["snapshots"]
last = "%06d" % (s.attrs["count"] - 1)
ids = list(s[last]["id"][:])
times = re.findall(r'<Time Value="([^"]+)"', open(xmf).read())
groups = re.findall(r"snapshots/(\d{6})/position", open(xmf).read())
print("final snapshot ids", ids, "index times", times, "groups", groups)
assert ids == [0, 1], ids
assert len(times) == len(set(times)), times
assert groups and groups[-1] == last, (groups, last)
print("final snapshot ok")
