#!/usr/bin/python3
"""What accuracy costs in time: error against wall time, one curve per knob.

usage: /usr/bin/python3 tools/plot_accuracy.py accuracy_impact.csv [--x wall_time_s|steps]
                                               [--quantities restitution,contact_duration] [-o fig.png]

Reads the CSV written by tools/accuracy.lua (one row per setting and quantity)
and draws one panel per quantity: the relative error of each setting against
its knob's reference run, over the run's cost (wall time, or steps for cases
too quick to time), log-log, one curve per knob, each point labelled with its
setting. Settings whose error is exactly zero (an exact knob, such as the skin
of a binary impact) are drawn at the bottom of the panel. Stiffness settings
below a bound of Eqs. 5.12/5.15 (Mechanofusion case) are drawn hollow.
Prints the figure's path and, per knob, the setting with the smallest cost
whose errors are all below 1 % (a noise estimate, `*_noise`, is not an error;
a setting below a bound of Eqs. 5.12/5.15 never qualifies).
"""

import argparse
import csv
import math
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("csv")
    ap.add_argument("--x", default="wall_time_s", choices=["wall_time_s", "steps"])
    ap.add_argument("--quantities", default="", help="comma-separated (default: all)")
    ap.add_argument("--tolerance", type=float, default=0.01,
                    help="error below which a setting counts as accurate (default 1 %%)")
    ap.add_argument("-o", "--output", default="")
    a = ap.parse_args()

    with open(a.csv, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{a.csv}: no rows")
    need = {"knob", "setting", "is_reference", "quantity", "relative_error", a.x}
    missing = need - set(rows[0])
    if missing:
        sys.exit(f"{a.csv}: not an accuracy table (missing columns {sorted(missing)})")
    case = rows[0]["case"]
    quantities = []
    for r in rows:
        if r["quantity"] not in quantities:
            quantities.append(r["quantity"])
    if a.quantities:
        wanted = a.quantities.split(",")
        unknown = [q for q in wanted if q not in quantities]
        if unknown:
            sys.exit(f"unknown quantities {unknown}; the table has {quantities}")
        quantities = wanted

    # (knob, quantity) -> [(cost, error, setting, broken)]
    curves = defaultdict(list)
    worst = defaultdict(float)  # (knob, setting) -> largest error over the quantities
    broken_settings = set()  # below a bound of Eqs. 5.12/5.15: never the cheapest good one
    cost_of = {}
    for r in rows:
        if r["is_reference"] == "1":
            continue
        broken = any(r.get(m) not in (None, "") and float(r[m]) < 1 for m in ("margin_5_12", "margin_5_15"))
        cost = max(float(r[a.x]), 1e-4)
        err = float(r["relative_error"])
        key = (r["knob"], r["setting"])
        cost_of[key] = cost
        if r["quantity"] in quantities:
            curves[(r["knob"], r["quantity"])].append((cost, err, r["setting"], broken))
            # A noise estimate (the Mechanofusion case's normal_force_noise) is the
            # scatter a difference must exceed, not an error of the setting.
            if not r["quantity"].endswith("_noise"):
                worst[key] = max(worst[key], err)
        if broken:
            broken_settings.add(key)

    knobs = sorted({k for k, _ in curves})
    fig, axes = plt.subplots(len(quantities), 1, squeeze=False, figsize=(7, 1.5 + 2.6 * len(quantities)))
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for ax, q in zip(axes[:, 0], quantities):
        positive = [e for (k, qq), pts in curves.items() if qq == q for _, e, _, _ in pts if e > 0]
        floor = min(positive) / 10 if positive else 1e-12
        for n, knob in enumerate(knobs):
            pts = sorted(curves.get((knob, q), []))
            if not pts:
                continue
            xs = [c for c, _, _, _ in pts]
            ys = [max(e, floor) for _, e, _, _ in pts]
            colour = colours[n % len(colours)]
            ax.plot(xs, ys, "-", color=colour, lw=1, label=knob)
            for (c, e, s, broken), y in zip(pts, ys):
                ax.plot([c], [y], "o", ms=5, color=colour, mfc="none" if broken else colour)
                ax.annotate(s, (c, y), textcoords="offset points", xytext=(3, 3), fontsize=7)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.axhline(a.tolerance, color="grey", lw=0.5, ls=":")
        ax.set_ylabel(f"{q}\nrelative error", fontsize=9)
        ax.legend(fontsize=8)
    axes[-1, 0].set_xlabel("wall time [s]" if a.x == "wall_time_s" else "steps")
    fig.suptitle(f"accuracy against cost: {case}", fontsize=10)
    fig.tight_layout()
    out = a.output or a.csv.rsplit(".", 1)[0] + ".png"
    fig.savefig(out, dpi=110)
    print(out)
    for knob in knobs:
        good = [(cost_of[k], k[1]) for k in worst
                if k[0] == knob and worst[k] < a.tolerance and k not in broken_settings]
        if good:
            cost, setting = min(good, key=lambda t: t[0])
            print(f"{knob}: cheapest setting with every error below {a.tolerance:g}: {setting} "
                  f"({a.x} {cost:.3g})")
        else:
            print(f"{knob}: no setting has every error below {a.tolerance:g}")
    if not math.isfinite(sum(worst.values())):
        sys.exit("non-finite errors in the table")


if __name__ == "__main__":
    main()
