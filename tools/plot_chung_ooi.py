#!/usr/bin/python3
"""Draws Chung and Ooi's Test 4 (an oblique impact on a plane) as
scenarios/chung_ooi.lua writes it (<out>_test4.csv): the tangential
restitution, the spin after and the contact patch's rebound angle against the
incidence angle, one line per law, the gross-sliding closed forms as dashes.

    /usr/bin/python3 tools/plot_chung_ooi.py chung_ooi_test4.csv [more.csv ...] [-o figure.png]
"""
import argparse
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

PANELS = [
    ("tangential_restitution", "tangential_restitution_closed", "e_t = v_t' / v_t"),
    ("spin_rad_s", "spin_closed_rad_s", "spin after [rad/s]"),
    ("rebound_angle_deg", None, "patch rebound angle [deg]"),
]


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows or "angle_deg" not in rows[0]:
        sys.exit(f"{path}: not a Test 4 table of scenarios/chung_ooi.lua (no angle_deg column)")
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("tables", nargs="+", help="<out>_test4.csv files")
    parser.add_argument("-o", "--output", default=None, help="figure file (default: the first table's name, .png)")
    args = parser.parse_args()
    curves = {}
    for path in args.tables:
        for row in read(path):
            rescaled = ", shrink_rescale" if row.get("shrink_rescale") == "1" else ""
            label = f"{row['model']}{rescaled}, n = {row['steps_per_contact']}, mu = {row['friction']}"
            curves.setdefault(label, []).append(row)
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5))
    for (column, closed, title), ax in zip(PANELS, axes):
        for label, rows in curves.items():
            rows = sorted(rows, key=lambda r: float(r["angle_deg"]))
            angles = [float(r["angle_deg"]) for r in rows]
            ax.plot(angles, [float(r[column]) for r in rows], "o-", ms=3, label=label)
            if closed:
                sliding = [(float(r["angle_deg"]), float(r[closed])) for r in rows if r[closed]]
                if sliding:
                    ax.plot(*zip(*sliding), "k--", lw=1)
        ax.set_xlabel("incidence angle from the normal [deg]")
        ax.set_title(title)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8, loc="lower right")
    axes[1].text(0.98, 0.02, "dashed: gross sliding, closed form", transform=axes[1].transAxes,
                 ha="right", va="bottom", fontsize=8)
    fig.suptitle("Chung and Ooi (2011), Test 4: aluminium oxide sphere onto a plane")
    fig.tight_layout()
    out = args.output or args.tables[0].rsplit(".", 1)[0] + ".png"
    fig.savefig(out, dpi=120)
    print(out)


if __name__ == "__main__":
    main()
