#!/usr/bin/python3
"""Map the preparation protocol (dissertation 7.3): coordination number and diameter against its choices.

usage: /usr/bin/python3 tools/agglomerate_preparation.py [--dimension 2] [--work prep] [--only NAME,...]
           [--csv docs/data/agglomerate_preparation_2d.csv] [--figure docs/figures/agglomerate_preparation_2d.png]
           [--granule build/granule]

Runs scenarios/agglomerate_prepare.lua once per variant below (217 primaries,
seed 1, Gamma = 1 J/m^2 unless the variant says otherwise; outputs that exist
in WORK are reused), then writes one CSV row per variant (the /results of the
preparation: bonds, coordination, diameter, packing fraction, compressive and
tensile contacts, stage durations, CPU time) and a figure of coordination
number against diameter, with the dissertation's 216 bonds at 87 um marked.
Every variant changes one choice of the "dense" protocol (7.3 read literally)
or of the "sticky" one (friction and adhesion on while the field compacts).
"""

import argparse
import csv
import os
import subprocess
import sys
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

TOOLS = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(TOOLS)
sys.path.insert(0, TOOLS)
import granule_h5 as g  # noqa: E402

# name: (what it changes, -D settings)
VARIANTS = [
    ("dense", "7.3 literally: mu = Gamma = 0 while compacting, both on at rest", {}),
    ("dense_field_5e4", "field 5e4 m/s^2 (default 5e5)", {"field_strength": 5e4}),
    ("dense_field_5e6", "field 5e6 m/s^2", {"field_strength": 5e6}),
    ("dense_damping_1e5", "damping 1e5 1/s (default 1e6)", {"damping_rate": 1e5}),
    ("dense_damping_1e7", "damping 1e7 1/s", {"damping_rate": 1e7}),
    ("dense_generation_150", "generated in a 150 um circle (default 100)", {"generation_diameter": 150e-6}),
    ("dense_friction_first", "stage 2: mu on, to rest, then Gamma", {"switch_order": "friction_first"}),
    ("dense_adhesion_first", "stage 2: Gamma on, to rest, then mu", {"switch_order": "adhesion_first"}),
    ("dense_gamma_5_steps", "stage 2: Gamma raised in 5 steps", {"surface_energy_steps": 5}),
    ("dense_field_1_step", "stage 3: field removed at once", {"field_decrements": 1}),
    ("dense_field_ramp_1us", "stage 3: 10 decrements 1 us apart (a ramp)", {"decrement_duration": 1e-6}),
    ("friction_compaction", "mu = 0.25 while compacting, Gamma = 0", {"compaction_friction": 0.25}),
    ("adhesion_compaction", "Gamma = 1 while compacting, mu = 0", {"compaction_surface_energy": 1.0}),
    ("sticky", "mu = 0.25 and Gamma = 1 while compacting", {"protocol": "sticky"}),
    ("sticky_field_5e4", "sticky, field 5e4 m/s^2", {"protocol": "sticky", "field_strength": 5e4}),
    ("sticky_field_5e6", "sticky, field 5e6 m/s^2", {"protocol": "sticky", "field_strength": 5e6}),
    ("sticky_damping_1e5", "sticky, damping 1e5 1/s", {"protocol": "sticky", "damping_rate": 1e5}),
    ("sticky_damping_1e7", "sticky, damping 1e7 1/s", {"protocol": "sticky", "damping_rate": 1e7}),
    ("sticky_generation_150", "sticky, generated in a 150 um circle", {"protocol": "sticky",
                                                                       "generation_diameter": 150e-6}),
    ("sticky_gamma_2", "sticky, Gamma = 2 J/m^2", {"protocol": "sticky", "surface_energy": 2.0}),
]
COLUMNS = ["name", "change", "bonds", "coordination", "diameter_um", "packing_fraction", "compressive_contacts",
           "tensile_contacts", "rms_speed", "quiet_bonds_lost", "stages_by_criterion", "stage1_us", "stage2_us",
           "stage3_us", "cpu_s"]


