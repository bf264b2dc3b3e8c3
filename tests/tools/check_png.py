#!/usr/bin/python3
"""Checks that each argument is a PNG figure with something drawn in it.

usage: /usr/bin/python3 tests/tools/check_png.py fig.png [...]
"""
import sys

import matplotlib.image as mpimg
import numpy as np

for path in sys.argv[1:]:
    with open(path, "rb") as f:
        if f.read(8) != b"\x89PNG\r\n\x1a\n":
            sys.exit(f"{path}: not a PNG file")
    image = mpimg.imread(path)
    if image.ndim != 3 or image.shape[0] < 100 or image.shape[1] < 100:
        sys.exit(f"{path}: unexpected image shape {image.shape}")
    # A figure with axes and data has many distinct colours; a blank one has one.
    colours = np.unique((image[..., :3] * 255).astype(np.uint8).reshape(-1, 3), axis=0)
    if len(colours) < 8:
        sys.exit(f"{path}: only {len(colours)} colours: nothing drawn")
    print(f"{path}: {image.shape[1]} x {image.shape[0]}, {len(colours)} colours")
