#!/usr/bin/python3
"""Draw the particles of a Granule snapshot in the x-y plane (3D: or x-z, y-z, a slab).

usage: /usr/bin/python3 tools/plot_pattern.py out.h5 [--index -1 | --all-every K [--gif movie.gif]]
                                              [--color-by speed] [--view xy|xz|yz]
                                              [--slab LO HI] [-o pattern.png]

Particles are circles of their true radius, coloured by speed [m/s] (or, with
--color-by, by radius [m], spin [rad/s], material or fixed, as sim:picture
does); fixed particles are dark grey in the continuous colourings. Walls described under /walls are drawn too: a cylinder
(type="cylinder", center, radius, inside; axis taken along z) as a circle -
an outline if the particles are inside it, filled grey if outside - and a plane
(type="plane", point, normal) as the line where it cuts the x-y plane through
its point, clipped to the particles' bounding box. In 3D the particles are
projected onto x-y (looking along -z), or with --view onto x-z (looking along
+y) or y-z (looking along -x), the nearest drawn last, as sim:picture does; a
cylinder whose axis lies across the view is drawn as the band it projects to.
--slab LO HI keeps the particles whose centre lies in [LO, HI] m along the
viewing axis (z, y or x).

--index I draws snapshot I (negative counts from the end; default -1, the last).
--all-every K draws every K-th snapshot and the last, one PNG each, named
<output stem>_NNNNNN.png, with one speed scale and one view for all, so that the
frames can be put together into an animation; --gif FILE puts them together
into an animated GIF (10 frames per second).
Writes PNGs (default: <file>_pattern.png next to the input) and prints their paths.
"""

import argparse
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import EllipseCollection  # noqa: E402
from matplotlib.patches import Circle  # noqa: E402
from matplotlib.ticker import MaxNLocator  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import granule_h5 as g  # noqa: E402

FIXED_COLOUR = "0.25"
VIEWS = ("xy", "xz", "yz")
# Rows: the picture's right, up and towards-the-viewer directions (as sim:picture).
VIEW_MATRIX = {"xy": np.eye(3),
               "xz": np.array([[1.0, 0, 0], [0, 0, 1], [0, -1, 0]]),
               "yz": np.array([[0.0, 1, 0], [0, 0, 1], [1, 0, 0]])}
VIEW_AXIS = {"xy": 2, "xz": 1, "yz": 0}  # the axis looked along, for --slab
AXIS_LABELS = {"xy": ("x [m]", "y [m]"), "xz": ("x [m]", "z [m]"), "yz": ("y [m]", "z [m]")}


def in_view(snap, walls, view, slab=None):
    """The snapshot and walls in the view's coordinates (right, up, towards the viewer),
    keeping the particles in the slab."""
    pos = snap["position"]
    if pos.shape[1] == 2:
        if view != "xy" or slab is not None:
            raise g.GranuleH5Error("--view and --slab are for 3D output")
        return snap, walls
    n = len(snap["radius"])
    keep = np.ones(n, dtype=bool)
    if slab is not None:
        along = pos[:, VIEW_AXIS[view]]
        keep = (along >= slab[0]) & (along <= slab[1])
    m = VIEW_MATRIX[view]
    out = dict(snap)
    for key, value in snap.items():
        if isinstance(value, np.ndarray) and value.ndim >= 1 and value.shape[0] == n:
            out[key] = value[keep]
    out["position"] = pos[keep] @ m.T
    moved = {}
    for name, w in walls.items():
        w = dict(w)
        for key in ("point", "normal", "center", "axis"):
            if key in w:
                w[key] = m @ np.asarray(w[key], dtype=float)
        if w.get("type") == "cylinder" and "axis" not in w:
            w["axis"] = m @ np.array([0.0, 0.0, 1.0])
        moved[name] = w
    return out, moved


