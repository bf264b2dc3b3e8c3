#!/usr/bin/python3
"""Damage and debris ratios against time for agglomerate tests (Figs. 7.15-7.23, 7.35-7.36).

usage: /usr/bin/python3 tools/plot_breakage.py a.h5 [b.h5 ...] [--x time|wall_travel]
                                                [--graph contacts|bonds] [-o breakage.png]

Reads the series /breakage that the agglomerate tests write (granule.agglomerate_tests)
and draws, for every file, the damage ratio (broken / initial bonds) and the debris
ratio (mass in fragments under 2.5 % of the initial mass / initial mass) against
time in microseconds, or against the wall travel for compression tests. Each
curve is labelled with the file's velocity and surface energy (/results); the
first contact episode of a single file is shaded. --graph bonds draws the debris
ratio of the surviving initial bonds' graph instead of the contact graph.

Writes a PNG (default: <first file>_breakage.png) and prints its path.
"""

import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import granule_h5 as g  # noqa: E402


def read(path):
    """The /breakage series and the /results attributes of one test output."""
    with g.open_run(path) as f:
        data = g.series(f, "/breakage")
        g.require_columns(f, "/breakage", data, ["time", "damage_ratio", "debris_ratio"])
        results = {k: float(v) for k, v in f["results"].attrs.items()} if "results" in f else {}
    return data, results


def label_of(path, results):
    if "velocity" in results:
        return f"v = {results['velocity']:g} m/s, $\\Gamma$ = {results.get('surface_energy', float('nan')):g}"
    return os.path.basename(path)


def plot(axes, paths, x="time", graph="contacts", shade=True, measure="debris_ratio"):
    """Draws damage (axes[0]) and debris (axes[1]) for every file. `measure` is
    debris_ratio (by mass, 7.4) or debris_ratio_by_size (by primaries, 7.6);
    graph "bonds" takes its surviving-bond version."""
    debris_key = measure + "_bonds" if graph == "bonds" else measure
    for path in paths:
        data, results = read(path)
        if x not in data or debris_key not in data:
            raise g.GranuleH5Error(f"{path}: /breakage has no column '{x if x not in data else debris_key}'")
        scale = 1e6  # s -> us, or m -> um for the wall travel
        xs = data[x] * scale
        line, = axes[0].plot(xs, data["damage_ratio"], lw=1.2, label=label_of(path, results))
        axes[1].plot(xs, data[debris_key], lw=1.2, color=line.get_color())
        if shade and len(paths) == 1 and x == "time" and results.get("impact_duration", -1) > 0:
            t0 = results["contact_start"] * 1e6
            for ax in axes:
                ax.axvspan(t0, t0 + results["impact_duration"] * 1e6, color="0.9", zorder=0,
                           label="first contact" if ax is axes[0] else None)
    axes[0].set_ylabel("damage ratio")
    axes[1].set_ylabel("debris ratio" + (" by size" if measure.endswith("by_size") else "")
                       + (" (surviving bonds)" if graph == "bonds" else ""))
    axes[1].set_xlabel("time [$\\mu$s]" if x == "time" else "wall travel [$\\mu$m]")
    for ax in axes:
        ax.set_ylim(bottom=0)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="+", help="outputs of agglomerate tests (.h5)")
    parser.add_argument("--x", default="time", choices=("time", "wall_travel"))
    parser.add_argument("--graph", default="contacts", choices=("contacts", "bonds"))
    parser.add_argument("--measure", default="debris_ratio", choices=("debris_ratio", "debris_ratio_by_size"),
                        help="debris by mass (7.4) or by size in primaries (7.6)")
    parser.add_argument("--log-x", action="store_true", help="logarithmic time axis")
    parser.add_argument("-o", "--output", help="PNG to write")
    args = parser.parse_args(argv)
    output = args.output or os.path.splitext(args.files[0])[0] + "_breakage.png"
    try:
        fig, axes = plt.subplots(2, 1, sharex=True, figsize=(6, 5.5))
        plot(axes, args.files, args.x, args.graph, measure=args.measure)
        if args.log_x:
            axes[1].set_xscale("log")
        fig.tight_layout()
        fig.savefig(output, dpi=110)
        plt.close(fig)
    except g.GranuleH5Error as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    print(output)
    return 0


if __name__ == "__main__":
    sys.exit(main())
