"""Opens granule's XDMF output in ParaView, headless, as the README's recipe does.

usage: pvbatch tests/io/paraview_check.py OUT.xmf SCREENSHOT.png

For each of ParaView's three XDMF readers (XDMFReader, Xdmf3ReaderS,
Xdmf3ReaderT) it opens OUT.xmf at its last time, applies the recipe (Glyph:
Sphere, Scale Array radius, Scale Factor 2) and checks that the glyphs' bounds
are the particles' (position -+ radius, from the HDF5 file beside it); opens
OUT_walls.xmf and checks that its bounds are the walls' inline geometry; and
saves a screenshot of particles and walls that must not be blank.

The Xdmf3 readers of ParaView 5.11 resolve the HDF5 reference against the
directory of the path they are given and take a bare file name ("out.xmf")
for that directory; they get the absolute path here, as ParaView's file
dialog gives them. The XDMF reader gets the relative path.
"""
import os
import sys
import xml.etree.ElementTree as ET

import h5py
import numpy as np
from paraview.simple import (GetActiveViewOrCreate, Glyph, Render, SaveScreenshot, Show,
                             XDMFReader, Xdmf3ReaderS, Xdmf3ReaderT)


def fail(message):
    print(f"paraview_check: {message}")
    sys.exit(1)


def particle_bounds(h5_path):
    with h5py.File(h5_path, "r") as f:
        count = int(f["snapshots"].attrs["count"])
        last = f[f"snapshots/{count - 1:06d}"]
        x = last["position"][()]
        r = last["radius"][()]
        time = float(last.attrs["time"])
    if x.shape[1] == 2:
        x = np.column_stack([x, np.zeros(len(x))])
    lo = (x - r[:, None]).min(axis=0)
    hi = (x + r[:, None]).max(axis=0)
    if x.shape[1] == 3 and np.all(x[:, 2] == 0):
        lo[2], hi[2] = -r.max(), r.max()  # 2D: the glyphs are spheres in z = 0
    return lo, hi, time


def inline_bounds(walls_path):
    points = []
    for item in ET.parse(walls_path).getroot().iter("Geometry"):
        data = item.find("DataItem")
        points.append(np.array([float(v) for v in data.text.split()]).reshape(-1, 3))
    p = np.vstack(points)
    return p.min(axis=0), p.max(axis=0)


def as_lo_hi(b):
    return np.array(b[0::2]), np.array(b[1::2])


def close(got, want, scale, what):
    lo, hi = got
    wlo, whi = want
    tol = 2e-3 * scale
    if np.any(np.abs(lo - wlo) > tol) or np.any(np.abs(hi - whi) > tol):
        fail(f"{what}: bounds {lo}..{hi}, expected {wlo}..{whi} (tolerance {tol:.3g} m)")


def open_reader(kind, path):
    if kind == "XDMFReader":
        return XDMFReader(FileNames=[path])
    reader = {"Xdmf3ReaderS": Xdmf3ReaderS, "Xdmf3ReaderT": Xdmf3ReaderT}[kind]
    return reader(FileName=[os.path.abspath(path)])


def main(xmf, screenshot):
    h5 = os.path.splitext(xmf)[0] + ".h5"
    walls_xmf = os.path.splitext(xmf)[0] + "_walls.xmf"
    lo, hi, time = particle_bounds(h5)
    scale = float(np.max(hi - lo))
    glyphs = None
    for kind in ("XDMFReader", "Xdmf3ReaderS", "Xdmf3ReaderT"):
        reader = open_reader(kind, xmf)
        times = list(reader.TimestepValues or [])
        if not times or abs(times[-1] - time) > 1e-12 * max(1.0, abs(time)):
            fail(f"{kind}: last time {times[-1] if times else None}, the HDF5 file's {time}")
        glyph = Glyph(Input=reader, GlyphType="Sphere")
        glyph.ScaleArray = ["POINTS", "radius"]
        glyph.ScaleFactor = 2.0
        glyph.GlyphMode = "All Points"
        glyph.UpdatePipeline(time)
        close(as_lo_hi(glyph.GetDataInformation().GetBounds()), (lo, hi), scale, f"{kind} glyphs")
        print(f"{kind}: {reader.GetDataInformation().GetNumberOfPoints()} particles, glyph bounds ok")
        if glyphs is None:
            glyphs = glyph
    walls = None
    if os.path.exists(walls_xmf):
        want = inline_bounds(walls_xmf)
        for kind in ("XDMFReader", "Xdmf3ReaderS"):
            reader = open_reader(kind, walls_xmf)
            reader.UpdatePipeline(time)
            close(as_lo_hi(reader.GetDataInformation().GetBounds()), want, scale, f"{kind} walls")
            print(f"{kind}: walls bounds ok")
            if walls is None:
                walls = reader
    view = GetActiveViewOrCreate("RenderView")
    view.ViewSize = [400, 300]
    view.ViewTime = time
    Show(glyphs, view)
    if walls is not None:
        display = Show(walls, view)
        display.SetRepresentationType("Wireframe")
    view.ResetCamera()
    Render(view)
    SaveScreenshot(screenshot, view, ImageResolution=[400, 300])
    # Not blank: the particles' colour covers a visible part of the picture.
    import matplotlib.image
    image = matplotlib.image.imread(screenshot)[..., :3]
    background = image[0, 0]
    drawn = float(np.mean(np.any(np.abs(image - background) > 0.05, axis=-1)))
    if drawn < 0.005:
        fail(f"{screenshot} is blank ({drawn:.2%} of its pixels differ from the background)")
    print(f"screenshot {screenshot}: {drawn:.1%} of its pixels drawn")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        fail(__doc__)
    main(sys.argv[1], sys.argv[2])
