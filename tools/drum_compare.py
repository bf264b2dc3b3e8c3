#!/usr/bin/python3
"""The rotating drum with its shell as a triangle mesh against the analytic
cylinder (docs/mesh_walls.md, "A drum from a mesh"): reads the summary of

  build/granule sweep scenarios/drum_3d.lua -D seed=1,2,3 -D drum=analytic,mesh \
      -D flat_angle=20,0 -o DIR --threads 1

and writes, per (drum, flat_angle), the mean over the seeds and its standard
error (sample standard deviation / sqrt(seeds)) of the mean kinetic energy and
of the dynamic angle of repose, and each mesh case's ratio to the analytic
drum (its standard error from both, added in quadrature), to
docs/data/drum_mesh.csv; prints the same as a markdown table.

usage: /usr/bin/python3 tools/drum_compare.py DIR/drum_3d.sweep.csv [--out docs/data/drum_mesh.csv]
"""
import argparse
import csv
import math
import sys


def mean_se(values):
    n = len(values)
    m = sum(values) / n
    if n < 2:
        return m, float("nan")
    sd = math.sqrt(sum((v - m) ** 2 for v in values) / (n - 1))
    return m, sd / math.sqrt(n)


def ratio(a, b):
    (ma, sa), (mb, sb) = a, b
    r = ma / mb
    return r, r * math.hypot(sa / ma, sb / mb)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("summary")
    parser.add_argument("--out", default="docs/data/drum_mesh.csv")
    a = parser.parse_args()
    rows = [r for r in csv.DictReader(open(a.summary)) if r["status"] in ("ok", "reused")]
    if not rows:
        sys.exit(f"{a.summary}: no finished case")
    groups = {}
    for r in rows:
        # The analytic drum ignores flat_angle: its cases of both values are one group
        # (they must be identical: a check of the runs' reproducibility).
        key = ("analytic", "-") if r["drum"] == "analytic" else (r["drum"], r["flat_angle"])
        groups.setdefault(key, {}).setdefault(r["seed"], []).append(r)
    for key, seeds in groups.items():
        for seed, cases in seeds.items():
            values = {(c["mean_kinetic_energy"], c["repose_angle"]) for c in cases}
            if len(values) > 1:
                sys.exit(f"{key} seed {seed}: runs that should be identical differ: {values}")
    stats = {}
    for key, seeds in groups.items():
        firsts = [cases[0] for cases in seeds.values()]
        stats[key] = {
            "seeds": len(firsts),
            "ke": mean_se([float(c["mean_kinetic_energy"]) for c in firsts]),
            "angle": mean_se([float(c["repose_angle"]) for c in firsts]),
        }
    if ("analytic", "-") not in stats:
        sys.exit("no analytic case to compare with")
    ref = stats[("analytic", "-")]
    with open(a.out, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["drum", "flat_angle_deg", "seeds", "mean_kinetic_energy_j", "mean_kinetic_energy_se_j",
                    "repose_angle_deg", "repose_angle_se_deg", "kinetic_energy_ratio", "kinetic_energy_ratio_se",
                    "repose_angle_ratio", "repose_angle_ratio_se"])
        print("| drum | flat_angle | seeds | mean kinetic energy [J] | angle of repose [deg] "
              "| KE / analytic | angle / analytic |")
        print("|---|---|---|---|---|---|---|")
        for key in sorted(stats, key=lambda k: (k[0] != "analytic", k)):
            s = stats[key]
            ke_r, an_r = ratio(s["ke"], ref["ke"]), ratio(s["angle"], ref["angle"])
            if s is ref:  # the reference itself: no uncertainty of a ratio to itself
                ke_r = an_r = (1.0, 0.0)
            w.writerow([key[0], key[1], s["seeds"], f"{s['ke'][0]:.6g}", f"{s['ke'][1]:.3g}",
                        f"{s['angle'][0]:.4g}", f"{s['angle'][1]:.3g}", f"{ke_r[0]:.4f}", f"{ke_r[1]:.4f}",
                        f"{an_r[0]:.4f}", f"{an_r[1]:.4f}"])
            print(f"| {key[0]} | {key[1]} | {s['seeds']} | {s['ke'][0]:.3e} +- {s['ke'][1]:.1e} "
                  f"| {s['angle'][0]:.1f} +- {s['angle'][1]:.1f} | {ke_r[0]:.3f} +- {ke_r[1]:.3f} "
                  f"| {an_r[0]:.3f} +- {an_r[1]:.3f} |")
    print(f"wrote {a.out}", file=sys.stderr)


if __name__ == "__main__":
    main()
