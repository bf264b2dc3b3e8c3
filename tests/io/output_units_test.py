#!/usr/bin/env python3
"""Output that documents itself, read back with h5py.

Runs tests/scenes/output_documented.lua, then checks: every dataset in the file but the
scene's text has a `units` attribute, and the snapshot, contact and /series datasets have the unit their
quantity is in; every /scene/parameters value has its declared unit in
/scene/parameters/units; the scene's series carry the units it gave (or, unnamed, the
standard one of time); the wall_force diagnostic's columns carry its units; /scene holds
gravity and the central field as the scene set them; the snapshots asked for hold force,
torque and the contact network, and each particle's force is the sum of its contacts'
forces (Newton's third law for the pair: the normal points from j to i, the forces are
on i) plus m g and the central field's pull; the snapshot taken without them holds neither.

Usage: output_units_test.py GRANULE SOURCE_DIR WORK_DIR
"""
import os
import subprocess
import sys

import h5py
import numpy as np


def fail(message):
    print(f"FAILED: {message}")
    sys.exit(1)


def text(v):
    return v.decode() if isinstance(v, bytes) else str(v)


def main():
    granule, source, work = sys.argv[1:4]
    os.makedirs(work, exist_ok=True)
    os.chdir(work)
    scene = os.path.join(source, "tests", "scenes", "output_documented.lua")
    r = subprocess.run([granule, "run", scene, "-q"], capture_output=True, text=True, timeout=120)
    if r.returncode != 0 or "output_documented ok" not in r.stdout:
        fail(f"the scene failed ({r.returncode}):\n{r.stdout}\n{r.stderr}")
    expected = {"id": "-", "radius": "m", "position": "m", "velocity": "m/s", "spin": "rad/s",
                "material": "-", "fixed": "-", "force": "N", "torque": "N m", "i": "-", "j": "-",
                "wall": "-", "overlap": "m", "normal_force": "N", "tangential_force": "N",
                "normal": "-"}
    with h5py.File("output_documented_test.h5", "r") as f:
        datasets = []
        f.visititems(lambda name, obj: datasets.append(name) if isinstance(obj, h5py.Dataset) else None)
        text_datasets = {"scene/source", "scene/description"}  # the scene's text: no quantity
        missing = [n for n in datasets if "units" not in f[n].attrs and n not in text_datasets]
        if missing:
            fail(f"datasets without a units attribute: {missing}")
        for name in datasets:
            if name.startswith("snapshots/"):
                base = name.rsplit("/", 1)[1]
                if text(f[name].attrs["units"]) != expected[base]:
                    fail(f"{name} units {text(f[name].attrs['units'])!r}, expected {expected[base]!r}")
        series_units = {"series/time": "s", "series/kinetic_energy_translational": "J",
                        "series/momentum_x": "kg m/s", "probe/time": "s", "probe/height": "m",
                        "plain/time": "s", "plain/whatever": "",
                        "diagnostics/floor/normal_force": "N", "diagnostics/floor/samples": "-",
                        "diagnostics/floor/time": "s",
                        "diagnostics/overlaps/max_overlap_ratio/time": "s",
                        "diagnostics/overlaps/max_overlap_ratio/wall": "-"}
        # Every diagnostic column has a unit, not the empty one (a group's units
        # given in any form reach each of its columns).
        unitless = [n for n in datasets if n.startswith("diagnostics/") and not text(f[n].attrs["units"])]
        if unitless:
            fail(f"diagnostic columns without a unit: {unitless}")
        for name, unit in series_units.items():
            if text(f[name].attrs["units"]) != unit:
                fail(f"{name} units {text(f[name].attrs['units'])!r}, expected {unit!r}")
        if "rubber" not in f["materials"] or "glass-rubber" not in f["contacts"]:
            fail(f"a material and law declared after the first output are missing: "
                 f"{list(f['materials'])}, {list(f['contacts'])}")
        if f["contacts/glass-rubber"].attrs["k_normal"] != 2e3:
            fail("the later law's parameters are not the ones declared")
        params = f["scene/parameters"].attrs
        punits = f["scene/parameters/units"].attrs
        if sorted(params) != sorted(punits):
            fail(f"parameters {sorted(params)} but units for {sorted(punits)}")
        for name, unit in {"radius": "m", "overlap": "m", "label": "", "file": ""}.items():
            if text(punits[name]) != unit:
                fail(f"parameter {name}: unit {text(punits[name])!r}, expected {unit!r}")
        # Parameters declared integer = true stay whole (a tool reading the seed
        # gets 7, not 7.0); the rest are doubles, whatever -D wrote.
        if not np.issubdtype(np.asarray(params["seed"]).dtype, np.integer) or params["seed"] != 7:
            fail(f"parameter seed: {params['seed']!r} ({np.asarray(params['seed']).dtype}), "
                 "expected the integer 7")
        for name in ("radius", "speed"):  # speed: a whole default, not declared integer
            if not np.issubdtype(np.asarray(params[name]).dtype, np.floating):
                fail(f"parameter {name}: {np.asarray(params[name]).dtype}, expected a double")
        scene = f["scene"].attrs
        if not np.array_equal(scene["gravity"], [0, 0, -9.81]) or text(scene["gravity_units"]) != "m/s^2":
            fail(f"/scene gravity {scene.get('gravity')}")
        if (scene["central_field"] != 1 or not np.array_equal(scene["central_field_point"], [0, 0, 1])
                or scene["central_field_strength"] != 0.5):
            fail(f"/scene central field {dict(scene)}")

        snaps = [f["snapshots"][k] for k in sorted(f["snapshots"])]
        steps = [int(s.attrs["step"]) for s in snaps]
        if len(set(steps)) != len(steps):
            fail(f"two snapshots of one step (the second a copy of the first): steps {steps}")
        full = [s for s in snaps if "force" in s]
        plain = [s for s in snaps if "force" not in s]
        if len(full) < 2 or len(plain) != 1 or "contacts" in plain[0]:
            fail(f"{len(full)} snapshots with forces, {len(plain)} without (want >= 2 and 1, "
                 "that one without contacts)")
        checked = 0
        for s in full:
            if s.attrs["step"] == 0:
                continue  # before the first step no force has been computed
            ids = s["id"][:]
            force = s["force"][:]
            if s["torque"].shape != (len(ids), 3):
                fail(f"torque shape {s['torque'].shape}")
            c = s["contacts"]
            i, j, wall = c["i"][:], c["j"][:], c["wall"][:]
            on_i = c["normal_force"][:][:, None] * c["normal"][:] + c["tangential_force"][:]
            if len(i) != 3 or sorted(wall.tolist()) != [-1, 0, 0]:
                fail(f"contacts at step {s.attrs['step']}: i={i}, j={j}, wall={wall} (want one pair, "
                     "two on the floor)")
            total = {int(p): np.zeros(3) for p in ids}
            for k in range(len(i)):
                total[int(i[k])] += on_i[k]
                if j[k] >= 0:
                    total[int(j[k])] -= on_i[k]
            # The body forces too: m g and m a towards the field's point (strength a = 0.5 m/s^2).
            pos, radius = s["position"][:], s["radius"][:]
            for row, p in enumerate(ids):
                m = 2500 * 4 / 3 * np.pi * radius[row] ** 3
                towards = np.array([0, 0, 1.0]) - pos[row]
                body = m * (np.array([0, 0, -9.81]) + 0.5 * towards / np.linalg.norm(towards))
                want = total[int(p)] + body
                if np.abs(want - force[row]).max() > 1e-9 * np.abs(force).max():
                    fail(f"particle {p}: force {force[row]}, but its contacts and body forces sum "
                         f"to {want}")
            checked += 1
        if checked == 0:
            fail("no snapshot after a step to check forces in")
    print(f"output_units_test ok: {len(datasets)} datasets with units, forces checked in {checked} snapshots")


if __name__ == "__main__":
    main()
