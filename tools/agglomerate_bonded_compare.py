#!/usr/bin/python3
"""Damage and debris against impact velocity: the bonded agglomerate beside the JKR one (wall impact, 7.6).

usage: /usr/bin/python3 tools/agglomerate_bonded_compare.py
           --jkr docs/data/agglomerate_wall_2d.csv --bonded docs/data/agglomerate_bonded_wall_2d.csv
           [--jkr docs/data/agglomerate_wall_3d.csv --bonded docs/data/agglomerate_bonded_wall_3d.csv]
           [--variant 1:LABEL:docs/data/agglomerate_bonded_strong_wall_2d.csv]
           -o docs/figures/agglomerate_bonded_wall.png

Reads the summary tables of tools/agglomerate_study.py (means and standard errors over the
seeds), one column of panels per (--jkr, --bonded) pair in the order given. Damage: broken
over initial bonds (JKR: contacts lost; bonded: parallel bonds broken). Debris: mass in fragments
below 2.5 % of the agglomerate's, fragments being the clusters of the initial bonds that survive
(JKR: the surviving-bond graph, debris_ratio_bonds; bonded: the intact parallel bonds), and for
JKR also of the contact graph (7.4, dashed). --variant COLUMN:LABEL:CSV adds another bonded
table to panel column COLUMN (1 = the first pair).
"""

import argparse
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_summary(path):
    with open(path) as f:
        rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]
    if not rows:
        sys.exit(f"{path}: no rows")
    return sorted(rows, key=lambda r: r["velocity"])


def bars(ax, rows, key, label, style, color):
    ax.errorbar([r["velocity"] for r in rows], [r[f"{key}_mean"] for r in rows],
                yerr=[r[f"{key}_se"] for r in rows], fmt=style, color=color, capsize=3, label=label)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--jkr", action="append", required=True, help="summary CSV of the JKR wall impacts")
    parser.add_argument("--bonded", action="append", required=True, help="summary CSV of the bonded ones")
    parser.add_argument("--variant", action="append", default=[], metavar="COLUMN:LABEL:CSV",
                        help="another bonded summary CSV for panel column COLUMN (repeatable)")
    parser.add_argument("--titles", help="comma-separated panel titles (default: 2D, 3D)")
    parser.add_argument("-o", "--output", required=True)
    args = parser.parse_args(argv)
    if len(args.jkr) != len(args.bonded):
        sys.exit("give as many --bonded tables as --jkr tables")
    titles = args.titles.split(",") if args.titles else ["2D", "3D"][: len(args.jkr)]
    columns = len(args.jkr)
    variants = []
    for v in args.variant:
        parts = v.split(":", 2)
        if len(parts) != 3 or not parts[0].isdigit() or not 1 <= int(parts[0]) <= len(args.jkr):
            sys.exit(f"--variant {v}: give COLUMN:LABEL:CSV with COLUMN in 1..{len(args.jkr)}")
        variants.append((int(parts[0]) - 1, parts[1], read_summary(parts[2])))
    fig, axes = plt.subplots(2, columns, figsize=(4.6 * columns, 6.4), squeeze=False, sharex="col")
    for c, (jkr_path, bonded_path) in enumerate(zip(args.jkr, args.bonded)):
        jkr, bonded = read_summary(jkr_path), read_summary(bonded_path)
        n_j, n_b = int(min(r["n"] for r in jkr)), int(min(r["n"] for r in bonded))
        top, bottom = axes[0][c], axes[1][c]
        bars(top, jkr, "damage_ratio", f"JKR, Gamma = 1 J/m^2 ({n_j} seeds)", "o-", "C0")
        bars(top, bonded, "damage_ratio", f"parallel bonds ({n_b} seeds)", "s-", "C3")
        bars(bottom, jkr, "debris_ratio_bonds", "JKR, surviving bonds", "o-", "C0")
        bars(bottom, jkr, "debris_ratio", "JKR, contact graph", "o--", "C0")
        bars(bottom, bonded, "debris_ratio", "parallel bonds, intact bonds", "s-", "C3")
        for k, (column, label, rows) in enumerate(variants):
            if column == c:
                n_v = int(min(r["n"] for r in rows))
                bars(top, rows, "damage_ratio", f"{label} ({n_v} seeds)", "^-", f"C{k + 4}")
                bars(bottom, rows, "debris_ratio", label, "^-", f"C{k + 4}")
        top.set_title(f"{titles[c] if c < len(titles) else ''} wall impact")
        top.set_ylabel("damage ratio")
        bottom.set_ylabel("debris ratio")
        bottom.set_xlabel("impact velocity [m/s]")
        for ax in (top, bottom):
            ax.set_xscale("log")
            ax.set_ylim(-0.03, 1.03)
            ax.grid(alpha=0.3)
            ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(args.output, dpi=100)
    print(args.output)
    return 0


if __name__ == "__main__":
    sys.exit(main())
