#!/usr/bin/python3
"""The speed exponent of the force on the inner piece from the loading study's
case files, over the whole measuring window and from a later start: how much
the fall from the random fill, still under way after a short settle, lowers
the exponent (docs/mechanofusion.md, "The force on the inner piece").

For each loading and seed the force is the sample-weighted mean of the
window series /diagnostics/inner_piece_force/normal_force, over every window
and over the windows from --from (s) on; the exponent is the least-squares
slope of log force against log speed over the speeds present (1000, 2000,
4000 rpm), and the table gives its mean over the seeds +- the standard error.

usage: /usr/bin/python3 tools/mechanofusion_window_exponents.py WORK/loading [--from 0.5]
       [--csv docs/data/mechanofusion_window_exponents.csv]
"""
import argparse
import collections
import csv
import glob
import os
import re
import sys

import h5py
import numpy as np


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("directory", help="the loading study's sweep directory (WORK/loading)")
    ap.add_argument("--from", dest="start", type=float, default=0.5, help="the later start, s (default 0.5)")
    ap.add_argument("--csv", default=None, help="also write the table here")
    args = ap.parse_args()
    means = collections.defaultdict(dict)  # (particles, seed) -> rpm -> (whole, late)
    pattern = re.compile(r"seed=(\d+)_rpm=(\d+)_particles=(\d+)\.h5$")
    for path in sorted(glob.glob(os.path.join(args.directory, "*.h5"))):
        m = pattern.search(path)
        if not m:
            continue
        seed, rpm, particles = map(int, m.groups())
        try:
            with h5py.File(path, "r") as f:
                g = f["diagnostics/inner_piece_force"]
                t, force, weight = g["time"][:], g["normal_force"][:], g["samples"][:]
        except (OSError, KeyError) as e:
            print(f"{path}: skipped ({e})", file=sys.stderr)
            continue
        late = t >= args.start
        if not late.any() or weight.sum() <= 0:
            print(f"{path}: no window from {args.start} s on; skipped", file=sys.stderr)
            continue
        means[(particles, seed)][rpm] = (np.average(force, weights=weight),
                                          np.average(force[late], weights=weight[late]))
    if not means:
        sys.exit(f"no loading-study case files under {args.directory}")
    rows = []
    for particles in sorted({p for p, _ in means}):
        whole, late, ratio = [], [], collections.defaultdict(list)
        for (p, seed), by_rpm in sorted(means.items()):
            if p != particles or len(by_rpm) < 2:
                continue
            speeds = sorted(by_rpm)
            x = np.log(speeds)
            whole.append(np.polyfit(x, np.log([by_rpm[r][0] for r in speeds]), 1)[0])
            late.append(np.polyfit(x, np.log([by_rpm[r][1] for r in speeds]), 1)[0])
            for r in speeds:
                ratio[r].append(by_rpm[r][1] / by_rpm[r][0])
        if not whole:
            continue

        def se(v):
            return float(np.std(v, ddof=1) / np.sqrt(len(v))) if len(v) > 1 else float("nan")

        rows.append({"particles": particles, "seeds": len(whole),
                     "exponent_whole": f"{np.mean(whole):.4f}", "exponent_whole_se": f"{se(whole):.4f}",
                     "exponent_from": f"{np.mean(late):.4f}", "exponent_from_se": f"{se(late):.4f}",
                     "from_s": args.start,
                     **{f"late_over_whole_rpm{r}": f"{np.mean(v):.4f}" for r, v in sorted(ratio.items())}})
    print(f"| particles | seeds | exponent, whole window | exponent from {args.start} s | late / whole mean by rpm |")
    print("|---|---|---|---|---|")
    for r in rows:
        by = ", ".join(f"{k[len('late_over_whole_rpm'):]}: {v}" for k, v in r.items() if k.startswith("late_over"))
        print(f"| {r['particles']} | {r['seeds']} | {r['exponent_whole']} +- {r['exponent_whole_se']} | "
              f"{r['exponent_from']} +- {r['exponent_from_se']} | {by} |")
    if args.csv:
        columns = sorted({c for r in rows for c in r}, key=lambda c: (c != "particles", c))
        with open(args.csv, "w", newline="") as f:
            w = csv.DictWriter(f, columns)
            w.writeheader()
            w.writerows(rows)
        print(f"{args.csv}: {len(rows)} rows")


if __name__ == "__main__":
    main()
