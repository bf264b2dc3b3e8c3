#!/usr/bin/python3
"""Plot maximum contact force against impact velocity and angle (Fig. 4.26).

usage: /usr/bin/python3 tools/plot_impact_map.py binary_impact_map.h5 [-o fig.png]

Reads /impacts (angle, velocity, max_normal_force) written by
scenarios/binary_impact_map.lua, fits F_max = c dv through the origin for each
angle (here, independently of the scene's own fit), prints one line per angle
with c, the linear-spring prediction (K m / 2)^(1/2) cos(angle) stored in
/slopes, and the ratio to section 7.2's c = 0.02 N s/m; then whether every
fitted c lies within --tolerance (default 2 %) of the prediction; and draws two
panels: F_max against dv with the fitted lines, and c against the angle.
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

SECTION_7_2_SLOPE = 0.02  # N s/m, F_max = 0.02 dv (dissertation section 7.2)


def fit_slopes(angle, velocity, force):
    """{angle: c} with c minimising sum (F - c v)^2 for each angle."""
    slopes = {}
    for a in np.unique(angle):
        sel = angle == a
        v, f = velocity[sel], force[sel]
        slopes[float(a)] = float(np.dot(v, f) / np.dot(v, v))
    return slopes


def plot_impact_map(path, output=None, out=sys.stdout, tolerance=0.02):
    with g.open_run(path) as f:
        impacts = g.series(f, "/impacts")
        g.require_columns(f, "/impacts", impacts, ["angle", "velocity", "max_normal_force"])
        predicted = {}
        if "slopes" in f:
            s = g.series(f, "/slopes")
            if "angle" in s and "predicted_slope" in s:
                predicted = {float(a): float(c) for a, c in zip(s["angle"], s["predicted_slope"])}
    angle, velocity, force = impacts["angle"], impacts["velocity"], impacts["max_normal_force"]
    if len(angle) == 0:
        raise g.GranuleH5Error(f"{path}: /impacts is empty")
    slopes = fit_slopes(angle, velocity, force)

    print(f"{'angle [deg]':>11} {'c fitted [N s/m]':>17} {'c predicted':>12} {'c / 0.02':>9}", file=out)
    for a, c in slopes.items():
        p = predicted.get(a, float("nan"))
        print(f"{a:11g} {c:17.5g} {p:12.5g} {c / SECTION_7_2_SLOPE:9.4f}", file=out)
    if predicted:
        worst = max(abs(c / predicted[a] - 1) for a, c in slopes.items() if a in predicted)
        verdict = "yes" if worst <= tolerance else "no"
        print(
            f"slopes within {100 * tolerance:g} % of (K m/2)^(1/2) cos(angle): {verdict} "
            f"(worst {100 * worst:.2f} %)",
            file=out,
        )

    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4.2))
    colours = plt.cm.viridis(np.linspace(0, 0.9, len(slopes)))
    v_line = np.array([0, velocity.max()])
    for colour, (a, c) in zip(colours, slopes.items()):
        sel = angle == a
        left.plot(velocity[sel], force[sel] * 1e3, "o", color=colour, ms=4, label=f"{a:g} deg")
        left.plot(v_line, c * v_line * 1e3, "-", color=colour, lw=1)
    left.set_xlabel("relative impact velocity dv [m/s]")
    left.set_ylabel("maximum normal force [mN]")
    left.set_title("Fig. 4.26: F_max = c dv per angle", fontsize=10)
    left.legend(fontsize=8)
    left.grid(True, alpha=0.3)

    a_fit = np.array(list(slopes.keys()))
    right.plot(a_fit, list(slopes.values()), "o", label="fitted to the runs")
    if predicted:
        a_smooth = np.linspace(0, max(a_fit.max(), 1), 100)
        c0 = predicted.get(0.0)
        if c0 is not None:
            right.plot(a_smooth, c0 * np.cos(np.radians(a_smooth)), "-", lw=1,
                       label="(K m/2)^(1/2) cos(angle)")
    right.axhline(SECTION_7_2_SLOPE, color="k", ls="--", lw=1, label="section 7.2: 0.02 N s/m")
    right.set_xlabel("impact angle [deg]")
    right.set_ylabel("slope c [N s/m]")
    right.set_title("slope against angle", fontsize=10)
    right.set_ylim(bottom=0)
    right.legend(fontsize=8)
    right.grid(True, alpha=0.3)
    fig.suptitle(f"{os.path.basename(path)}: binary impacts")
    fig.tight_layout()
    if output is None:
        output = os.path.splitext(path)[0] + "_map.png"
    fig.savefig(output, dpi=80)
    plt.close(fig)
    return output, slopes


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("file", help="output of scenarios/binary_impact_map.lua (.h5)")
    parser.add_argument("-o", "--output", help="PNG to write")
    parser.add_argument(
        "--tolerance", type=float, default=0.02, help="relative agreement asked of the slopes"
    )
    args = parser.parse_args(argv)
    try:
        output, _ = plot_impact_map(args.file, args.output, tolerance=args.tolerance)
    except g.GranuleH5Error as e:
        sys.exit(f"{parser.prog}: error: {e}")
    print(output)


if __name__ == "__main__":
    main()
