#!/usr/bin/python3
"""Times Granule against LAMMPS (and LIGGGHTS where it can run the scene) on
the same scene, particle count, time step, contact law and starting state,
in one go on this machine, and prints particle-steps/s and the ratios.

    /usr/bin/python3 tools/bench/compare.py [--case mechanofusion2d|box3d|all]
        [--steps N] [--threads 1,2] [--work DIR] [--repeat N] [--csv FILE]

Each program starts from the state Granule settled and saved (converted to a
LAMMPS data file), so both time the same steady flow; the mean number of
contacts in the timed window is printed for each so that unlike work shows.
Every run also appends one row to a CSV file (--csv, default
WORK/bench_results.csv): the case, program, threads, steps, particles,
contacts, wall seconds and, for Granule, the seconds of each stage of the step
(the columns are listed in docs/performance.md). Without LAMMPS (`lmp`) or
LIGGGHTS (`liggghts`) on PATH, or without `mpirun` for more than one rank, the
Granule runs still happen and the report says which peers are missing.
On more than one core Granule runs twice: as threads, and spread over as many
MPI ranks ("granule ... (mpirun)", one thread each), as LAMMPS runs.
"""
import argparse
import csv
import datetime
import math
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import time

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
GRANULE = os.path.join(ROOT, "build", "granule")  # --granule replaces it
BENCH = os.path.join(ROOT, "tools", "bench")


def run(cmd, cwd, env=None):
    t0 = time.time()
    p = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, env=env)
    if p.returncode != 0:
        sys.exit(f"failed ({p.returncode}): {' '.join(cmd)}\n{p.stdout[-2000:]}\n{p.stderr[-2000:]}")
    return p.stdout + p.stderr, time.time() - t0


def last_snapshot(path):
    with h5py.File(path, "r") as f:
        g = f["snapshots/%06d" % (f["snapshots"].attrs["count"] - 1)]
        return {k: g[k][:] for k in ("id", "radius", "position", "velocity", "spin", "fixed")}


def write_lammps_data(state, path, box, dimension, density=1000.0, types=1):
    n = len(state["id"])
    pos, vel, spin = state["position"], state["velocity"], state["spin"]
    with open(path, "w") as f:
        f.write("Granule state converted by tools/bench/compare.py\n\n")
        f.write(f"{n} atoms\n{types} atom types\n\n")
        for axis, (lo, hi) in zip("xyz", box):
            f.write(f"{lo:.17g} {hi:.17g} {axis}lo {axis}hi\n")
        # The LAMMPS decks also `set` the mass (2D: LAMMPS reads density per area)
        f.write("\nAtoms # sphere\n\n")
        for k in range(n):
            z = pos[k][2] if dimension == 3 else 0.0
            f.write(f"{k + 1} 1 {2 * state['radius'][k]:.17g} {density:.17g} {pos[k][0]:.17g} {pos[k][1]:.17g} "
                    f"{z:.17g}\n")
        f.write("\nVelocities\n\n")
        for k in range(n):
            vz = vel[k][2] if dimension == 3 else 0.0
            w = spin[k] if dimension == 3 else (0.0, 0.0, spin[k][0])
            f.write(f"{k + 1} {vel[k][0]:.17g} {vel[k][1]:.17g} {vz:.17g} {w[0]:.17g} {w[1]:.17g} {w[2]:.17g}\n")


