#!/usr/bin/python3
"""Plot the columns of a Granule time series against its "time" column.

usage: /usr/bin/python3 tools/plot_series.py out.h5 [--group /series] [--columns a,b] [-o fig.png]

One subplot per column (all columns but time unless --columns is given), sharing
the time axis. Axis labels carry the units stored with the series. Writes a PNG
(default: <file>_<group>.png next to the input) and prints its path.
"""

import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import granule_h5 as g  # noqa: E402


def plot_series(path, group="/series", columns=None, output=None, x="time", log_x=False):
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
        unit = units.get(c, "")
        ax.set_ylabel(f"{c} [{unit}]" if unit and unit != "-" else c, fontsize=8)
        ax.grid(True, alpha=0.3)
    x_unit = units.get(x, "s" if x == "time" else "")
    axes[-1, 0].set_xlabel(f"{x} [{x_unit}]" if x_unit and x_unit != "-" else x)
    fig.suptitle(f"{os.path.basename(path)}: {group} ({len(time)} rows)")
    fig.tight_layout()
    if output is None:
        stem = os.path.splitext(path)[0]
        output = f"{stem}_{group.strip('/').replace('/', '_') or 'root'}.png"
    fig.savefig(output, dpi=120)
    plt.close(fig)
    return output


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("file", help="Granule output file (.h5)")
    parser.add_argument("--group", default="/series", help="series group (default /series)")
    parser.add_argument("--columns", help="comma-separated columns to plot (default: all)")
    parser.add_argument("--x", default="time", help="column for the horizontal axis (default time)")
    parser.add_argument("--log-x", action="store_true", help="logarithmic horizontal axis")
    parser.add_argument("-o", "--output", help="PNG to write")
    args = parser.parse_args(argv)
    columns = [c.strip() for c in args.columns.split(",") if c.strip()] if args.columns else None
    try:
        print(plot_series(args.file, args.group, columns, args.output, args.x, args.log_x))
    except g.GranuleH5Error as e:
        sys.exit(f"{parser.prog}: error: {e}")


if __name__ == "__main__":
    main()
