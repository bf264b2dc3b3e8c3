#!/usr/bin/python3
"""Draw the fragments of an agglomerate test as in dissertation Figs. 7.14-7.34.

usage: /usr/bin/python3 tools/plot_agglomerate.py out.h5 [--graph contacts|bonds] [--index -1]
                                                   [--debris 0.025] [--title TEXT] [-o clusters.png]

Reads a snapshot (default the last) and the per-particle fragment labels that
the agglomerate tests write to the series /clusters (id, label, mass_fraction,
label_bonds, mass_fraction_bonds; label 1 = the largest fragment). Fragments of
at least --debris of the initial mass are drawn in colour (the largest black,
as the dissertation's "surviving cluster"), debris (smaller fragments) grey,
fines (below 0.2 %) light grey. The host particle (material "host") is drawn as
an outline, the walls (their final heights from /results) as lines. 3D scenes
are projected onto the x-y plane (the impact axis is y), the highest z drawn
last. Axes in micrometres, a scale bar, and a legend of the colours.

--graph bonds uses the clusters of the surviving initial bonds instead of the
contact graph (pieces pressed together between two walls stay apart).
A preparation output (no /clusters) is drawn in one colour: --index 0 gives the
random start (Fig. 7.10), -1 the agglomerate (Fig. 7.12).

Writes a PNG (default: <file>_clusters.png next to the input) and prints its path.
"""

import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.patches import Circle, Patch  # noqa: E402
from matplotlib.ticker import FuncFormatter  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import granule_h5 as g  # noqa: E402
from plot_pattern import _circles  # noqa: E402

FRAGMENT_COLOURS = ["0.05", "tab:blue", "tab:red", "tab:green", "tab:orange", "tab:purple",
                    "tab:brown", "tab:pink", "tab:olive", "tab:cyan"]
DEBRIS_COLOUR, FINES_COLOUR, PRIMARY_COLOUR = "0.62", "0.85", "tab:blue"
FINES = 0.002  # 7.4: fines are clusters under 0.2 % of the initial mass


def load(path, index=-1, graph="contacts"):
    """The snapshot plus, per particle, its fragment label and mass fraction (NaN if none)."""
    if graph not in ("contacts", "bonds"):
        raise g.GranuleH5Error(f"--graph must be 'contacts' or 'bonds', got {graph!r}")
    with g.open_run(path) as f:
        snap = g.snapshot(f, index)
        walls = g.walls(f)
        results = {k: float(v) for k, v in f["results"].attrs.items()} if "results" in f else {}
        n = len(snap["id"])
        label, fraction = np.full(n, -1), np.full(n, np.nan)
        if "clusters" in f:
            c = g.series(f, "/clusters")
            suffix = "_bonds" if graph == "bonds" else ""
            g.require_columns(f, "/clusters", c, ["id", "label" + suffix, "mass_fraction" + suffix])
            where = {int(i): k for k, i in enumerate(snap["id"])}
            for i, lab, frac in zip(c["id"], c["label" + suffix], c["mass_fraction" + suffix]):
                k = where.get(int(i))
                if k is not None:
                    label[k], fraction[k] = int(lab), float(frac)
    names = snap["material_names"]
    material = np.array([names[m] if 0 <= m < len(names) else "?" for m in snap["material"]])
    return snap, walls, results, label, fraction, material


def colours(label, fraction, debris):
    """A colour per particle: fragments >= debris by rank, debris grey, fines light grey."""
    out = []
    for lab, frac in zip(label, fraction):
        if lab < 0 or np.isnan(frac):
            out.append(PRIMARY_COLOUR)
        elif frac >= debris:
            out.append(FRAGMENT_COLOURS[(lab - 1) % len(FRAGMENT_COLOURS)])
        elif frac < FINES:
            out.append(FINES_COLOUR)
        else:
            out.append(DEBRIS_COLOUR)
    return out


def scale_bar_length(span):
    """A round length (1, 2 or 5 times a power of ten, m) about a fifth of span."""
    target = span / 5
    power = 10.0 ** np.floor(np.log10(target))
    return max(m * power for m in (1, 2, 5) if m * power <= target)


def legend_handles(label, fraction, debris, has_host):
    """What the colours mean, for the classes present."""
    handles = []
    ranked = sorted({int(lab) for lab, frac in zip(label, fraction)
                     if lab > 0 and not np.isnan(frac) and frac >= debris})
    for lab in ranked[:4]:
        name = "largest fragment" if lab == 1 else f"fragment {lab}"
        handles.append(Patch(color=FRAGMENT_COLOURS[(lab - 1) % len(FRAGMENT_COLOURS)], label=name))
    if len(ranked) > 4:
        handles.append(Patch(color="white", label=f"(+{len(ranked) - 4} more fragments)"))
    if any(FINES <= frac < debris for frac in fraction if not np.isnan(frac)):
        handles.append(Patch(color=DEBRIS_COLOUR, label=f"debris (< {100 * debris:g} % of mass)"))
    if any(frac < FINES for frac in fraction if not np.isnan(frac)):
        handles.append(Patch(color=FINES_COLOUR, label=f"fines (< {100 * FINES:g} %)"))
    if (label < 0).any():
        handles.append(Patch(color=PRIMARY_COLOUR, label="primary (no fragment data)"))
    if has_host:
        handles.append(Patch(facecolor="none", edgecolor="k", label="host particle"))
    return handles