def lammps_loop(out):
    m = re.search(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms", out)
    if not m:
        sys.exit("could not read the LAMMPS loop time:\n" + out[-3000:])
    loop, procs, steps, atoms = float(m.group(1)), int(m.group(2)), int(m.group(3)), int(m.group(4))
    # thermo rows: step atoms pair_contacts [kinetic energy]
    rows = re.findall(r"^\s*(\d+)\s+(\d+)\s+([0-9.eE+-]+)(?:\s+([0-9.eE+-]+))?\s*$", out, re.M)
    contacts = np.mean([float(r[2]) for r in rows[1:]]) if len(rows) > 1 else float("nan")
    energies = [float(r[3]) for r in rows[1:] if r[3]]
    energy = float(np.mean(energies)) if energies else float("nan")
    return loop, procs, steps, atoms, contacts, energy


def granule_line(out):
    """The key=value fields of the line a bench scene prints (granule.bench's result_line)."""
    m = re.search(r"^granule (.*particle_steps_per_s=.*)$", out, re.M)
    if not m:
        sys.exit("could not read Granule's timing line:\n" + out[-3000:])
    fields = dict(kv.split("=", 1) for kv in m.group(1).split())
    for k, v in fields.items():
        if k != "model":
            fields[k] = float(v)
    return fields


def granule_row(program, threads, fields):
    """A result row out of a Granule run's timing line."""
    row = {"program": program, "threads": threads}
    row.update({k: v for k, v in fields.items() if k in CSV_COLUMNS})
    row["pair_contacts"] = fields.get("mean_pair_contacts", float("nan"))
    row["kinetic_energy"] = fields.get("mean_kinetic_energy", float("nan"))
    for k in ("steps", "particles", "list_rebuilds", "thread_rebalances"):
        if k in row:
            row[k] = int(row[k])
    return row


def peer_row(program, procs, out):
    """A result row out of a LAMMPS or LIGGGHTS run's output."""
    loop, p, steps, atoms, pair_contacts, energy = lammps_loop(out)
    return {"program": program, "threads": procs, "steps": steps, "particles": atoms, "wall_s": loop,
            "particle_steps_per_s": atoms * steps / loop, "pair_contacts": pair_contacts,
            "kinetic_energy": energy}


def peers_available(threads):
    """Which peer programs can run here: {'lmp': bool, 'liggghts': bool, 'mpirun': bool}."""
    have = {tool: shutil.which(tool) is not None for tool in ("lmp", "liggghts", "mpirun")}
    have["mpirun"] = have["mpirun"] or max(threads) == 1
    return have


def lammps_builds(args):
    """The LAMMPS binaries to time, each with the label suffix its rows get: Debian's `lmp`
    and, with --lammps-native, a build of the same source for this CPU."""
    builds = [("lmp", "")]
    if args.lammps_native:
        builds.append((args.lammps_native, " (native build)"))
    return builds


def peer_procs(args):
    """The rank counts the peers can run with (more than one needs mpirun)."""
    return [p for p in args.threads if p == 1 or args.peers["mpirun"]]


def granule_rows(args, work, program, scene_args):
    """Granule on each core count: as threads, and on more than one core also spread
    over as many MPI ranks of one thread each (a scene over ranks), where mpirun is
    here. Both rows are reported; the user picks the faster (docs/performance.md)."""
    rows = []
    for t in args.threads:
        out, _ = run([args.granule] + scene_args + ["--threads", str(t), "--quiet"], work)
        rows.append(granule_row(program, t, granule_line(out)))
        if t > 1 and shutil.which("mpirun"):
            out, _ = run(mpi_prefix(t) + [args.granule] + scene_args + ["--threads", "1", "--quiet"], work)
            rows.append(granule_row(program + RANKS, t, granule_line(out)))
    return rows


# The label of Granule's rows spread over MPI ranks (one thread each).
RANKS = " (mpirun)"


def mpi_prefix(procs):
    if procs == 1:
        return []
    return ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(procs)]


