#!/usr/bin/env python3
"""An output goes on recording after a failed run that the scene caught; a
second output opened later records from where it was opened; -o names both.

A run fails (a particle sent too fast: it steps over a contact); the scene
catches the error with pcall, slows the particle, adds a wall and runs on,
as a REPL session does. The file must then hold: the failure's snapshot,
marked, at the step the failure took, with the time of that step; the later
run's series rows up to its last step; the wall added after the failure; a
final snapshot at the last step; and nothing non-finite. The scene then
opens a second file and runs on: under `-o first.h5` the first output is
first.h5 and the second first_second.h5, whose first snapshot and series row
are of the step it was opened at.

A scene that ends on an error of its own (in a callback, or in its Lua after a
run) leaves `failure` on its file's root, naming the error and the step; a
scene that ends well leaves none.

Usage: failure_recovery_test.py GRANULE WORK_DIR
"""
import os
import subprocess
import sys

import h5py
import numpy as np

SCENE = r"""
local sim = simulation { dimension = 2, time_step = 1e-6 }
sim:material { name = "grain", density = 2500 }
sim:material { name = "steel", density = 7800 }
sim:contact { "grain", "grain", model = "linear", k_normal = 1e3, restitution = 0.5 }
sim:contact { "grain", "steel", model = "linear", k_normal = 1e3, restitution = 0.5 }
sim:wall_plane { name = "floor", point = { 0, 0 }, normal = { 0, 1 }, material = "steel" }
for k = 0, 9 do sim:add_particle { position = { k * 1e-3, 1e-3 }, radius = 0.4e-3, material = "grain" } end
sim:gravity { 0, -9.81 }
sim:output { file = "recovery.h5", snapshot_every = 0, series_every = 20e-6 }
sim:run { steps = 50 }
sim:set_velocity(3, { 0, 1e3 })  -- 1 mm a step upwards: more than the radius
local ok, err = pcall(function() sim:run { steps = 50 } end)
assert(not ok and err:find("more than the smallest radius"), tostring(err))
print("failed at", sim:step_count())
sim:set_velocity(3, { 0, 0 })
sim:wall_plane { name = "lid", point = { 0, 5e-3 }, normal = { 0, -1 }, material = "steel" }
sim:run { steps = 120 }
print("ended at", sim:step_count())
sim:output { file = "second.h5", snapshot_every = 50e-6 }
-- Set up after opening, before the run: the file records the state the run starts from.
sim:add_particle { position = { 20e-3, 1e-3 }, radius = 0.4e-3, material = "grain" }
sim:gravity { 0, -5 }
sim:run { steps = 100 }
-- A failure that leaves an infinite kinetic energy (a particle at 1e308 m/s), caught; a
-- third file opened then records from the next run on, whose rows are finite again.
sim:set_velocity(3, { 0, 1e308 })
assert(not pcall(function() sim:run { steps = 5 } end))
sim:set_velocity(3, { 0, 0 })
sim:set_position(3, { 3e-3, 1e-3 })
local ok, err = pcall(function() sim:output { file = "third.h5" } end)
assert(ok, tostring(err))
sim:run { steps = 20 }
print("third ended at", sim:step_count())
"""


ENDING = r"""
local sim = simulation { dimension = 2, time_step = 1e-6 }
sim:material { name = "grain", density = 2500 }
sim:contact { "grain", "grain", model = "linear", k_normal = 1e3, restitution = 0.5 }
sim:wall_plane { name = "floor", point = { 0, 0 }, normal = { 0, 1 }, material = "grain" }
for k = 0, 4 do sim:add_particle { position = { k * 1e-3, 1e-3 }, radius = 0.4e-3, material = "grain" } end
sim:gravity { 0, -9.81 }
sim:output { file = "ending.h5", snapshot_every = 0 }
local how = os.getenv("ENDING")
sim:every { steps = 30, function(s) if how == "callback" and s:step_count() >= 60 then error("callback gave up") end end }
sim:run { steps = 100 }
if how == "lua" then error("scene gave up") end
"""


def fail(message):
    print(f"FAILED: {message}")
    sys.exit(1)


