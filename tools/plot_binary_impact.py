#!/usr/bin/python3
"""Plot the force history of a binary impact (two particles colliding).

usage: /usr/bin/python3 tools/plot_binary_impact.py out.h5 [--group /impact] [-o fig.png]

Reads the series group /impact (columns time, overlap, normal_force,
tangential_force; others are ignored) and draws two panels:
  left:  normal force against overlap (loading and unloading, as in Figs 3.4-3.6
         of the dissertation);
  right: tangential force against normal force (as in Figs 3.7-3.8).
Both curves are coloured by time, so loading and unloading can be told apart.
Writes a PNG (default: <file>_impact.png next to the input) and prints its path.
"""

import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import granule_h5 as g  # noqa: E402

REQUIRED = ["time", "overlap", "normal_force", "tangential_force"]


def _time_coloured(ax, x, y, time, norm):
    """A curve whose colour follows time, with its start and end marked."""
    points = np.column_stack([x, y]).reshape(-1, 1, 2)
    segments = np.concatenate([points[:-1], points[1:]], axis=1)
    lines = LineCollection(segments, cmap="viridis", norm=norm, linewidths=1.5)
    lines.set_array(0.5 * (time[:-1] + time[1:]))
    ax.add_collection(lines)
    ax.plot(x[:1], y[:1], "o", color="k", ms=4, label="start")
    ax.plot(x[-1:], y[-1:], "s", color="k", ms=4, mfc="none", label="end")
    ax.autoscale()
    ax.grid(True, alpha=0.3)
    return lines


def plot_binary_impact(path, group="/impact", output=None):
    with g.open_run(path) as f:
        data = g.series(f, group)
        units = g.series_units(f, group)
        g.require_columns(f, group, data, REQUIRED)
    time = data["time"]
    if len(time) < 2:
        raise g.GranuleH5Error(f"{path}: series '{group}' has {len(time)} rows, need 2 or more")

    def label(c, default):
        return f"{c.replace('_', ' ')} [{units.get(c, default)}]"

    norm = plt.Normalize(time.min(), time.max())
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.5), constrained_layout=True)
    _time_coloured(left, data["overlap"], data["normal_force"], time, norm)
    left.set_xlabel(label("overlap", "m"))
    left.set_ylabel(label("normal_force", "N"))
    left.set_title("normal force vs overlap")
    left.legend(fontsize=8)
    lines = _time_coloured(right, data["normal_force"], data["tangential_force"], time, norm)
    right.set_xlabel(label("normal_force", "N"))
    right.set_ylabel(label("tangential_force", "N"))
    right.set_title("tangential force vs normal force")
    fig.colorbar(lines, ax=[left, right], label=f"time [{units.get('time', 's')}]")
    fig.suptitle(f"{os.path.basename(path)}: binary impact")
    if output is None:
        output = os.path.splitext(path)[0] + "_impact.png"
    fig.savefig(output, dpi=120)
    plt.close(fig)
    return output


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("file", help="Granule output file (.h5)")
    parser.add_argument("--group", default="/impact", help="series group (default /impact)")
    parser.add_argument("-o", "--output", help="PNG to write")
    args = parser.parse_args(argv)
    try:
        print(plot_binary_impact(args.file, args.group, args.output))
    except g.GranuleH5Error as e:
        sys.exit(f"{parser.prog}: error: {e}")


if __name__ == "__main__":
    main()
