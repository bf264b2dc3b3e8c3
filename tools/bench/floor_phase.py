#!/usr/bin/python3
"""The 3D box's shaking floor in Granule, LAMMPS and LIGGGHTS, side by side:
one sphere resting on the floor of each program's deck (the floors of
tools/bench/box_3d.lmp, box_3d.liggghts and lua/granule/bench.lua, at the
packing's 0.05 mm and 50 Hz) rides its stroke; this prints its height above
rest, z - z0, at T/8, T/4 and T/2 next to the stroke z = A (1 - cos wt) they
all should follow (the sphere's own weight on the contact shifts it by
~1e-8 m). A floor at another phase shows at once (mid-stroke, z = A sin wt:
3.5e-5 m at T/8).

    /usr/bin/python3 tools/bench/floor_phase.py
"""
import math
import os
import re
import shutil
import subprocess
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
GRANULE = os.path.join(ROOT, "build", "granule")
A, PERIOD, DT, R = 0.05e-3, 0.02, 1.5e-6, 1e-3
EIGHTH = round(PERIOD / 8 / DT)
MASS = 4 / 3 * math.pi * R**3 * 2500
Z0 = R - MASS * 9.81 / 1e4  # resting on the floor: overlap m g / k_n

DATA = """one sphere

1 atoms
{types} atom types

-0.01 0.01 xlo xhi
-0.01 0.01 ylo yhi
-0.001 0.02 zlo zhi

Atoms

1 1 0.002 2500 0 0 {z0!r}
"""
# Both decks end alike: integrate, print the sphere's height every T/8.
DECK_END = """fix integrate all nve/sphere
variable zp equal z[1]
thermo_style custom step v_zp
thermo_modify format float %.10g
thermo {eighth}
run {steps}
"""
LAMMPS = """units si
atom_style sphere
atom_modify map array
boundary f f f
comm_modify vel yes
read_data one.data
pair_style gran/hooke/history 1e4 3e3 100 50 0.5 1
pair_coeff * *
neighbor 0.0005 bin
timestep {dt}
fix gravity all gravity 9.81 vector 0 0 -1
fix floor all wall/gran hooke/history 1e4 3e3 100 50 0.5 1 zplane 0 NULL wiggle z {a} {period}
"""
LIGGGHTS = """atom_style granular
atom_modify map array
boundary f f f
newton off
communicate single vel yes
units si
read_data one.data
neighbor 0.0005 bin
fix kn all property/global kn peratomtypepair 2 1e4 1e4 1e4 1e4
fix kt all property/global kt peratomtypepair 2 3e3 3e3 3e3 3e3
fix gn all property/global gamman peratomtypepair 2 100 100 100 100
fix gt all property/global gammat peratomtypepair 2 50 50 50 50
fix mu all property/global coefficientFriction peratomtypepair 2 0.5 0.5 0.5 0.5
pair_style gran model hooke/stiffness tangential history
pair_coeff * *
timestep {dt}
fix gravity all gravity 9.81 vector 0.0 0.0 -1.0
fix floor all mesh/surface file floor.stl type 2
fix floor_contact all wall/gran model hooke/stiffness tangential history mesh n_meshes 1 meshes floor
fix shake all move/mesh mesh floor viblin axis 0 0 1 order 1 amplitude {a} phase {phase!r} period {period}
"""
SCENE = """local bench = require "granule.bench"
local sim = bench.shaken_box {{ per_side = 10, amplitude = {a!r}, frequency = {f!r}, time_step = {dt!r} }}
local id = sim:add_particle {{ position = {{ 0.005, 0.005, {z0!r} }}, radius = {r!r}, material = "glass" }}
for k = 1, 4 do
  sim:run {{ steps = {eighth} }}
  print(string.format("%d %.10g", k * {eighth}, sim:particle(id).position[3]))
end
"""
FLOOR = """solid floor
 facet normal 0 0 1
  outer loop
   vertex -0.01 -0.01 0
   vertex 0.01 -0.01 0
   vertex 0.01 0.01 0
  endloop
 endfacet
 facet normal 0 0 1
  outer loop
   vertex -0.01 -0.01 0
   vertex 0.01 0.01 0
   vertex -0.01 0.01 0
  endloop
 endfacet
endsolid floor
"""


def heights(out):
    """Step -> z from lines "step z" (thermo output or the scene's prints)."""
    z = {}
    for line in out.splitlines():
        m = re.match(r"\s*(\d+)\s+([0-9.eE+-]+)\s*$", line)
        if m:
            z[int(m.group(1))] = float(m.group(2))
    return z


def run(cmd, cwd):
    return subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, check=True).stdout


def main():
    steps = 4 * EIGHTH
    common = dict(dt=DT, a=A, period=PERIOD, eighth=EIGHTH, steps=steps)
    rows = {}
    with tempfile.TemporaryDirectory() as work:
        with open(os.path.join(work, "one.lua"), "w") as f:
            f.write(SCENE.format(a=A, f=1 / PERIOD, dt=DT, z0=Z0, r=R, eighth=EIGHTH))
        rows["granule"] = heights(run([GRANULE, "run", "one.lua", "--quiet"], work))
        if shutil.which("lmp"):
            with open(os.path.join(work, "one.data"), "w") as f:
                f.write(DATA.format(types=1, z0=Z0))
            with open(os.path.join(work, "in.lmp"), "w") as f:
                f.write((LAMMPS + DECK_END).format(**common))
            rows["lammps"] = heights(run(["lmp", "-in", "in.lmp", "-log", "none"], work))
        if shutil.which("liggghts"):
            with open(os.path.join(work, "one.data"), "w") as f:
                f.write(DATA.format(types=2, z0=Z0))
            with open(os.path.join(work, "floor.stl"), "w") as f:
                f.write(FLOOR)
            with open(os.path.join(work, "in.liggghts"), "w") as f:
                f.write((LIGGGHTS + DECK_END).format(phase=math.pi, **common))
            rows["liggghts"] = heights(run(["liggghts", "-in", "in.liggghts", "-log", "none"], work))
    omega = 2 * math.pi / PERIOD
    print(f"one sphere on the shaking floor (A = {A:g} m, T = {PERIOD:g} s): z - z0 [m]")
    print(f"{'':10s} {'T/8':>11s} {'T/4':>11s} {'T/2':>11s}")
    marks = (EIGHTH, 2 * EIGHTH, 4 * EIGHTH)
    print(f"{'stroke':10s} " + " ".join(f"{A * (1 - math.cos(omega * m * DT)):11.4g}" for m in marks))
    for name, z in rows.items():
        print(f"{name:10s} " + " ".join(f"{z[m] - Z0:11.4g}" if m in z else f"{'-':>11s}" for m in marks))


if __name__ == "__main__":
    main()