def _circles(ax, xy, radius, **kwargs):
    """Circles with radii in data units, whatever the zoom."""
    d = 2 * np.asarray(radius)
    try:
        c = EllipseCollection(d, d, np.zeros_like(d), units="xy", offsets=xy,
                              offset_transform=ax.transData, **kwargs)
    except TypeError:  # matplotlib before 3.6 calls it transOffset
        c = EllipseCollection(d, d, np.zeros_like(d), units="xy", offsets=xy,
                              transOffset=ax.transData, **kwargs)
    ax.add_collection(c)
    return c


def clip_line(point, direction, box):
    """The segment of the infinite line point + t*direction inside box = (x0, x1, y0, y1),
    or None if it misses the box."""
    lo, hi = -math.inf, math.inf
    for k, (bmin, bmax) in enumerate(((box[0], box[1]), (box[2], box[3]))):
        p, d = point[k], direction[k]
        if abs(d) < 1e-300:
            if p < bmin or p > bmax:
                return None
            continue
        t0, t1 = sorted(((bmin - p) / d, (bmax - p) / d))
        lo, hi = max(lo, t0), min(hi, t1)
    if lo > hi:
        return None
    return [point[0] + lo * direction[0], point[0] + hi * direction[0]], [
        point[1] + lo * direction[1],
        point[1] + hi * direction[1],
    ]


def _wall_extent(walls):
    """Bounding box of the cylinders, which the view should include."""
    boxes = []
    for w in walls.values():
        if w.get("type") == "cylinder" and "center" in w and "radius" in w:
            c, r = np.asarray(w["center"], dtype=float), float(w["radius"])
            boxes.append((c[0] - r, c[0] + r, c[1] - r, c[1] + r))
    return boxes


def _draw_walls(ax, walls, particle_box):
    for name, w in walls.items():
        kind = w.get("type")
        if kind == "cylinder":
            try:
                c, r = np.asarray(w["center"], dtype=float), float(w["radius"])
            except KeyError as e:
                print(f"note: wall '{name}' lacks {e}; not drawn", file=sys.stderr)
                continue
            a = np.asarray(w.get("axis", (0.0, 0.0, 1.0)), dtype=float)
            if len(a) > 2 and math.hypot(a[0], a[1]) > 1e-9 * np.linalg.norm(a):
                # The axis lies across the view: the band of half-width r about it.
                u = a[:2] / math.hypot(a[0], a[1])
                for side in (1, -1):
                    seg = clip_line((c[0] - side * u[1] * r, c[1] + side * u[0] * r), u, particle_box)
                    if seg is not None:
                        ax.plot(seg[0], seg[1], color="k", lw=1.2, zorder=3)
                continue
            inside = int(w.get("inside", 1))
            ax.add_patch(Circle((c[0], c[1]), r, fill=not inside, facecolor="0.85",
                                edgecolor="k", lw=1.2, zorder=0 if not inside else 3))
        elif kind == "plane":
            try:
                p, n = np.asarray(w["point"], dtype=float), np.asarray(w["normal"], dtype=float)
            except KeyError as e:
                print(f"note: wall '{name}' lacks {e}; not drawn", file=sys.stderr)
                continue
            if math.hypot(n[0], n[1]) < 1e-9 * np.linalg.norm(n):
                continue  # parallel to the x-y plane: no line to draw
            seg = clip_line(p[:2], (-n[1], n[0]), particle_box)
            if seg is not None:
                ax.plot(seg[0], seg[1], color="k", lw=1.2, zorder=3)
        else:
            print(f"note: wall '{name}' has unknown type {kind!r}; not drawn", file=sys.stderr)


def _particle_box(snaps):
    x0 = min(float(np.min(s["position"][:, 0] - s["radius"])) for s in snaps)
    x1 = max(float(np.max(s["position"][:, 0] + s["radius"])) for s in snaps)
    y0 = min(float(np.min(s["position"][:, 1] - s["radius"])) for s in snaps)
    y1 = max(float(np.max(s["position"][:, 1] + s["radius"])) for s in snaps)
    return x0, x1, y0, y1


