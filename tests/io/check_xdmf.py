#!/usr/bin/python3
"""Checks an XDMF file that granule wrote beside its HDF5 output.

usage: /usr/bin/python3 tests/io/check_xdmf.py out.xmf [--walls]

Checks out.xmf and, when it exists (it must with --walls), out_walls.xmf.
The XML must parse; every HDF DataItem must name a dataset that exists with
exactly the declared shape and a matching number type and precision; every
inline (XML) DataItem must hold as many numbers as its Dimensions say;
topologies must agree with their data; the particle grids must be the
file's snapshots, at their times, with their particle counts, and the only
grids of out.xmf (a Glyph over it must see particles only); out_walls.xmf
holds one collection 'walls' of grids named wall_<name>, and no particles.
"""
import math
import os
import sys
import xml.etree.ElementTree as ET

import h5py
import numpy as np

KINDS = {("Float", 8): "f8", ("Int", 4): "i4", ("Int", 8): "i8", ("UChar", 1): "u1"}


def fail(message):
    sys.exit(f"check_xdmf: {message}")


def dims(item):
    return tuple(int(d) for d in item.get("Dimensions").split())


def check_item(item, base, files):
    shape = dims(item)
    kind = (item.get("NumberType", "Float"), int(item.get("Precision", "4")))
    if item.get("Format") == "HDF":
        path, _, dataset = item.text.strip().partition(":")
        full = os.path.join(base, path)
        if full not in files:
            if not os.path.exists(full):
                fail(f"{path} (referenced by the XDMF) does not exist")
            files[full] = h5py.File(full, "r")
        f = files[full]
        if dataset not in f:
            fail(f"{path}:{dataset} does not exist")
        d = f[dataset]
        if d.shape != shape:
            fail(f"{path}:{dataset} has shape {d.shape}, the XDMF declares {shape}")
        want = np.dtype(KINDS[kind])
        if d.dtype.kind != want.kind or d.dtype.itemsize != want.itemsize:
            fail(f"{path}:{dataset} is {d.dtype}, the XDMF declares {kind}")
        return d[()]
    if item.get("Format") == "XML":
        values = np.array([float(v) for v in item.text.split()])
        if values.size != math.prod(shape):
            fail(f"inline data has {values.size} numbers, Dimensions say {shape}")
        if not np.all(np.isfinite(values)):
            fail("inline data is not finite")
        return values.reshape(shape)
    fail(f"unknown DataItem format {item.get('Format')!r}")


def check_grids(root, base, files):
    """Checks every Uniform grid; returns their count and the temporal collection 'particles'."""
    particles = None
    grids = 0
    for grid in root.iter("Grid"):
        if grid.get("Name") == "particles" and grid.get("CollectionType") == "Temporal":
            particles = grid
        if grid.get("GridType") != "Uniform":
            continue
        grids += 1
        topology, geometry = grid.find("Topology"), grid.find("Geometry")
        points = check_item(geometry.find("DataItem"), base, files)
        width = {"XY": 2, "XYZ": 3}[geometry.get("GeometryType")]
        if points.ndim != 2 or points.shape[1] != width:
            fail(f"grid {grid.get('Name')}: geometry is {points.shape}, not N x {width}")
        elements = int(topology.get("NumberOfElements"))
        per = int(topology.get("NodesPerElement", "1"))
        connectivity = topology.find("DataItem")
        if connectivity is not None:
            c = check_item(connectivity, base, files)
            if c.shape != (elements, per):
                fail(f"grid {grid.get('Name')}: connectivity {c.shape} vs {elements} x {per}")
            if c.min() < 0 or c.max() >= points.shape[0]:
                fail(f"grid {grid.get('Name')}: connectivity refers to missing nodes")
        elif topology.get("TopologyType") == "Polyvertex" and elements != points.shape[0]:
            fail(f"grid {grid.get('Name')}: {elements} vertices but {points.shape[0]} points")
        for attribute in grid.findall("Attribute"):
            values = check_item(attribute.find("DataItem"), base, files)
            if values.shape[0] != points.shape[0]:
                fail(f"attribute {attribute.get('Name')}: {values.shape[0]} values, {points.shape[0]} points")
    return grids, particles


def check_walls(path, base, files):
    root = ET.parse(path).getroot()
    if root.tag != "Xdmf":
        fail(f"{path}: the root element is not Xdmf")
    grids, particles = check_grids(root, base, files)
    if particles is not None:
        fail(f"{path}: holds particles")
    top = root.find("Domain").findall("Grid")
    if [g.get("Name") for g in top] != ["walls"]:
        fail(f"{path}: one top-level grid 'walls' expected, found {[g.get('Name') for g in top]}")
    uniform = [g for g in top[0].iter("Grid") if g.get("GridType") == "Uniform"]
    if not uniform or any(not g.get("Name", "").startswith("wall_") for g in uniform):
        fail(f"{path}: its wall grids must be named wall_<name>")
    return grids


def main(path, walls_required=False):
    root = ET.parse(path).getroot()
    if root.tag != "Xdmf":
        fail("the root element is not Xdmf")
    base = os.path.dirname(path)
    files = {}
    grids, particles = check_grids(root, base, files)
    top = root.find("Domain").findall("Grid")
    if [g.get("Name") for g in top] != ["particles"]:
        fail(f"{path}: grids other than the particles' ({[g.get('Name') for g in top]})")
    walls_path = os.path.splitext(path)[0] + "_walls.xmf"
    wall_grids = 0
    if os.path.exists(walls_path):
        wall_grids = check_walls(walls_path, base, files)
    elif walls_required:
        fail(f"{walls_path} does not exist")
    if particles is None:
        fail("no temporal collection named 'particles'")
    # The particle grids are the snapshots, in order, with their times.
    h5 = os.path.splitext(path)[0] + ".h5"
    with h5py.File(h5, "r") as f:
        count = int(f["snapshots"].attrs["count"])
        snaps = [f"snapshots/{k:06d}" for k in range(count)]
        snaps = [s for s in snaps if f[s]["id"].shape[0] > 0]
        children = particles.findall("Grid")
        if len(children) != len(snaps):
            fail(f"{len(children)} particle grids for {len(snaps)} non-empty snapshots")
        for child, s in zip(children, snaps):
            t = float(child.find("Time").get("Value"))
            if t != float(f[s].attrs["time"]):
                fail(f"grid {child.get('Name')} at t = {t}, snapshot {s} at {f[s].attrs['time']}")
    for f in files.values():
        f.close()
    print(f"{path}: ok, {grids} grids, {len(snaps)} snapshots; {wall_grids} wall grids")


if __name__ == "__main__":
    args = sys.argv[1:]
    if len(args) not in (1, 2) or (len(args) == 2 and args[1] != "--walls"):
        sys.exit(__doc__)
    main(args[0], walls_required=len(args) == 2)
