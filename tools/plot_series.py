#!/usr/bin/python3
"""Plot the columns of a Granule time series against its "time" column.

usage: /usr/bin/python3 tools/plot_series.py out.h5 [--group /series] [--columns a,b]
                                             [--x time] [--log-x] [--log-y] [-o fig.png]

Any series group a scene writes (/series, /impact, /sweep, zone profiles...):
one subplot per column (all columns but the x column unless --columns is
given), sharing the x axis (default "time"; any column with --x). Axis labels
carry the units stored with the series. --list prints the file's series groups
and their columns instead. Writes a PNG (default: <file>_<group>.png next to
the input) and prints its path.
"""

import argparse
import os
import sys

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
        if columns is None:
            columns = [c for c in data if c != x]
        g.require_columns(f, group, data, columns)
        if not columns:
            raise g.GranuleH5Error(f"{path}: series '{group}' has no column besides {x}")
        time = data[x]

    fig, axes = plt.subplots(
        len(columns), 1, sharex=True, squeeze=False, figsize=(7, 1.0 + 1.9 * len(columns))
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
    fig.suptitle(f"{os.path.basename(path)}: {group} ({len(time)} rows)")
    fig.tight_layout()
    output = g.output_path(path, group.strip("/").replace("/", "_") or "root", output)
    fig.savefig(output, dpi=120)
    plt.close(fig)
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