CATEGORY_COLOURS = plt.get_cmap("tab10").colors  # the same ten as sim:picture


def _draw(snap, walls, view, particle_box, scale, path, output, color_by="speed", axis_labels=AXIS_LABELS["xy"]):
    pos, radius = snap["position"], snap["radius"]
    order = np.argsort(pos[:, 2]) if pos.shape[1] > 2 else np.arange(len(radius))
    fixed = snap["fixed"][order]
    xy, r = pos[order, :2], radius[order]

    fig, ax = plt.subplots(figsize=(7, 6.2))
    if color_by in ("material", "fixed"):
        if color_by == "material":
            codes = snap["material"][order]
            names = snap["material_names"]
            labels = {m: names[m] if m < len(names) else f"material {m}" for m in np.unique(codes)}
        else:
            codes = fixed.astype(int)
            labels = {0: "free", 1: "fixed"}
        colours = [FIXED_COLOUR if color_by == "fixed" and c == 1
                   else CATEGORY_COLOURS[c % len(CATEGORY_COLOURS)] for c in codes]
        _circles(ax, xy, r, facecolors=colours, edgecolors="none", zorder=2)
        for c, label in labels.items():  # legend entries without drawing anything
            ax.scatter([], [], color=FIXED_COLOUR if color_by == "fixed" and c == 1
                       else CATEGORY_COLOURS[c % len(CATEGORY_COLOURS)], label=label)
        ax.legend(fontsize=8, loc="upper right")
    else:
        values, unit = g.snapshot_quantity(snap, color_by)
        v = values[order]
        grey = fixed if color_by != "radius" else np.zeros_like(fixed)
        moving = _circles(ax, xy[~grey], r[~grey], cmap="viridis", edgecolors="none", zorder=2)
        moving.set_array(v[~grey])
        moving.set_clim(*scale)
        if grey.any():
            _circles(ax, xy[grey], r[grey], facecolors=FIXED_COLOUR, edgecolors="none", zorder=2)
        fig.colorbar(moving, ax=ax, label=g.axis_label(color_by, unit))
    _draw_walls(ax, walls, particle_box)
    ax.set_xlim(view[0], view[1])
    ax.set_ylim(view[2], view[3])
    ax.set_aspect("equal")
    ax.xaxis.set_major_locator(MaxNLocator(6))  # metre tick labels are long
    ax.yaxis.set_major_locator(MaxNLocator(6))
    ax.set_xlabel(axis_labels[0])
    ax.set_ylabel(axis_labels[1])
    ax.set_title(
        f"{os.path.basename(path)}  t = {snap['time']:.6g} s  (step {snap['step']}, "
        f"{len(radius)} particles, {int(fixed.sum())} fixed)",
        fontsize=9,
    )
    fig.tight_layout()
    fig.savefig(output, dpi=130)
    plt.close(fig)


COLOR_BY = ("speed", "radius", "spin", "material", "fixed")


