#!/usr/bin/env python3
"""Reads /scene/effects written by tests/scenes/effects_check.lua: a 2D scene
with linear pairs (friction 0.4), an adhesive law declared for a material no
particle has, a moving floor, gravity declared zero, no diagnostics."""
import sys

import h5py

with h5py.File(sys.argv[1], "r") as f:
    e = dict(f["/scene/effects"].attrs)
text = {k: (v.decode() if isinstance(v, bytes) else v) for k, v in e.items()}
expected = {"dimension": 2, "adhesion": 0, "friction": 1, "rotation": 1, "gravity": 0, "central_field": 0,
            "moving_walls": 1, "moving_wall_names": "floor", "periodic": 0, "diagnostics": ""}
wrong = {k: (text.get(k), v) for k, v in expected.items() if text.get(k) != v}
if wrong:
    sys.exit(f"/scene/effects: (got, expected) {wrong}")
pairs = text["pairs"].split(", ")
if sorted(pairs) != ["powder-powder linear", "powder-steel linear"]:
    sys.exit(f"/scene/effects pairs: {pairs}")
print("effects attributes ok")