def draw(ax, path, index=-1, graph="contacts", debris=0.025, title=None, legend=False):
    """Draws one file's fragments on ax; returns the results attributes."""
    snap, walls, results, label, fraction, material = load(path, index, graph)
    pos, radius = snap["position"], snap["radius"]
    primary = material != "host"
    if not primary.any():
        raise g.GranuleH5Error(f"{path}: no primaries in the snapshot")
    order = np.argsort(pos[:, 2]) if pos.shape[1] > 2 else np.arange(len(radius))
    order = order[primary[order]]
    col = colours(label[order], fraction[order], debris)
    _circles(ax, pos[order, :2], radius[order], facecolors=col, edgecolors="white", linewidths=0.2, zorder=2)
    lo = (pos[primary, :2] - radius[primary, None]).min(axis=0)
    hi = (pos[primary, :2] + radius[primary, None]).max(axis=0)
    pad = 0.08 * float(max(hi - lo))
    x0, x1, y0, y1 = lo[0] - pad, hi[0] + pad, lo[1] - pad, hi[1] + pad
    for k in np.flatnonzero(~primary):  # the host: an outline, clipped by the view
        ax.add_patch(Circle(pos[k, :2], radius[k], fill=False, edgecolor="k", lw=1.2, zorder=3))
    # Walls across y: the tests record their final heights in /results.
    heights = [results[k] for k in ("wall_bottom_y", "wall_top_y") if k in results]
    heights += [float(np.asarray(w["point"])[1]) for w in walls.values()
                if w.get("type") == "plane" and abs(float(np.asarray(w["normal"])[1])) > 0.5]
    for y in heights:
        ax.axhline(y, color="k", lw=1.6, zorder=3)
        y0, y1 = min(y0, y - pad), max(y1, y + pad)
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("equal")
    micrometres = FuncFormatter(lambda value, _: f"{value * 1e6:g}")
    ax.xaxis.set_major_formatter(micrometres)
    ax.yaxis.set_major_formatter(micrometres)
    ax.tick_params(labelsize=6)
    ax.set_xlabel("x [um]", fontsize=7)
    ax.set_ylabel("y [um]", fontsize=7)
    bar = scale_bar_length(x1 - x0)
    bx, by = x0 + 0.05 * (x1 - x0), y0 + 0.05 * (y1 - y0)
    ax.plot([bx, bx + bar], [by, by], color="k", lw=2.5, zorder=4, solid_capstyle="butt")
    ax.text(bx + bar / 2, by + 0.015 * (y1 - y0), f"{bar * 1e6:g} um", ha="center", va="bottom",
            fontsize=6, zorder=4)
    if legend:
        ax.legend(handles=legend_handles(label[primary], fraction[primary], debris, (~primary).any()),
                  fontsize=6, loc="upper center", bbox_to_anchor=(0.5, -0.3), ncol=2, frameon=False)
    if title is None:
        title = os.path.basename(path)
        if "velocity" in results:
            title = f"v = {results['velocity']:g} m/s, Gamma = {results.get('surface_energy', float('nan')):g} J/m$^2$"
    if "damage_ratio" in results:
        key = "_bonds" if graph == "bonds" else ""
        debris_ratio = results.get("debris_ratio" + key, results.get("debris_ratio", float("nan")))
        title += f"\ndamage {results['damage_ratio']:.2f}, debris {debris_ratio:.2f}"
    ax.set_title(title, fontsize=8)
    return results


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("file", help="output of an agglomerate test or preparation (.h5)")
    parser.add_argument("--index", type=int, default=-1, help="snapshot (default -1, the last)")
    parser.add_argument("--graph", default="contacts", choices=("contacts", "bonds"),
                        help="fragments of the contact graph (7.4) or of the surviving initial bonds")
    parser.add_argument("--debris", type=float, default=0.025,
                        help="mass fraction below which a fragment is debris (default 0.025)")
    parser.add_argument("--title", help="title (default: velocity and Gamma from /results, or the file name)")
    parser.add_argument("-o", "--output", help="PNG to write")
    args = parser.parse_args(argv)
    output = args.output or os.path.splitext(args.file)[0] + "_clusters.png"
    try:
        fig, ax = plt.subplots(figsize=(4.6, 4.8))
        draw(ax, args.file, args.index, args.graph, args.debris, args.title, legend=True)
        fig.tight_layout()
        fig.savefig(output, dpi=120, bbox_inches="tight")
        plt.close(fig)
    except g.GranuleH5Error as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    print(output)
    return 0


if __name__ == "__main__":
    sys.exit(main())