def complete(path):
    """An output to reuse: its run got to writing /results (an interrupted one did not)."""
    if not os.path.exists(path):
        return False
    try:
        with g.open_run(path) as f:
            return "results" in f and len(f["results"].attrs) > 0
    except Exception:  # a file cut short is not HDF5 at all
        return False


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dimension", type=int, default=2, choices=(2, 3))
    parser.add_argument("--work", default="prep")
    parser.add_argument("--only", help="comma-separated variant names")
    parser.add_argument("--csv", help="default WORK/agglomerate_preparation_<d>d.csv")
    parser.add_argument("--figure", help="default WORK/agglomerate_preparation_<d>d.png")
    parser.add_argument("--granule", default=os.path.join(ROOT, "build", "granule"))
    args = parser.parse_args(argv)
    d = args.dimension
    work = os.path.abspath(args.work)
    os.makedirs(work, exist_ok=True)
    wanted = set(args.only.split(",")) if args.only else None
    rows = []
    for name, change, settings in VARIANTS:
        if wanted and name not in wanted:
            continue
        path = os.path.join(work, f"prep_{d}d_{name}.h5")
        cpu = float("nan")
        if not complete(path):
            command = [args.granule, "run", "scenarios/agglomerate_prepare.lua", "-D", f"dimension={d}"]
            for k, v in settings.items():
                command += ["-D", f"{k}={v:g}" if isinstance(v, float) else f"{k}={v}"]
            start = time.process_time()
            done = subprocess.run(command + ["-o", path, "--quiet"], cwd=ROOT, capture_output=True, text=True)
            if done.returncode != 0:
                raise SystemExit(f"error: {' '.join(command)} failed:\n{done.stdout}{done.stderr}")
            sys.stdout.write(f"{name}: {done.stdout}")
            cpu = time.process_time() - start
            for part in done.stdout.split():
                if part.startswith("cpu_time_s="):
                    cpu = float(part.split("=")[1])
        with g.open_run(path) as f:
            r = {k: float(v) for k, v in f["results"].attrs.items()}
        rows.append({"name": name, "change": change, "bonds": int(r["bonds"]), "coordination": r["coordination"],
                     "diameter_um": r["diameter"] * 1e6, "packing_fraction": r["packing_fraction"],
                     "compressive_contacts": int(r["compressive_contacts"]),
                     "tensile_contacts": int(r["tensile_contacts"]), "rms_speed": r["rms_speed"],
                     "quiet_bonds_lost": int(r["quiet_bonds_lost"]), "stages_by_criterion": int(r["stages_by_criterion"]),
                     "stage1_us": r["stage1_duration"] * 1e6, "stage2_us": r["stage2_duration"] * 1e6,
                     "stage3_us": r["stage3_duration"] * 1e6, "cpu_s": cpu})
    table = os.path.abspath(args.csv or os.path.join(work, f"agglomerate_preparation_{d}d.csv"))
    os.makedirs(os.path.dirname(table), exist_ok=True)
    with open(table, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS)
        w.writeheader()
        for row in rows:
            w.writerow({k: (f"{row[k]:.4g}" if isinstance(row[k], float) else row[k]) for k in COLUMNS})
    figure = os.path.abspath(args.figure or os.path.join(work, f"agglomerate_preparation_{d}d.png"))
    plot(table, figure, d)
    print(f"{'variant':24} {'bonds':>5} {'Z':>5} {'D_um':>6} {'phi':>5} {'comp/tens':>9} {'stages':>6}")
    for r in rows:
        print(f"{r['name']:24} {r['bonds']:5d} {r['coordination']:5.2f} {r['diameter_um']:6.1f} "
              f"{r['packing_fraction']:5.3f} {r['compressive_contacts']:4d}/{r['tensile_contacts']:<4d} "
              f"{r['stages_by_criterion']:6d}")
    print(table)
    print(figure)
    return 0


def plot(table, figure, d):
    """Coordination number against diameter, one point per variant, from the CSV."""
    with open(table) as f:
        rows = list(csv.DictReader(f))
    fig, ax = plt.subplots(figsize=(7.5, 5))
    for r in rows:
        sticky = not r["name"].startswith("dense")
        ax.plot(float(r["diameter_um"]), float(r["coordination"]), "s" if sticky else "o",
                color="tab:red" if sticky else "tab:blue")
        ax.annotate(r["name"], (float(r["diameter_um"]), float(r["coordination"])), fontsize=6,
                    xytext=(3, 2), textcoords="offset points")
    if d == 2:
        ax.plot([87], [2 * 216 / 217], "k*", markersize=12)
        ax.annotate("dissertation: 216 bonds, 87 $\\mu$m", (87, 2 * 216 / 217), fontsize=7, xytext=(5, -10),
                    textcoords="offset points")
    ax.set_xlabel("agglomerate diameter [$\\mu$m]")
    ax.set_ylabel("coordination number 2 bonds / primaries")
    ax.set_title(f"preparation choices, {d}D, 217 primaries, seed 1 (circles: dense family, squares: other)",
                 fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(figure, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    sys.exit(main())
