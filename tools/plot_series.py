#!/usr/bin/python3
"""Plot the columns of a Granule time series against its "time" column.

usage: /usr/bin/python3 tools/plot_series.py out.h5 [--group /series] [--columns a,b]
                                             [--x time] [--log-x] [--log-y] [-o fig.png]

Any series group a scene writes (/series, /impact, /sweep, zone profiles...):
one subplot per column (all columns but the x column unless --columns is
given), sharing the x axis (default "time"; any column with --x). Axis labels
carry the units stored with the series. Without --columns, a column that is
zero throughout (momentum_z of a 2D run, a counter that never moved) gets no
panel of its own; the figure's footnote names it. --list prints the file's
series groups and their columns instead. Writes a PNG (default: <file>_<group>.png next to
the input) and prints its path.
"""

import argparse
import os
import sys

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import granule_h5 as g  # noqa: E402


def plot_series(path, group="/series", columns=None, output=None, x="time", log_x=False,
                log_y=False):
    with g.open_run(path) as f:
        data = g.series(f, group)
        units = g.series_units(f, group)
        g.require_columns(f, group, data, [x])
        skipped = []
        if columns is None:
            columns = [c for c in data if c != x]
            # Zero throughout: a line on its axis says nothing a footnote cannot.
            skipped = [c for c in columns if not np.any(np.nan_to_num(np.asarray(data[c], float)))]
            if len(skipped) < len(columns):
                columns = [c for c in columns if c not in skipped]
            else:
                skipped = []
        g.require_columns(f, group, data, columns)
        if not columns:
            raise g.GranuleH5Error(f"{path}: series '{group}' has no column besides {x}")
        time = data[x]

    # constrained layout keeps the title clear of the first panel's labels
    fig, axes = plt.subplots(
        len(columns), 1, sharex=True, squeeze=False, figsize=(7, 1.2 + 1.9 * len(columns)),
        layout="constrained"
    )
    for ax, c in zip(axes[:, 0], columns):
        ax.plot(time, data[c], lw=1, marker="o" if len(time) < 50 else None, ms=3)
        if log_x:
            ax.set_xscale("log")
        if log_y:
            ax.set_yscale("log")
        ax.set_ylabel(g.axis_label(c, units.get(c, "")), fontsize=8)
        ax.grid(True, alpha=0.3)
    x_unit = units.get(x, "s" if x == "time" else "")
    axes[-1, 0].set_xlabel(g.axis_label(x, x_unit))
    fig.suptitle(f"{os.path.basename(path)}: {group} ({len(time)} rows)", fontsize=10)
    if skipped:
        fig.text(0.01, 0.002, "zero throughout, not drawn: " + ", ".join(skipped), fontsize=7,
                 va="bottom", ha="left")
    output = g.output_path(path, group.strip("/").replace("/", "_") or "root", output)
    fig.savefig(output, dpi=120)
    plt.close(fig)
    if skipped:
        print("zero throughout, not drawn: " + ", ".join(skipped))
    return output


def list_series(path):
    with g.open_run(path) as f:
        return [f"{grp}: {', '.join(g.series_columns(f, grp))}" for grp in g.series_groups(f)]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("file", help="Granule output file (.h5)")
    parser.add_argument("--group", default="/series", help="series group (default /series)")
    parser.add_argument("--columns", help="comma-separated columns to plot (default: all)")
    parser.add_argument("--x", default="time", help="column for the horizontal axis (default time)")
    parser.add_argument("--log-x", action="store_true", help="logarithmic horizontal axis")
    parser.add_argument("--log-y", action="store_true", help="logarithmic vertical axes")
    parser.add_argument("--list", action="store_true", help="list the series groups and columns")
    parser.add_argument("-o", "--output", help="PNG to write")
    g.run_tool(parser, lambda a: list_series(a.file) if a.list else plot_series(
        a.file, a.group, g.column_list(a.columns), a.output, a.x, a.log_x, a.log_y))


if __name__ == "__main__":
    main()
