#!/usr/bin/python3
"""Plot the deformation study of section 4.6 (Figs 4.27-4.30).

usage: /usr/bin/python3 tools/plot_coating_deformation.py coating_deformation.h5 [-o fig.png]

Reads the series that scenarios/coating_deformation.lua writes (/velocity,
/guest_size, /hardness) and draws four panels:
  contact area pi a_m^2 against the relative impact velocity (Fig. 4.27);
  central displacement ratio against velocity, Hertz and JKR, and JKR for the
  harder host (Figs 4.28 and 4.30);
  the ratio against the guest diameter (Fig. 4.29);
  the ratio against the host's Young's modulus (Fig. 4.30 as a sweep).
Prints the PNG's path and the slope of log(area) against log(v) over the
upper half of the velocities (1 = linear, as Fig. 4.27 says).
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


def _read(f, group, columns):
    data = g.series(f, group)
    g.require_columns(f, group, data, columns)
    return data


def plot_coating_deformation(path, output=None):
    with g.open_run(path) as f:
        vel = _read(
            f,
            "/velocity",
            ["impact_velocity", "contact_area", "ratio_hertz", "ratio_jkr", "ratio_jkr_hard"],
        )
        size = _read(f, "/guest_size", ["guest_diameter", "ratio_hertz", "ratio_jkr"])
        hard = _read(f, "/hardness", ["host_young", "ratio_hertz", "ratio_jkr"])
        params = {k: g._text(v) for k, v in f["/scene/parameters"].attrs.items()}

    v = vel["impact_velocity"]
    upper = v >= np.median(v)
    area_exponent = np.polyfit(np.log(v[upper]), np.log(vel["contact_area"][upper]), 1)[0]

    fig, axes = plt.subplots(2, 2, figsize=(9, 7))
    ax = axes[0, 0]
    ax.plot(v, vel["contact_area"] * 1e12, "o-", ms=3)
    ax.set_xlabel("relative impact velocity [m/s]")
    ax.set_ylabel("contact area pi a_m^2 [um^2]")
    ax.set_title(f"Fig. 4.27: area ~ v^{area_exponent:.3f}", fontsize=10)
    ax.grid(True, alpha=0.3)

    ax = axes[0, 1]
    ax.plot(v, vel["ratio_hertz"], "--", label="Hertz (B.7)")
    ax.plot(v, vel["ratio_jkr"], "-", label="JKR (B.8-B.10)")
    hard_e = params.get("hard_host_young", "?")
    ax.plot(v, vel["ratio_jkr_hard"], "-", label=f"JKR, host E = {float(hard_e) / 1e9:g} GPa")
    ax.set_xscale("log")
    ax.set_xlabel("relative impact velocity [m/s]")
    ax.set_ylabel("central displacement / guest diameter")
    ax.set_title("Figs 4.28, 4.30: ratio vs velocity", fontsize=10)
    ax.set_ylim(0, 1.3 * max(vel["ratio_jkr"].max(), vel["ratio_hertz"].max()))
    ax.legend(fontsize=8)
    ax.grid(True, alpha=0.3)

    ax = axes[1, 0]
    ax.plot(size["guest_diameter"] * 1e6, size["ratio_hertz"], "--", label="Hertz")
    ax.plot(size["guest_diameter"] * 1e6, size["ratio_jkr"], "-", label="JKR")
    ax.set_xscale("log")
    ax.set_xlabel("guest diameter [um]")
    ax.set_ylabel("central displacement / guest diameter")
    ax.set_title(f"Fig. 4.29: at v = {float(params.get('velocity', 'nan')):g} m/s", fontsize=10)
    ax.legend(fontsize=8)
    ax.grid(True, alpha=0.3)

    ax = axes[1, 1]
    ax.plot(hard["host_young"] / 1e9, hard["ratio_hertz"], "--", label="Hertz")
    ax.plot(hard["host_young"] / 1e9, hard["ratio_jkr"], "-", label="JKR")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("host Young's modulus [GPa]")
    ax.set_ylabel("central displacement / guest diameter")
    ax.set_title("Fig. 4.30: harder host, less deformation", fontsize=10)
    ax.legend(fontsize=8)
    ax.grid(True, alpha=0.3, which="both")

    fig.suptitle(
        f"{params.get('host', '?')} host {2 * float(params.get('host_radius', 'nan')) * 1e6:g} um, "
        f"{params.get('guest', '?')} guest {2 * float(params.get('guest_radius', 'nan')) * 1e6:g} um "
        "(appendix B)"
    )
    fig.tight_layout()
    if output is None:
        output = os.path.splitext(path)[0] + "_deformation.png"
    fig.savefig(output, dpi=80)
    plt.close(fig)
    return output, area_exponent


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("file", help="output of scenarios/coating_deformation.lua (.h5)")
    parser.add_argument("-o", "--output", help="PNG to write")
    args = parser.parse_args(argv)
    try:
        output, exponent = plot_coating_deformation(args.file, args.output)
    except g.GranuleH5Error as e:
        sys.exit(f"{parser.prog}: error: {e}")
    print(f"contact area ~ v^{exponent:.4f} over the upper half of the velocities")
    print(output)


if __name__ == "__main__":
    main()
