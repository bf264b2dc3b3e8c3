#!/usr/bin/env python3
"""Reads /scene/effects written by tests/scenes/effects_check.lua: a 2D scene
with linear pairs (friction 0.4), an adhesive law declared for a material no
particle has, a moving floor, gravity declared zero, no diagnostics; and
/walls, which must also hold the lid the scene adds after the header; the
rolling scene's file, its rolling model by name and canonical_order = 1."""
import sys

import h5py

with h5py.File(sys.argv[1], "r") as f:
    e = dict(f["/scene/effects"].attrs)
text = {k: (v.decode() if isinstance(v, bytes) else v) for k, v in e.items()}
expected = {"dimension": 2, "adhesion": 0, "friction": 1, "rotation": 1, "gravity": 0, "central_field": 0,
            "moving_walls": 1, "moving_wall_names": "floor", "periodic": 0, "diagnostics": "",
            "canonical_order": 0}
wrong = {k: (text.get(k), v) for k, v in expected.items() if text.get(k) != v}
if wrong:
    sys.exit(f"/scene/effects: (got, expected) {wrong}")
pairs = text["pairs"].split(", ")
if sorted(pairs) != ["powder-powder linear", "powder-steel linear"]:
    sys.exit(f"/scene/effects pairs: {pairs}")
with h5py.File(sys.argv[1], "r") as f:
    walls = sorted(f["/walls"].keys())
    if walls != ["floor", "lid"]:
        sys.exit(f"/walls: {walls}, expected floor and lid (lid added after the header)")
    # The index contacts/wall gives each wall: declaration order, not HDF5's by name.
    index = {w: int(f["/walls"][w].attrs["index"]) for w in walls}
    if index != {"floor": 0, "lid": 1}:
        sys.exit(f"/walls index attributes {index}, expected floor 0 and lid 1")
    # Each snapshot says where the walls are then: the floor moves at 0.01 m/s along x from x = 0.
    snapshots = f["/snapshots"]
    last = snapshots[sorted(snapshots.keys())[-1]]
    t = float(last.attrs["time"])
    floor = last["walls/floor"].attrs
    if not (t > 0 and abs(floor["point"][0] - 0.01 * t) < 1e-15 and list(floor["velocity"]) == [0.01, 0.0]
            and int(last["walls/lid"].attrs["index"]) == 1):
        sys.exit(f"last snapshot (t = {t}): floor point {list(floor['point'])}, velocity "
                 f"{list(floor['velocity'])}; expected x = 0.01 t and (0.01, 0), lid index 1")
    lid = f["/walls/lid"].attrs
    if list(lid["point"]) != [0.0, 5e-3] or list(lid["normal"]) != [0.0, -1.0]:
        sys.exit(f"/walls/lid: point {list(lid['point'])}, normal {list(lid['normal'])}")
rolling = sys.argv[1][: -len(".h5")] + "_rolling.h5"
with h5py.File(rolling, "r") as f:
    model = f["/contacts/m-m"].attrs["rolling_model"]
    model = model.decode() if isinstance(model, bytes) else model
    if model != "epsd":
        sys.exit(f"{rolling}: /contacts/m-m rolling_model {model!r}, expected 'epsd'")
    canonical = f["/scene/effects"].attrs["canonical_order"]
    if canonical != 1:
        sys.exit(f"{rolling}: /scene/effects canonical_order {canonical}, expected 1 (sim:set)")
stages = sys.argv[1][: -len(".h5")] + "_stages.h5"
with h5py.File(stages, "r") as f:
    e = {k: (v.decode() if isinstance(v, bytes) else v) for k, v in f["/scene/effects"].attrs.items()}
    want = {"friction": 1, "rotation": 1, "gravity": 1, "moving_walls": 1, "moving_wall_names": "floor, lid",
            "bonds": 0, "rolling": 0}
    wrong = {k: (e.get(k), v) for k, v in want.items() if e.get(k) != v}
    if wrong:
        sys.exit(f"{stages}: /scene/effects after a second stage (got, expected) {wrong}")
    steps = list(f["/series/step"][:])
    if steps != [0, 20, 40]:
        sys.exit(f"{stages}: /series steps {steps}: expected rows at step 0 and at each run's end")
bonds = sys.argv[1][: -len(".h5")] + "_bonds.h5"
with h5py.File(bonds, "r") as f:
    e = dict(f["/scene/effects"].attrs)
    if e.get("bonds") != 1 or e.get("rotation") != 1 or e.get("friction") != 0:
        sys.exit(f"{bonds}: /scene/effects bonds {e.get('bonds')}, rotation {e.get('rotation')}, "
                 f"friction {e.get('friction')}: expected 1, 1 and 0 (the bonds turn the particles)")
periodic = sys.argv[1][: -len(".h5")] + "_periodic.h5"
with h5py.File(periodic, "r") as f:
    a = {k: (v.decode() if isinstance(v, bytes) else v) for k, v in f["/scene"].attrs.items()}
    got = (a.get("periodic_axis"), a.get("periodic_origin"), a.get("periodic_length"), a.get("periodic_units"))
    if got != ("y", -2e-3, 8e-3, "m"):
        sys.exit(f"{periodic}: /scene periodic attributes {got}, expected ('y', -0.002, 0.008, 'm')")
turning = sys.argv[1][: -len(".h5")] + "_turning.h5"
with h5py.File(turning, "r") as f:
    snapshots = f["/snapshots"]
    last = snapshots[sorted(snapshots.keys())[-1]]
    t = float(last.attrs["time"])
    a = last["walls/paddle"].attrs
    if not (t > 0 and abs(a["angle"] - 100 * t) <= 1e-9 * 100 * t and a["angle_units"] == "rad"):
        sys.exit(f"{turning}: last snapshot (t = {t}) paddle angle {a.get('angle')}, expected 100 t rad")
print("effects attributes ok")