def plot_pattern(path, index=-1, every=None, output=None, color_by="speed", view_name="xy", slab=None,
                 gif=None):
    if color_by not in COLOR_BY:
        raise g.GranuleH5Error(f"--color-by must be one of {', '.join(COLOR_BY)}")
    if view_name not in VIEWS:
        raise g.GranuleH5Error(f"--view must be one of {', '.join(VIEWS)}")
    if slab is not None and not (np.all(np.isfinite(slab)) and slab[0] < slab[1]):
        raise g.GranuleH5Error(f"--slab needs LO < HI, got {slab[0]} {slab[1]}")
    if gif is not None and every is None:
        raise g.GranuleH5Error("--gif puts the frames of --all-every together: give --all-every K")
    with g.open_run(path) as f:
        names = g.snapshots(f)
        if not names:
            raise g.GranuleH5Error(f"{path}: no snapshots")
        if every is not None:
            if every < 1:
                raise g.GranuleH5Error(f"--all-every must be 1 or more, got {every}")
            indices = list(range(0, len(names), every))
            if indices[-1] != len(names) - 1:
                indices.append(len(names) - 1)
        else:
            indices = [index]
        snaps = [g.snapshot(f, i) for i in indices]
        walls = g.walls(f)
    viewed = [in_view(s, walls, view_name, slab) for s in snaps]
    snaps = [v[0] for v in viewed]
    walls = viewed[0][1] if viewed else walls

    drawable = [s for s in snaps if len(s["radius"])]
    if not drawable:
        raise g.GranuleH5Error(f"{path}: the chosen snapshots hold no particles")
    particle_box = _particle_box(drawable)
    boxes = [particle_box] + _wall_extent(walls)
    view = [min(b[0] for b in boxes), max(b[1] for b in boxes),
            min(b[2] for b in boxes), max(b[3] for b in boxes)]
    pad = 0.03 * max(view[1] - view[0], view[3] - view[2], 1e-12)
    view = [view[0] - pad, view[1] + pad, view[2] - pad, view[3] + pad]
    # One colour scale for every frame, as sim:picture chooses it for one.
    scale = (0.0, 1e-12)
    if color_by in ("speed", "radius", "spin"):
        values = [g.snapshot_quantity(s, color_by)[0][s["fixed"] == 0 if color_by != "radius"
                                                       else slice(None)] for s in drawable]
        values = [v for v in values if v.size]
        lo = min((float(v.min()) for v in values), default=0.0)
        hi = max((float(v.max()) for v in values), default=0.0)
        if color_by == "speed":
            lo = 0.0
        if color_by == "spin" and drawable[0]["dimension"] == 2:
            lo, hi = -max(abs(lo), abs(hi)), max(abs(lo), abs(hi))
        scale = (lo, hi if hi > lo else lo + 1e-12)

    base = os.path.splitext(output or os.path.splitext(path)[0] + "_pattern.png")
    written = []
    for s in snaps:
        if not len(s["radius"]):
            print(f"note: {s['name']} holds no particles; skipped", file=sys.stderr)
            continue
        out = base[0] + (base[1] or ".png")
        if every is not None:
            out = f"{base[0]}_{s['name'].rsplit('/', 1)[-1]}{base[1] or '.png'}"
        _draw(s, walls, view, particle_box, scale, path, out, color_by, AXIS_LABELS[view_name])
        written.append(out)
    if gif is not None and written:
        from PIL import Image  # Debian: python3-pil, which python3-matplotlib brings
        frames = [Image.open(p).convert("P", palette=Image.Palette.ADAPTIVE) for p in written]
        frames[0].save(gif, save_all=True, append_images=frames[1:], duration=100, loop=0)
        written.append(gif)
    return written


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("file", help="Granule output file (.h5)")
    which = parser.add_mutually_exclusive_group()
    which.add_argument("--index", type=int, default=-1,
                       help="snapshot to draw; negative counts from the end (default -1)")
    which.add_argument("--all-every", type=int, metavar="K",
                       help="draw every K-th snapshot (and the last), one PNG each")
    parser.add_argument("--color-by", default="speed", choices=COLOR_BY,
                        help="what the colour shows (default speed)")
    parser.add_argument("--view", default="xy", choices=VIEWS,
                        help="3D: xy (along -z, default), xz (along +y) or yz (along -x)")
    parser.add_argument("--slab", type=float, nargs=2, metavar=("LO", "HI"),
                        help="3D: only particles whose centre lies in [LO, HI] m along the viewing axis")
    parser.add_argument("--gif", help="with --all-every: also an animated GIF of the frames")
    parser.add_argument("-o", "--output", help="PNG to write (a stem for --all-every)")
    g.run_tool(parser, lambda a: plot_pattern(a.file, a.index, a.all_every, a.output, a.color_by, a.view,
                                              a.slab, a.gif))


if __name__ == "__main__":
    main()
