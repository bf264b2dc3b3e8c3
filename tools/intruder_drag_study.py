#!/usr/bin/python3
"""The intruder-drag study (scenarios/intruder_drag.lua): drag against depth and speed.

Reads the summaries of two `granule sweep` runs of the scene, one over the
intruder's height (so its depth below the settled surface) and seeds, one over
the drag speed and seeds, and writes
- a table, one row per case (depth, speed, seed, drag and its standard error,
  bulk density, k = F / (rho_bulk g h D^2)), as CSV;
- a figure: drag against depth with the least-squares line through the origin
  F = k rho g h D^2 (k from all the depth cases), and drag against speed;
and prints the fitted k with its standard error and the speed cases' k.

    mpirun --allow-run-as-root -np 2 build/granule sweep scenarios/intruder_drag.lua \\
        -D height=6e-3,9e-3,12e-3,15e-3,18e-3 -D seed=1,2 -o depth -q
    mpirun --allow-run-as-root -np 2 build/granule sweep scenarios/intruder_drag.lua \\
        -D speed=0.025,0.1 -D seed=1,2 -o speed -q
    /usr/bin/python3 tools/intruder_drag_study.py depth/intruder_drag.sweep.csv \\
        speed/intruder_drag.sweep.csv --csv docs/data/intruder_drag.csv \\
        --figure docs/figures/intruder_drag.png
"""
import argparse
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

G = 9.81


def read(path):
    with open(path, newline="") as f:
        rows = [r for r in csv.DictReader(f)]
    bad = [r for r in rows if r.get("status") not in ("ok", "reused")]
    if bad:
        sys.exit(f"{path}: {len(bad)} case(s) did not finish ({', '.join(r.get('status', '?') for r in bad)})")
    return rows


def number(row, key, default=None):
    value = row.get(key, "")
    if value == "":
        if default is None:
            sys.exit(f"a case has no '{key}' (columns: {', '.join(row)})")
        return default
    return float(value)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("depth_csv", help="summary CSV of the sweep over height")
    parser.add_argument("speed_csv", help="summary CSV of the sweep over speed")
    parser.add_argument("--csv", required=True, help="table to write")
    parser.add_argument("--figure", required=True, help="PNG to write")
    parser.add_argument("--intruder-radius", type=float, default=3e-3, help="m (the scene's default)")
    parser.add_argument("--speed", type=float, default=0.05, help="m/s: the depth sweep's speed (the default)")
    parser.add_argument("--height", type=float, default=12e-3, help="m: the speed sweep's height (the default)")
    a = parser.parse_args()
    diameter = 2 * a.intruder_radius
    cases = []
    for path, sweep in ((a.depth_csv, "depth"), (a.speed_csv, "speed")):
        for r in read(path):
            cases.append({
                "sweep": sweep,
                "height_m": number(r, "height", a.height),
                "speed_m_per_s": number(r, "speed", a.speed),
                "seed": int(number(r, "seed", 1)),
                "depth_m": number(r, "depth"),
                "drag_N": number(r, "drag"),
                "drag_standard_error_N": number(r, "drag_standard_error"),
                "bulk_density_kg_per_m3": number(r, "bulk_density"),
                "k": number(r, "k"),
            })
    with open(a.csv, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(cases[0]))
        w.writeheader()
        for c in cases:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in c.items()})
    depth_cases = [c for c in cases if c["sweep"] == "depth"]
    # Least squares through the origin, F = k x with x = rho g h D^2, weighted by 1/se^2.
    xs = [c["bulk_density_kg_per_m3"] * G * c["depth_m"] * diameter ** 2 for c in depth_cases]
    ws = [1 / max(c["drag_standard_error_N"], 1e-12) ** 2 for c in depth_cases]
    sxx = sum(w * x * x for w, x in zip(ws, xs))
    k = sum(w * x * c["drag_N"] for w, x, c in zip(ws, xs, depth_cases)) / sxx
    # The fit's error from the scatter about it (a reduced chi-square scaling).
    residual = sum(w * (c["drag_N"] - k * x) ** 2 for w, x, c in zip(ws, xs, depth_cases))
    dof = max(len(depth_cases) - 1, 1)
    k_se = math.sqrt(residual / dof / sxx)
    print(f"k = {k:.3g} +- {k_se:.2g} (fit through the origin of {len(depth_cases)} depth cases; "
          f"reduced chi-square {residual / dof:.2g})")
    for c in sorted((c for c in cases if c["sweep"] == "speed"), key=lambda c: (c["speed_m_per_s"], c["seed"])):
        print(f"speed {c['speed_m_per_s']:g} m/s seed {c['seed']}: depth {c['depth_m']:.4g} m, "
              f"drag {c['drag_N']:.4g} +- {c['drag_standard_error_N']:.2g} N, k = {c['k']:.3g}")

    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
    for seed, marker in ((1, "o"), (2, "s")):
        sel = [c for c in depth_cases if c["seed"] == seed]
        left.errorbar([1e3 * c["depth_m"] for c in sel], [1e3 * c["drag_N"] for c in sel],
                      yerr=[1e3 * c["drag_standard_error_N"] for c in sel], fmt=marker, capsize=3,
                      label=f"seed {seed}")
    top = max(c["depth_m"] for c in depth_cases) * 1.1
    rho = sum(c["bulk_density_kg_per_m3"] for c in depth_cases) / len(depth_cases)
    left.plot([0, 1e3 * top], [0, 1e3 * k * rho * G * top * diameter ** 2], "k--",
              label=f"F = k rho g h D^2, k = {k:.3g}")
    left.set_xlabel("depth of the intruder's centre h [mm]")
    left.set_ylabel("drag [mN]")
    left.set_title(f"drag against depth ({a.speed:g} m/s, D = {1e3 * diameter:g} mm)")
    left.legend()
    speeds = [c for c in cases if c["sweep"] == "speed"] + [
        c for c in depth_cases if abs(c["height_m"] - a.height) < 1e-12]
    for seed, marker in ((1, "o"), (2, "s")):
        sel = sorted((c for c in speeds if c["seed"] == seed), key=lambda c: c["speed_m_per_s"])
        right.errorbar([c["speed_m_per_s"] for c in sel], [c["k"] for c in sel],
                       yerr=[c["k"] * c["drag_standard_error_N"] / c["drag_N"] for c in sel], fmt=marker,
                       capsize=3, label=f"seed {seed}")
    right.axhline(k, color="k", ls="--", label="k of the depth fit")
    right.set_xscale("log")
    right.set_xlabel("drag speed [m/s]")
    right.set_ylabel("k = F / (rho g h D^2)")
    right.set_title(f"k against speed (centre {1e3 * a.height:g} mm above the floor)")
    right.legend()
    fig.tight_layout()
    fig.savefig(a.figure, dpi=110)
    print(f"wrote {a.csv} and {a.figure}")


if __name__ == "__main__":
    main()
