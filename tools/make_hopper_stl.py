#!/usr/bin/python3
"""Writes a conical hopper as a binary STL: a vertical bin (cylinder) on top of
a cone that narrows to a flat circular outlet at z = 0, open at the top and
at the outlet, in metres, axis z.

    /usr/bin/python3 tools/make_hopper_stl.py -o hopper.stl \
        --bin-radius 0.03 --bin-height 0.04 --outlet-radius 0.008 --half-angle 30

The cone's half-angle (from the vertical axis) sets its height:
(bin_radius - outlet_radius) / tan(half_angle). Each ring has --segments
vertices; each band of the surface is split into --bands rings in height, so
the triangles stay near-equilateral.
"""
import argparse
import math
import struct
import sys

import numpy as np


def rings_surface(radii, heights, segments):
    """Triangles of the surface of revolution through the rings (radius, z)."""
    a = np.linspace(0.0, 2 * math.pi, segments, endpoint=False)
    ring = [np.stack([r * np.cos(a), r * np.sin(a), np.full(segments, z)], axis=1)
            for r, z in zip(radii, heights)]
    tris = []
    for lo, hi in zip(ring[:-1], ring[1:]):
        for k in range(segments):
            k1 = (k + 1) % segments
            tris.append((lo[k], lo[k1], hi[k1]))
            tris.append((lo[k], hi[k1], hi[k]))
    return np.array(tris)


def write_binary_stl(path, tris):
    with open(path, "wb") as f:
        f.write(b"granule hopper".ljust(80, b" "))
        f.write(struct.pack("<I", len(tris)))
        for t in tris:
            n = np.cross(t[1] - t[0], t[2] - t[0])
            n = n / np.linalg.norm(n)
            f.write(struct.pack("<12fH", *n, *t[0], *t[1], *t[2], 0))


def main(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("-o", "--output", required=True)
    p.add_argument("--bin-radius", type=float, default=0.03, help="m")
    p.add_argument("--bin-height", type=float, default=0.04, help="m, the cylinder above the cone")
    p.add_argument("--outlet-radius", type=float, default=0.008, help="m")
    p.add_argument("--half-angle", type=float, default=30.0, help="degrees from the axis")
    p.add_argument("--segments", type=int, default=48)
    p.add_argument("--bands", type=int, default=8, help="rings in the cone's height")
    a = p.parse_args(argv)
    if not (0 < a.outlet_radius < a.bin_radius):
        p.error("need 0 < outlet radius < bin radius")
    if not (0 < a.half_angle < 90):
        p.error("the half-angle must lie between 0 and 90 degrees")
    if a.segments < 3 or a.bands < 1 or a.bin_height < 0:
        p.error("need segments >= 3, bands >= 1, bin height >= 0")
    cone_h = (a.bin_radius - a.outlet_radius) / math.tan(math.radians(a.half_angle))
    radii = list(np.linspace(a.outlet_radius, a.bin_radius, a.bands + 1))
    heights = list(np.linspace(0.0, cone_h, a.bands + 1))
    if a.bin_height > 0:
        n_bin = max(1, int(round(a.bin_height / (cone_h / a.bands))))
        for k in range(1, n_bin + 1):
            radii.append(a.bin_radius)
            heights.append(cone_h + a.bin_height * k / n_bin)
    tris = rings_surface(radii, heights, a.segments)
    write_binary_stl(a.output, tris)
    print(f"{a.output}: {len(tris)} triangles; cone height {cone_h:.6g} m, "
          f"top at z = {heights[-1]:.6g} m")


if __name__ == "__main__":
    main(sys.argv[1:])