def mechanofusion2d(args, work):
    steps = args.steps or 200000
    custom = args.mf_particles != 1500 or args.mf_settle != 0.05
    name = f"mf_state_{args.mf_particles}p_settled{args.mf_settle:g}s" if custom else "mf_state"
    state = os.path.join(work, name + ".h5")
    if not os.path.exists(state):
        print(f"settling the 2D base case ({args.mf_settle:g} s of simulated time)...", flush=True)
        run([args.granule, "run", os.path.join(BENCH, "mechanofusion_compare.lua"), "-D", f"save={state}",
             "-D", f"particles={args.mf_particles}", "-D", f"settle={args.mf_settle!r}", "--quiet"], work)
    s = last_snapshot(state)
    n = len(s["id"])
    r, rho, kn, e = 0.2e-3, 1200.0, 2e4, 0.85
    mass = 4 / 3 * math.pi * r**3 * rho
    dt = 6.6936e-8
    zeta = -math.log(e) / math.sqrt(math.pi**2 + math.log(e) ** 2)
    # Granule's linear law: c_n = 2 zeta sqrt(m* k_n); LAMMPS: c_n = m* gamma_n.
    gn = 2 * zeta * math.sqrt(kn / (mass / 2))   # particle pairs, m* = m/2
    gnw = 2 * zeta * math.sqrt(kn / mass)        # particle-wall, m* = m
    data = os.path.join(work, name + ".data")
    write_lammps_data(s, data, [(-0.0126, 0.0126), (-0.0126, 0.0126), (-0.5, 0.5)], 2)
    rows = []
    for model in ("linear", "walton_braun"):
        rows += granule_rows(args, work, "granule " + model,
                             ["run", os.path.join(BENCH, "mechanofusion_compare.lua"), "-D", f"state={state}",
                              "-D", f"steps={steps}", "-D", f"model={model}"])
    variables = dict(data=data, steps=steps, dt=dt, kn=kn, kt=kn * 2 / 7, gn=gn, gt=gn / 2, gnw=gnw,
                     gtw=gnw / 2, mu=0.4, muw=0.5, omega=2000 * 2 * math.pi / 60, mass=mass, skin=1e-4)
    lmp_vars = sum((["-var", k, str(v)] for k, v in variables.items()), [])
    if args.peers["lmp"]:
        # Two decks: the chamber as a rotating region (faithful: the baseline), and
        # as a zcylinder wall with a moving surface, LAMMPS's cheaper idiom, which
        # this LAMMPS computes wrongly (mechanofusion_2d_shear.lmp says how): run to
        # show it (its kinetic energy), left out of the ratios.
        for binary, build in lammps_builds(args):
            for deck, label in (("mechanofusion_2d.lmp", "lammps gran/hooke/history"),
                                ("mechanofusion_2d_shear.lmp", UNFAITHFUL + " zcylinder shear")):
                for procs in peer_procs(args):
                    out, _ = run(mpi_prefix(procs) + [binary, "-in", os.path.join(BENCH, deck), "-log", "none"]
                                 + lmp_vars, work)
                    rows.append(peer_row(label + build, procs, out))
    return f"2D Mechanofusion base case, {n} particles, dt = {dt:g} s, {steps} steps", os.path.basename(state), rows


