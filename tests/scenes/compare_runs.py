#!/usr/bin/python3
"""Compares two Granule output files as a restart must leave them: every
snapshot (its step, time and arrays), every series column, /results and the
diagnostics' groups, bit for bit. Exits 1 naming the first difference.

    compare_runs.py whole.h5 restarted.h5
"""
import sys

import h5py
import numpy as np

# Provenance that legitimately differs between two runs of one scene.
IGNORED_ATTRIBUTES = {"created", "file_id"}


def items(f):
    """Every dataset and attribute of the file, keyed by path, except the provenance."""
    out = {}

    def visit(name, obj):
        for key, value in obj.attrs.items():
            if key not in IGNORED_ATTRIBUTES:
                out[f"{name}@{key}"] = value
        if isinstance(obj, h5py.Dataset):
            out[name] = obj[()]

    for key, value in f.attrs.items():
        if key not in IGNORED_ATTRIBUTES:
            out[f"/@{key}"] = value
    f.visititems(visit)
    return out


def same(a, b):
    a, b = np.asarray(a), np.asarray(b)
    if a.dtype.kind in "fiub" and b.dtype.kind in "fiub":
        return a.shape == b.shape and a.dtype == b.dtype and a.tobytes() == b.tobytes()
    return a.shape == b.shape and all(x == y for x, y in zip(a.ravel().tolist(), b.ravel().tolist()))


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    with h5py.File(sys.argv[1], "r") as fa, h5py.File(sys.argv[2], "r") as fb:
        a, b = items(fa), items(fb)
        # The scene's source and path are the same scene; the output paths differ by name.
        for path in sorted(set(a) | set(b)):
            if path not in a or path not in b:
                print(f"{path}: only in {sys.argv[1] if path in a else sys.argv[2]}")
                sys.exit(1)
            if not same(a[path], b[path]):
                print(f"{path}: differs ({np.asarray(a[path]).ravel()[:4]} ... against "
                      f"{np.asarray(b[path]).ravel()[:4]} ...)")
                sys.exit(1)
        snapshots = fa["snapshots"].attrs["count"] if "snapshots" in fa else 0
        print(f"identical: {len(a)} datasets and attributes, {snapshots} snapshots")


if __name__ == "__main__":
    main()