def main():
    granule, work = sys.argv[1:3]
    os.makedirs(work, exist_ok=True)
    os.chdir(work)
    with open("recovery.lua", "w") as f:
        f.write(SCENE)
    for name in os.listdir("."):
        if name.endswith(".h5"):
            os.remove(name)
    r = subprocess.run([granule, "run", "recovery.lua", "-q", "-o", "first.h5"],
                       capture_output=True, text=True, timeout=120)
    if r.returncode != 0:
        fail(f"the scene failed ({r.returncode}):\n{r.stdout}\n{r.stderr}")
    failed_at = int(r.stdout.split("failed at")[1].split()[0])
    ended_at = int(r.stdout.split("ended at")[1].split()[0])
    if failed_at != 51 or ended_at != failed_at + 120:
        fail(f"failed at step {failed_at} (expected 51, the step taken), ended at {ended_at}")
    third_end = int(r.stdout.split("third ended at")[1].split()[0])
    names = sorted(n for n in os.listdir(".") if n.endswith(".h5"))
    if names != ["first.h5", "first_second.h5", "first_third.h5"]:
        fail(f"-o first.h5 should name first.h5, first_second.h5 and first_third.h5: {names}")
    with h5py.File("first_second.h5", "r") as f:
        snaps = f["snapshots"]
        steps = [int(snaps["%06d" % k].attrs["step"]) for k in range(snaps.attrs["count"])]
        series_steps = list(f["series/step"][:])
        if steps[0] != ended_at or series_steps[0] != ended_at or ended_at + 100 not in steps:
            fail(f"the second file should start at step {ended_at}: snapshots {steps}, "
                 f"series {series_steps}")
        if len(snaps["000000/id"]) != 11 or list(f["scene"].attrs["gravity"]) != [0, -5]:
            fail(f"the second file's start is not the state its run began from: "
                 f"{len(snaps['000000/id'])} particles, gravity {list(f['scene'].attrs['gravity'])}")
    with h5py.File("first_third.h5", "r") as f:
        snaps = f["snapshots"]
        steps = [int(snaps["%06d" % k].attrs["step"]) for k in range(snaps.attrs["count"])]
        if steps[-1] != third_end or steps[0] != third_end - 20:
            fail(f"the third file should hold steps {third_end - 20} to {third_end}: {steps}")
        for name in f["series"]:
            if not np.isfinite(f["series"][name][:]).all():
                fail(f"non-finite series column {name} in the third file")
    with h5py.File("first.h5", "r") as f:
        snaps = f["snapshots"]
        groups = [snaps["%06d" % k] for k in range(snaps.attrs["count"])]
        steps = [int(g.attrs["step"]) for g in groups]
        failed = [g for g in groups if "failure" in g.attrs]
        if len(failed) != 1 or int(failed[0].attrs["step"]) != failed_at:
            fail(f"one failure snapshot at step {failed_at} expected: steps {steps}")
        if abs(float(failed[0].attrs["time"]) - failed_at * 1e-6) > 1e-12:
            fail(f"the failure snapshot's time {failed[0].attrs['time']} is not its step's")
        if ended_at not in steps:
            fail(f"no snapshot at the end of the recovered run, step {ended_at}: steps {steps}")
        if len(set(steps)) != len(steps):
            fail(f"two snapshots of one step: {steps}")
        series_steps = f["series/step"][:]
        if series_steps[-1] != ended_at or not (np.diff(series_steps) > 0).all():
            fail(f"the series does not run on to step {ended_at}: {series_steps}")
        if sorted(f["walls"].keys()) != ["floor", "lid"]:
            fail(f"the wall added after the failure is missing: {list(f['walls'].keys())}")
        for g in groups:
            for q in ("position", "velocity", "spin"):
                if not np.isfinite(g[q][:]).all():
                    fail(f"non-finite {q} in snapshot at step {g.attrs['step']}")
        for name in f["series"]:
            if not np.isfinite(f["series"][name][:]).all():
                fail(f"non-finite series column {name}")
    with open("ending.lua", "w") as f:
        f.write(ENDING)
    for how, status, words, step in (("callback", 1, "callback gave up", 60),
                                     ("lua", 1, "scene gave up", 100), ("none", 0, None, None)):
        if os.path.exists("ending.h5"):
            os.remove("ending.h5")
        r = subprocess.run([granule, "run", "ending.lua", "-q"], capture_output=True, text=True,
                           timeout=60, env=dict(os.environ, ENDING=how))
        if r.returncode != status:
            fail(f"ending {how}: exit status {r.returncode}, expected {status}:\n{r.stderr}")
        with h5py.File("ending.h5", "r") as f:
            failure = f.attrs.get("failure")
        if words is None and failure is not None:
            fail(f"a scene that ended well has a failure: {failure}")
        if words is not None and (failure is None or words not in failure
                                  or f"(step {step})" not in failure
                                  or "traceback" in failure):
            fail(f"ending {how}: the file's failure should name '{words}' at step {step} "
                 f"(without the traceback): {failure!r}")
    print("failure_recovery_test ok")


main()
