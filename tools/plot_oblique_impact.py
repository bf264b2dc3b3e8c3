#!/usr/bin/python3
"""Figures 6.2-6.10 from scenarios/oblique_impact.lua: loading paths and tangential force-displacement curves.

usage: /usr/bin/python3 tools/plot_oblique_impact.py oblique_impact.h5 [-o oblique.png]

One row per surface energy Gamma: left, tangential force T against normal force N
(the loading path, Figs 6.2, 6.4-6.9); right, T against the tangential
displacement (Figs 6.3, 6.10); one curve per impact angle.
"""
import argparse
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import granule_h5 as g  # noqa: E402


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("file")
    parser.add_argument("-o", "--output")
    args = parser.parse_args(argv)
    try:
        f = g.open_run(args.file)
    except g.GranuleH5Error as e:
        sys.exit(f"{parser.prog}: error: {e}")
    cases = {}
    for name in f:
        m = re.fullmatch(r"angle_([0-9.eE+-]+)_gamma_([0-9.eE+-]+)", name)
        if m:
            cases.setdefault(float(m.group(2)), []).append((float(m.group(1)), name))
    if not cases:
        sys.exit(f"{parser.prog}: error: {args.file} has no angle_*_gamma_* series (run scenarios/oblique_impact.lua)")
    gammas = sorted(cases)
    fig, axes = plt.subplots(len(gammas), 2, figsize=(11, 4.2 * len(gammas)), squeeze=False)
    for row, gamma in enumerate(gammas):
        for angle, name in sorted(cases[gamma]):
            d = g.series(f, "/" + name)
            label = f"{angle:g} deg"
            axes[row, 0].plot(d["normal_force"] * 1e3, d["tangential_force"] * 1e3, label=label)
            axes[row, 1].plot(d["tangential_displacement"] * 1e9, d["tangential_force"] * 1e3, label=label)
        axes[row, 0].set_xlabel("normal force N [mN]")
        axes[row, 0].set_ylabel("tangential force T [mN]")
        axes[row, 0].set_title(f"loading path, Gamma = {gamma:g} J/m^2")
        axes[row, 1].set_xlabel("tangential displacement [nm]")
        axes[row, 1].set_ylabel("tangential force T [mN]")
        axes[row, 1].set_title(f"tangential force-displacement, Gamma = {gamma:g} J/m^2")
        for ax in axes[row]:
            ax.grid(True, alpha=0.3)
            ax.axhline(0, color="k", lw=0.5)
            ax.legend(fontsize=8)
    fig.tight_layout()
    out = args.output or os.path.splitext(args.file)[0] + "_paths.png"
    fig.savefig(out, dpi=120)
    print(out)


if __name__ == "__main__":
    main()
