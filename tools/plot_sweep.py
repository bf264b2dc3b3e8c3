#!/usr/bin/python3
"""Parameter-sweep curves: one result against one parameter.

usage: /usr/bin/python3 tools/plot_sweep.py out.h5 --group /sweep --x velocity
                                             [--y restitution,contact_time] [--by column]
                                             [--log-x] [--log-y] [-o fig.png]
       /usr/bin/python3 tools/plot_sweep.py run1.h5 run2.h5 ... --parameter velocity --result restitution

One file: a scene that sweeps a parameter itself writes one row per case into a
series group (e.g. scenarios/adhesive_restitution.lua writes /sweep); the rows
are sorted by the --x column and each --y column (default: all others) gets a
panel, points joined by lines; --by draws one line per value of another column.
The summary of `granule sweep` (DIR/<scene>.sweep.h5) is such a file: /sweep has
a row per finished case, its numeric parameters and results as columns. Several files: one run per case (e.g. `granule
run scene.lua -D velocity=...` repeated); x is a scene parameter (the attributes
of /scene/parameters, after -D) and y a result the scene reported with
sim:result (the attributes of /results), one point per file. Writes a PNG
(default: <first file>_sweep.png) and prints its path.
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


def _panels(x, x_label, curves, title, log_x, log_y, output, groups=None, group_label=""):
    fig, axes = plt.subplots(len(curves), 1, sharex=True, squeeze=False,
                             figsize=(7, 1.2 + 2.4 * len(curves)))
    # One line per value of the grouping column (a second swept parameter), else one line.
    lines = [(None, np.ones(len(x), bool))] if groups is None else \
        [(f"{group_label} = {v:g}", groups == v) for v in np.unique(groups)]
    for ax, (label, y) in zip(axes[:, 0], curves):
        for line_label, mask in lines:
            order = np.argsort(x[mask])
            ax.plot(x[mask][order], y[mask][order], marker="o", ms=4, lw=1, label=line_label)
        if groups is not None:
            ax.legend(fontsize=8)
        ax.set_ylabel(label, fontsize=9)
        if log_x:
            ax.set_xscale("log")
        if log_y:
            ax.set_yscale("log")
        ax.grid(True, alpha=0.3)
    axes[-1, 0].set_xlabel(x_label)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(output, dpi=120)
    plt.close(fig)
    return output


def sweep_from_series(path, group, x, y=None, log_x=False, log_y=False, output=None, by=None):
    with g.open_run(path) as f:
        data = g.series(f, group)
        units = g.series_units(f, group)
        g.require_columns(f, group, data, [x] + ([by] if by else []))
        y = y or [c for c in data if c not in (x, by)]
        g.require_columns(f, group, data, y)
    if not y:
        raise g.GranuleH5Error(f"{path}: series '{group}' has no column besides {x}")
    if len(data[x]) == 0:
        raise g.GranuleH5Error(f"{path}: series '{group}' has no rows")
    curves = [(g.axis_label(c, units.get(c, "")), data[c]) for c in y]
    title = f"{os.path.basename(path)}: {group} ({len(data[x])} cases)"
    return _panels(data[x], g.axis_label(x, units.get(x, "")), curves, title, log_x, log_y,
                   g.output_path(path, "sweep", output), data[by] if by else None, by)


def sweep_from_runs(paths, parameter, result, log_x=False, log_y=False, output=None):
    xs, ys = [], []
    for path in paths:
        with g.open_run(path) as f:
            p, r = g.parameters(f), g.results(f)
        if parameter not in p:
            raise g.GranuleH5Error(
                f"{path}: no scene parameter '{parameter}' (parameters: {', '.join(p) or 'none'})")
        if result not in r:
            raise g.GranuleH5Error(
                f"{path}: no result '{result}' (results: {', '.join(r) or 'none'})")
        try:
            xs.append(float(p[parameter]))
        except (TypeError, ValueError):
            raise g.GranuleH5Error(f"{path}: parameter '{parameter}' = {p[parameter]!r} is not a number")
        ys.append(float(r[result]))
    title = f"{result} against {parameter} ({len(paths)} runs)"
    return _panels(np.array(xs), parameter.replace("_", " "),
                   [(result.replace("_", " "), np.array(ys))], title, log_x, log_y,
                   g.output_path(paths[0], "sweep", output))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="+", help="Granule output file(s) (.h5)")
    parser.add_argument("--group", help="one file: the series group holding the sweep")
    parser.add_argument("--x", help="one file: the column swept")
    parser.add_argument("--y", help="one file: comma-separated result columns (default: all)")
    parser.add_argument("--by", help="one file: a column to draw one line per value of "
                                     "(the second parameter of a `granule sweep`)")
    parser.add_argument("--parameter", help="several files: the scene parameter swept")
    parser.add_argument("--result", help="several files: the result (sim:result) to plot")
    parser.add_argument("--log-x", action="store_true", help="logarithmic horizontal axis")
    parser.add_argument("--log-y", action="store_true", help="logarithmic vertical axes")
    parser.add_argument("-o", "--output", help="PNG to write")

    def work(a):
        if a.parameter or a.result:
            if not (a.parameter and a.result) or a.group or a.x or a.y or a.by:
                raise g.GranuleH5Error("give --parameter and --result (and no --group/--x/--y)")
            return sweep_from_runs(a.files, a.parameter, a.result, a.log_x, a.log_y, a.output)
        if len(a.files) != 1 or not (a.group and a.x):
            raise g.GranuleH5Error("give one file with --group and --x, or several with "
                                   "--parameter and --result")
        return sweep_from_series(a.files[0], a.group, a.x, g.column_list(a.y), a.log_x, a.log_y,
                                 a.output, a.by)

    g.run_tool(parser, work)


if __name__ == "__main__":
    main()
