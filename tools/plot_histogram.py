#!/usr/bin/python3
"""Histogram of a per-particle quantity in a snapshot, or of a series column.

usage: /usr/bin/python3 tools/plot_histogram.py out.h5 [--quantity speed] [--index -1]
                                                [--by-material] [--bins 30] [--log-y] [-o fig.png]
       /usr/bin/python3 tools/plot_histogram.py out.h5 --group /series --column max_overlap_ratio

Snapshot quantities: speed [m/s], radius, diameter [m], spin [rad/s] (2D: signed
spin about z; 3D: its magnitude), x, y, z [m], vx, vy, vz [m/s]. Fixed particles
are left out. --by-material stacks one colour per material. With --group and
--column the values of a series column are counted instead (e.g. the overlap
ratios over a run). Writes a PNG (default: <file>_histogram_<quantity>.png next
to the input) and prints its path.
"""

import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import granule_h5 as g  # noqa: E402


def plot_histogram(path, quantity="speed", index=-1, by_material=False, bins=30, log_y=False,
                   group=None, column=None, output=None):
    if bins < 1:
        raise g.GranuleH5Error(f"--bins must be 1 or more, got {bins}")
    with g.open_run(path) as f:
        if group or column:
            if not (group and column):
                raise g.GranuleH5Error("--group and --column go together")
            data = g.series(f, group)
            g.require_columns(f, group, data, [column])
            stacks = [(column, data[column])]
            unit = g.series_units(f, group).get(column, "")
            name, title = column, f"{group}: {len(data[column])} rows"
        else:
            snap = g.snapshot(f, index)
            values, unit = g.snapshot_quantity(snap, quantity)
            free = ~snap["fixed"]
            name = quantity
            title = f"{snap['name']}  t = {snap['time']:.6g} s, {int(free.sum())} free particles"
            if by_material:
                names = snap["material_names"]
                stacks = [(names[m] if m < len(names) else f"material {m}",
                           values[free & (snap["material"] == m)])
                          for m in np.unique(snap["material"][free])]
            else:
                stacks = [(name, values[free])]
    all_values = np.concatenate([v for _, v in stacks]) if stacks else np.array([])
    if all_values.size == 0:
        raise g.GranuleH5Error(f"{path}: no values to count")
    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.hist([v for _, v in stacks], bins=bins, stacked=len(stacks) > 1,
            label=[label for label, _ in stacks], edgecolor="white", linewidth=0.5)
    if log_y:
        ax.set_yscale("log")
    ax.set_xlabel(g.axis_label(name, unit))
    ax.set_ylabel("count")
    ax.grid(True, alpha=0.3)
    if len(stacks) > 1:
        ax.legend(fontsize=8)
    mean, std = float(np.mean(all_values)), float(np.std(all_values))
    ax.set_title(f"{os.path.basename(path)}: {title}\nmean {mean:.4g}, std {std:.4g}", fontsize=9)
    fig.tight_layout()
    output = g.output_path(path, f"histogram_{name}", output)
    fig.savefig(output, dpi=120)
    plt.close(fig)
    return output


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("file", help="Granule output file (.h5)")
    parser.add_argument("--quantity", default="speed", choices=sorted(g.SNAPSHOT_QUANTITIES),
                        help="per-particle quantity of a snapshot (default speed)")
    parser.add_argument("--index", type=int, default=-1,
                        help="snapshot; negative counts from the end (default -1)")
    parser.add_argument("--by-material", action="store_true", help="one stack per material")
    parser.add_argument("--bins", type=int, default=30, help="number of bins (default 30)")
    parser.add_argument("--log-y", action="store_true", help="logarithmic count axis")
    parser.add_argument("--group", help="series group, to count a column instead")
    parser.add_argument("--column", help="series column (with --group)")
    parser.add_argument("-o", "--output", help="PNG to write")
    g.run_tool(parser, lambda a: plot_histogram(a.file, a.quantity, a.index, a.by_material, a.bins,
                                                a.log_y, a.group, a.column, a.output))


if __name__ == "__main__":
    main()
