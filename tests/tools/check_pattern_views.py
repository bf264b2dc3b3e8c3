#!/usr/bin/python3
"""tools/plot_pattern.py's 3D views: the coordinates each view gives, the slab,
and an animated GIF with one frame per snapshot drawn.

usage: /usr/bin/python3 tests/tools/check_pattern_views.py TOOLS_DIR OUT_3D.h5
"""
import os
import sys

import numpy as np

sys.path.insert(0, sys.argv[1])
import granule_h5 as g  # noqa: E402
import plot_pattern as pp  # noqa: E402


def fail(message):
    sys.exit(f"check_pattern_views: {message}")


# Particles on +x, +y, +z: where each view puts them (right, up, towards the viewer).
snap = {"position": np.array([[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0]]), "radius": np.ones(3),
        "fixed": np.zeros(3, dtype=np.uint8), "velocity": np.zeros((3, 3))}
want = {"xy": [[1, 0, 0], [0, 1, 0], [0, 0, 1]],
        "xz": [[1, 0, 0], [0, 0, -1], [0, 1, 0]],   # looking along +y: nearer is smaller y
        "yz": [[0, 0, 1], [1, 0, 0], [0, 1, 0]]}   # looking along -x: nearer is larger x
walls = {"tube": {"type": "cylinder", "center": [0, 0, 0], "radius": 1.0}}
for view, rows in want.items():
    got, moved = pp.in_view(snap, walls, view)
    if not np.array_equal(got["position"], np.array(rows, dtype=float)):
        fail(f"--view {view}: positions {got['position'].tolist()}, expected {rows}")
    axis = moved["tube"]["axis"]
    if view != "xy" and abs(axis[1]) != 1:  # a z-axis cylinder stands up in the side views
        fail(f"--view {view}: the tube's axis became {axis}")
got, _ = pp.in_view(snap, walls, "xz", slab=(0.5, 1.5))  # y in [0.5, 1.5]: the second only
if len(got["radius"]) != 1 or not np.array_equal(got["position"][0], [0.0, 0.0, -1.0]):
    fail(f"--slab kept {got['position'].tolist()}")
try:
    pp.in_view({"position": np.zeros((1, 2)), "radius": np.ones(1)}, {}, "xz")
    fail("--view xz on 2D output was accepted")
except g.GranuleH5Error as e:
    if "3D" not in str(e):
        fail(f"2D refusal says {e}")

# The whole tool on real output: every snapshot a frame of the GIF.
out = os.path.abspath("pattern_views_test")
os.makedirs(out, exist_ok=True)
gif = os.path.join(out, "movie.gif")
written = pp.plot_pattern(sys.argv[2], every=1, output=os.path.join(out, "frame.png"), view_name="xz",
                          gif=gif)
from PIL import Image  # noqa: E402

frames = Image.open(gif).n_frames
if frames != len(written) - 1:
    fail(f"the GIF has {frames} frames for {len(written) - 1} PNGs")
print(f"pattern views ok: {frames} frames")