def box3d(args, work):
    per_side, layers, gap = args.box_side, args.box_layers, args.box_gap
    r = 1e-3
    # gap 0: the touching lattice; a gap: the disordered packing it collapses
    # into, settled for longer (docs/performance.md).
    packed = gap > 0
    tag = f"_gap{gap:g}" if packed else ""
    # Settled for whole periods of the floor (z = A (1 - cos wt), granule.bench),
    # so that each program restarts with the floor at rest under a bed at rest;
    # the file name holds the box's size, gap and settling time, so a state
    # settled otherwise is never reused.
    settle = 0.2 if packed else 0.02
    hertz = args.box_model == "hertz_mindlin"
    young, poisson = 5e7, 0.25  # Pa; the bench box's soft glass (granule.bench), spheres and walls alike
    if hertz:
        tag += "_hertz"
    state = os.path.join(work, f"box_{per_side}x{per_side}x{layers}{tag}_settled{settle:g}s.h5")
    scene = os.path.join(BENCH, "box3d_compare.lua")
    amplitude = args.box_amplitude
    size = ["-D", f"per_side={per_side}", "-D", f"layers={layers}", "-D", f"gap={gap!r}",
            "-D", f"amplitude={amplitude!r}", "-D", f"model={args.box_model}"]
    if hertz:
        size += ["-D", f"young={young!r}", "-D", f"poisson={poisson!r}"]
    if not os.path.exists(state):
        print(f"settling the 3D box ({per_side * per_side * layers} spheres, {settle} s)...", flush=True)
        run([args.granule, "run", scene, "-D", f"save={state}", "-D", f"settle={settle}", "--quiet",
             "--threads", str(max(args.threads))] + size, work)
    s = last_snapshot(state)
    n = len(s["id"])
    rho, kn, e, mu = 2500.0, 1e4, 0.5, 0.5
    mass = 4 / 3 * math.pi * r**3 * rho
    dt, frequency = 1.5e-6, 50.0
    side = per_side * (2 * r + gap)
    zeta = -math.log(e) / math.sqrt(math.pi**2 + math.log(e) ** 2)
    gn = 2 * zeta * math.sqrt(kn / (mass / 2))
    gnw = 2 * zeta * math.sqrt(kn / mass)
    data = os.path.join(work, f"box_state{tag}.data")
    top = float(np.max(s["position"][:, 2])) + 10 * r
    write_lammps_data(s, data, [(-r, side + r), (-r, side + r), (-r, top)], 3)
    steps = max(args.steps // 20, 200) if args.steps else 1000
    rows = []
    rows += granule_rows(args, work, "granule " + args.box_model,
                         ["run", scene, "-D", f"state={state}", "-D", f"steps={steps}"] + size)
    if hertz:
        # Mindlin's S_t / S_n = 8 G* a / (2 E* a) = 4 G* / E* for one material:
        # Granule's tangential damping is the normal one times its square root.
        shear = young / (2 * (1 + poisson))
        ratio = 4 * (shear / (2 * (2 - poisson))) / (young / (2 * (1 - poisson**2)))
        variables = dict(data=data, steps=steps, dt=dt, young=young, poisson=poisson, restitution=e,
                         xgt=math.sqrt(ratio), mu=mu, side=side, amplitude=amplitude, period=1 / frequency,
                         mass=mass, skin=0.5 * r)
        deck, label = "box_3d_hertz.lmp", "lammps granular hertz/material"
    else:
        variables = dict(data=data, steps=steps, dt=dt, kn=kn, kt=kn * 2 / 7, gn=gn, gt=gn / 2, gnw=gnw,
                         gtw=gnw / 2, mu=mu, side=side, amplitude=amplitude, period=1 / frequency, mass=mass,
                         skin=0.5 * r)
        deck, label = "box_3d.lmp", "lammps gran/hooke/history"
    lmp_vars = sum((["-var", k, str(v)] for k, v in variables.items()), [])
    if args.peers["lmp"]:
        for binary, build in lammps_builds(args):
            for procs in peer_procs(args):
                out, _ = run(mpi_prefix(procs) + [binary, "-in", os.path.join(BENCH, deck), "-log", "none"]
                             + lmp_vars, work)
                rows.append(peer_row(label + build, procs, out))
    if args.peers["liggghts"]:
        ldata = os.path.join(work, f"box_state_liggghts{tag}.data")
        write_lammps_data(s, ldata, [(-r, side + r), (-r, side + r), (-r, top)], 3, density=rho, types=2)
        mesh = os.path.join(work, "floor.stl")
        with open(mesh, "w") as f:  # the floor, z = 0, a little larger than the box
            a, b = -r, side + r
            f.write("solid floor\n")
            for tri in (((a, a), (b, a), (b, b)), ((a, a), (b, b), (a, b))):
                f.write(" facet normal 0 0 1\n  outer loop\n")
                for x, y in tri:
                    f.write(f"   vertex {x:.17g} {y:.17g} 0\n")
                f.write("  endloop\n endfacet\n")
            f.write("endsolid floor\n")
        common = dict(data=ldata, mesh=mesh, steps=steps, dt=dt, mu=mu, side=side, amplitude=amplitude,
                      phase=math.pi, period=1 / frequency, skin=0.5 * r)
        if hertz:
            lvars = dict(common, young=young, poisson=poisson, restitution=e)
            ldeck, llabel = "box_3d_hertz.liggghts", "liggghts hertz"
        else:
            gpp, gpw = gn, 2 * zeta * math.sqrt(kn / mass)  # per unit effective mass (m/2, m)
            lvars = dict(common, kn=kn, kt=kn * 2 / 7, gpp=gpp, gpw=gpw, gtpp=gpp / 2, gtpw=gpw / 2)
            ldeck, llabel = "box_3d.liggghts", "liggghts hooke/stiffness"
        largs = sum((["-var", k, str(v)] for k, v in lvars.items()), [])
        for procs in peer_procs(args):
            out, _ = run(mpi_prefix(procs) + ["liggghts", "-in", os.path.join(BENCH, ldeck),
                                              "-log", "none"] + largs, work)
            rows.append(peer_row(llabel, procs, out))
    kind = "disordered packing" if packed else "touching lattice"
    return (f"3D dense shaken box ({kind}, {args.box_model}, floor {amplitude * 1e3:g} mm at {frequency:g} Hz), {n} spheres, "
            f"dt = {dt:g} s, {steps} steps"), os.path.basename(state), rows


# A peer's deck that runs but does not compute the scene's physics (its file says
# why): reported with its kinetic energy, never a baseline.
UNFAITHFUL = "(unfaithful) lammps"


def ratios_to_lammps(rows):
    """Each row's particle-steps/s over LAMMPS's fastest faithful deck on the same cores, in one round."""
    lammps = {}
    for r in rows:
        if r["program"].startswith("lammps"):
            lammps[r["threads"]] = max(lammps.get(r["threads"], 0.0), r["particle_steps_per_s"])
    return {(r["program"], r["threads"]): r["particle_steps_per_s"] / lammps[r["threads"]]
            for r in rows if r["threads"] in lammps}


def report(title, rows, round_ratios=()):
    print(f"\n{title}")
    paired = len(round_ratios) > 1
    print(f"{'program':40s} {'cores':>5s} {'particle-steps/s':>17s} {'pair contacts':>13s} {'KE [J]':>9s} {'vs LAMMPS':>10s}"
          + (f" {'per round: median (min-max)':>28s}" if paired else ""))
    best = ratios_to_lammps(rows)
    for row in rows:
        key = (row["program"], row["threads"])
        ratio = f"{best[key]:10.2f}" if key in best else f"{'-':>10s}"
        line = (f"{row['program']:40s} {row['threads']:5d} {row['particle_steps_per_s']:17.3g} "
                f"{row['pair_contacts']:13.1f} {row.get('kinetic_energy', float('nan')):9.3g} {ratio}")
        if paired:
            r = sorted(rr[key] for rr in round_ratios if key in rr)
            if r:
                line += f" {statistics.median(r):11.2f} ({r[0]:.2f}-{r[-1]:.2f})"
        print(line)


# The CSV file's columns, one row per run (docs/performance.md describes them).
CSV_COLUMNS = [
    "date", "host", "commit", "case", "state", "round", "program", "threads", "steps", "particles",
    "pair_contacts", "mean_contacts", "wall_s", "particle_steps_per_s",
    "neighbour_s", "contacts_s", "walls_s", "sums_s", "diagnostics_s", "integrate_s", "hooks_s", "pair_wait_s",
    "list_rebuilds", "thread_rebalances",
]


def open_csv(path):
    """The CSV writer for `path`: appended to when it already has these columns, else started."""
    if os.path.exists(path) and os.path.getsize(path) > 0:
        with open(path, newline="") as f:
            header = next(csv.reader(f), [])
        if header != CSV_COLUMNS:
            sys.exit(f"{path}: its columns are not compare.py's ({','.join(header[:4])}...): "
                     "give another file with --csv")
        f = open(path, "a", newline="")
        return f, csv.DictWriter(f, CSV_COLUMNS, extrasaction="ignore")
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    f = open(path, "w", newline="")
    w = csv.DictWriter(f, CSV_COLUMNS, extrasaction="ignore")
    w.writeheader()
    return f, w


def git_commit(path):
    """The commit of the git tree holding `path` (+dirty when it has uncommitted
    changes), or '' outside one: for a binary in TREE/build, what it was built from."""
    where = os.path.dirname(path)
    try:
        commit = subprocess.run(["git", "-C", where, "rev-parse", "--short", "HEAD"], capture_output=True,
                                text=True, check=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", where, "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True, check=True).stdout.strip()
        return commit + ("+dirty" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return ""


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--case", default="mechanofusion2d", choices=["mechanofusion2d", "box3d", "all"])
    ap.add_argument("--steps", type=int, default=None,
                    help="2D: steps of the timed window (default 200,000: the flow is chaotic, and over "
                         "20,000 the two programs' trajectories part and their mean contacts differ by up "
                         "to 10 %%); 3D box: a twentieth of it (default 1000, at least 200)")
    ap.add_argument("--threads", default="1,2", help="core counts to time (threads / MPI ranks)")
    ap.add_argument("--work", default="bench_work")
    ap.add_argument("--csv", default=None, help="append one row per run here (default WORK/bench_results.csv)")
    ap.add_argument("--granule", default=GRANULE, help="the Granule binary (default build/granule)")
    ap.add_argument("--mf-particles", type=int, default=1500, help="2D: particles (Table 4.1: 1500)")
    ap.add_argument("--mf-settle", type=float, default=0.05, help="2D: settling time of the state, s")
    ap.add_argument("--box-side", type=int, default=50, help="3D box: spheres per side (50 -> 100,000 with 40 layers)")
    ap.add_argument("--box-layers", type=int, default=40)
    ap.add_argument("--box-gap", type=float, default=0.0,
                    help="3D box: gap between spheres on the starting lattice, m (0: touching; 1e-4: a "
                         "loose lattice that settles into a disordered packing)")
    ap.add_argument("--box-amplitude", type=float, default=0.1e-3, help="3D box: floor amplitude, m")
    ap.add_argument("--box-model", default="linear", choices=["linear", "hertz_mindlin"],
                    help="3D box: the contact law (hertz_mindlin: against LAMMPS's granular hertz/material)")
    ap.add_argument("--lammps-native", default=None,
                    help="also time this LAMMPS binary (Debian's LAMMPS source built for this CPU: "
                         "docs/performance.md says how); the ratios are to the fastest LAMMPS row")
    ap.add_argument("--repeat", type=int, default=1,
                    help="run every program this many times, alternating, and keep each one's best "
                         "(the machine is shared: the best run is the least disturbed)")
    args = ap.parse_args()
    try:
        args.threads = [int(t) for t in args.threads.split(",")]
    except ValueError:
        sys.exit(f"--threads: comma-separated whole numbers, got '{args.threads}'")
    if not args.threads or min(args.threads) < 1:
        sys.exit(f"--threads: each at least 1, got '{','.join(map(str, args.threads))}'")
    for name in ("steps", "repeat", "mf_particles", "box_side", "box_layers"):
        value = getattr(args, name)
        if value is not None and value < 1:
            sys.exit(f"--{name.replace('_', '-')}: at least 1, got {value}")
    if not (args.mf_settle > 0 and math.isfinite(args.mf_settle)):
        sys.exit(f"--mf-settle: a positive time in s, got {args.mf_settle}")
    if not (os.path.isfile(args.granule) and os.access(args.granule, os.X_OK)):
        sys.exit(f"{args.granule}: no Granule binary there (build it: cmake --build build), or give --granule")
    args.granule = os.path.abspath(args.granule)
    if args.lammps_native:
        if not (os.path.isfile(args.lammps_native) and os.access(args.lammps_native, os.X_OK)):
            sys.exit(f"--lammps-native: no executable at {args.lammps_native}")
        args.lammps_native = os.path.abspath(args.lammps_native)
    args.peers = peers_available(args.threads)
    missing = []
    if not args.peers["lmp"]:
        missing.append("LAMMPS (lmp: apt-get install lammps)")
    if args.case != "mechanofusion2d" and not args.peers["liggghts"]:
        missing.append("LIGGGHTS (liggghts)")
    if not args.peers["mpirun"]:
        missing.append("mpirun, so the peers run on one rank only")
    if missing:
        print("not found: " + "; ".join(missing) + ". Timing Granule without them.")
    os.makedirs(args.work, exist_ok=True)
    work = os.path.abspath(args.work)
    csv_path = args.csv or os.path.join(work, "bench_results.csv")
    csv_file, writer = open_csv(csv_path)
    print(f"machine: {platform.node()}, {os.cpu_count()} cores, {platform.processor() or platform.machine()}, "
          f"load average {os.getloadavg()[0]:.2f}")
    stamp = dict(date=datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"),
                 host=platform.node(), commit=git_commit(args.granule))
    cases = ["mechanofusion2d", "box3d"] if args.case == "all" else [args.case]
    for case in cases:
        best, round_ratios = {}, []
        for k in range(max(1, args.repeat)):
            title, state, rows = globals()[case](args, work)
            round_ratios.append(ratios_to_lammps(rows))  # the programs ran back to back
            for row in rows:
                writer.writerow({**stamp, "case": case, "state": state, "round": k + 1, **row})
                key = (row["program"], row["threads"])
                if key not in best or row["particle_steps_per_s"] > best[key]["particle_steps_per_s"]:
                    best[key] = row
            csv_file.flush()
        if args.repeat > 1:
            title += (f", best of {args.repeat} alternating runs; vs LAMMPS: best against best, and "
                      f"the ratio within each round")
        report(title, list(best.values()), round_ratios)
        if not any(r["program"].startswith("lammps") for r in best.values()):
            print("(no LAMMPS rows: the ratios need lmp)")
    csv_file.close()
    print(f"\none row per run in {csv_path}")


if __name__ == "__main__":
    main()
