#!/usr/bin/python3
"""Read Granule's HDF5 output ("granule-1" layout) from Python.

As a module (the plotting tools in this directory import it):

    import granule_h5 as g
    with g.open_run("out.h5") as f:
        s = g.series(f)                 # {"time": array, "step": array, ...}
        names = g.snapshots(f)          # ["/snapshots/000000", ...]
        snap = g.snapshot(f, -1)        # {"position": (N, dim) array, ..., "time": float}

As a program:

    /usr/bin/python3 tools/granule_h5.py summary out.h5

prints the groups, each series' columns with their lengths, the snapshots with
their times, and the scene parameters (attributes of /scene/parameters).

Files are opened read-only without an HDF5 file lock, so the output of a run
that is still going can be inspected up to its last flush.
"""

import argparse
import os
import re
import sys

import h5py
import numpy as np

FORMAT = "granule-1"


class GranuleH5Error(Exception):
    """A missing file, group, dataset or column, with a message fit for the user."""


def _text(value):
    """h5py gives variable-length string datasets as bytes and attributes as str."""
    if isinstance(value, bytes):
        return value.decode("utf-8", errors="replace")
    if isinstance(value, np.ndarray) and value.dtype.kind in "SO":
        return [_text(v) for v in value.tolist()]
    return value


def open_run(path):
    """Opens a Granule output file read-only. Raises GranuleH5Error if it cannot."""
    if not os.path.exists(path):
        raise GranuleH5Error(f"{path}: no such file")
    try:
        # No lock: a running simulation may still have the file open.
        return h5py.File(path, "r", locking=False)
    except (TypeError, ValueError):  # h5py < 3.5, or HDF5 without the locking property
        os.environ.setdefault("HDF5_USE_FILE_LOCKING", "FALSE")
        try:
            return h5py.File(path, "r")
        except OSError as e:
            raise GranuleH5Error(f"{path}: cannot open as HDF5: {e}") from None
    except OSError as e:
        raise GranuleH5Error(f"{path}: cannot open as HDF5: {e}") from None


def _require_group(f, group):
    if group not in f or not isinstance(f[group], h5py.Group):
        groups = sorted("/" + k for k in f.keys() if isinstance(f[k], h5py.Group))
        raise GranuleH5Error(
            f"{f.filename}: no group '{group}' (top-level groups: {', '.join(groups) or 'none'})"
        )
    return f[group]


def series_columns(f, group="/series"):
    """Column names of a series, in the order they were declared."""
    g = _require_group(f, group)
    if "columns" in g.attrs:
        return [c for c in _text(g.attrs["columns"]) if c in g]
    return sorted(k for k, v in g.items() if isinstance(v, h5py.Dataset) and v.ndim == 1)


def series_units(f, group="/series"):
    """{column: unit} for the columns that carry a "units" (or older "unit") attribute."""
    g = _require_group(f, group)
    out = {}
    for c in series_columns(f, group):
        a = g[c].attrs
        unit = _text(a["units"]) if "units" in a else _text(a["unit"]) if "unit" in a else ""
        if unit:
            out[c] = unit
    return out


def series(f, group="/series"):
    """{column: 1-D numpy array} for every column of the series group, in declared order."""
    g = _require_group(f, group)
    return {c: g[c][:] for c in series_columns(f, group)}


def require_columns(f, group, data, wanted):
    """Raises GranuleH5Error naming the first column of `wanted` missing from `data`."""
    for c in wanted:
        if c not in data:
            raise GranuleH5Error(
                f"{f.filename}: series '{group}' has no column '{c}' "
                f"(columns: {', '.join(data) or 'none'})"
            )


def snapshots(f):
    """Group names of the complete snapshots, in order: ["/snapshots/000000", ...]."""
    if "snapshots" not in f:
        return []
    g = f["snapshots"]
    names = sorted(k for k, v in g.items() if isinstance(v, h5py.Group))
    # The writer raises "count" only once a snapshot is complete; a crash mid-snapshot can
    # leave one more group behind.
    if "count" in g.attrs:
        names = names[: int(g.attrs["count"])]
    return ["/snapshots/" + n for n in names]


def snapshot(f, index=-1):
    """One snapshot as {"id", "radius", "position", "velocity", "spin", "material", "fixed":
    arrays, "time", "step", "dimension", "name", "material_names"}; index may be negative."""
    names = snapshots(f)
    if not names:
        raise GranuleH5Error(f"{f.filename}: no snapshots")
    if not -len(names) <= index < len(names):
        raise GranuleH5Error(
            f"{f.filename}: no snapshot {index} (the file holds {len(names)}, "
            f"indices 0..{len(names) - 1} or -{len(names)}..-1)"
        )
    g = f[names[index]]
    out = {}
    for key in ("id", "radius", "position", "velocity", "spin", "material", "fixed"):
        if key not in g:
            raise GranuleH5Error(f"{f.filename}: snapshot {names[index]} has no dataset '{key}'")
        out[key] = g[key][:]
    out["fixed"] = out["fixed"].astype(bool)
    out["time"] = float(g.attrs.get("time", np.nan))
    out["step"] = int(g.attrs.get("step", -1))
    out["dimension"] = int(g.attrs.get("dimension", out["position"].shape[1]))
    out["name"] = names[index]
    names_attr = f["materials"].attrs.get("names") if "materials" in f else None
    out["material_names"] = [] if names_attr is None else list(_text(names_attr))
    return out


def text(f, path):
    """A text dataset such as /scene/source, as str."""
    if path not in f:
        raise GranuleH5Error(f"{f.filename}: no dataset '{path}'")
    return _text(f[path][()])


def walls(f):
    """{name: {attribute: value}} for the groups under /walls; {} if there are none."""
    if "walls" not in f:
        return {}
    return {
        name: {k: _text(v) for k, v in g.attrs.items()}
        for name, g in f["walls"].items()
        if isinstance(g, h5py.Group)
    }


def series_groups(f):
    """Names ("/impact", "/series", ...) of the groups that hold time series: groups with a
    "columns" attribute (granule writes one for every series)."""
    return sorted("/" + k for k, v in f.items() if isinstance(v, h5py.Group) and "columns" in v.attrs)


def parameters(f):
    """{name: value} of the scene's parameters (after -D overrides), from /scene/parameters."""
    if "scene/parameters" not in f:
        return {}
    return {k: _text(v) for k, v in f["scene/parameters"].attrs.items()}


def results(f):
    """{name: value} of the scalars the scene reported with sim:result, from /results."""
    if "results" not in f:
        return {}
    return {k: _text(v) for k, v in f["results"].attrs.items()}


# ---- shared by the figure scripts ----

SNAPSHOT_QUANTITIES = {
    # name: (unit, function(snapshot) -> 1-D array)
    "speed": ("m/s", lambda s: np.linalg.norm(s["velocity"], axis=1)),
    "radius": ("m", lambda s: s["radius"]),
    "diameter": ("m", lambda s: 2 * s["radius"]),
    "spin": ("rad/s", lambda s: s["spin"][:, 0] if s["spin"].shape[1] == 1
             else np.linalg.norm(s["spin"], axis=1)),
    "x": ("m", lambda s: s["position"][:, 0]),
    "y": ("m", lambda s: s["position"][:, 1]),
    "z": ("m", lambda s: s["position"][:, 2] if s["position"].shape[1] > 2 else None),
    "vx": ("m/s", lambda s: s["velocity"][:, 0]),
    "vy": ("m/s", lambda s: s["velocity"][:, 1]),
    "vz": ("m/s", lambda s: s["velocity"][:, 2] if s["velocity"].shape[1] > 2 else None),
}


def snapshot_quantity(snap, name):
    """One value per particle of a snapshot: speed [m/s], radius [m], diameter [m], spin [rad/s]
    (2D: about z, signed; 3D: magnitude), x, y, z [m], vx, vy, vz [m/s]. Returns (values, unit)."""
    if name not in SNAPSHOT_QUANTITIES:
        raise GranuleH5Error(
            f"unknown quantity '{name}' (one of: {', '.join(SNAPSHOT_QUANTITIES)})")
    unit, fn = SNAPSHOT_QUANTITIES[name]
    values = fn(snap)
    if values is None:
        raise GranuleH5Error(f"'{name}' needs a 3D snapshot; this one is {snap['dimension']}D")
    return np.asarray(values, dtype=float), unit


def axis_label(name, unit=""):
    """"speed [m/s]", or just "step" for a dimensionless or unitless quantity."""
    name = name.replace("_", " ")
    return f"{name} [{unit}]" if unit and unit != "-" else name


def output_path(input_path, suffix, output=None):
    """Where a figure goes: the -o given, else <input stem>_<suffix>.png beside the input."""
    if output:
        return output
    return f"{os.path.splitext(input_path)[0]}_{suffix}.png"


def column_list(text):
    """"a, b" -> ["a", "b"]; None -> None."""
    if text is None:
        return None
    return [c.strip() for c in text.split(",") if c.strip()]


NEGATIVE_NUMBER = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")


def run_tool(parser, work):
    """Runs work(args) with parsed arguments, prints the files it returns, and turns a
    GranuleH5Error into a one-line message and exit status 1."""
    # argparse takes "-1e-3" for an option, its pattern for negative numbers
    # knowing no exponent (Python 3.11): --slab -1e-3 1e-3 would be refused.
    # No tool has an option that looks like a number, so a value may be any
    # negative number.
    parser._negative_number_matcher = NEGATIVE_NUMBER
    args = parser.parse_args()
    try:
        written = work(args)
    except GranuleH5Error as e:
        sys.exit(f"{parser.prog}: error: {e}")
    for path in [written] if isinstance(written, str) else written:
        print(path)


def _format_value(v):
    v = _text(v)
    if isinstance(v, np.ndarray):
        return np.array2string(v, separator=", ")
    return repr(v) if isinstance(v, str) else str(v)


def summary(path, out=sys.stdout):
    with open_run(path) as f:
        print(f"{path}", file=out)
        for k, v in f.attrs.items():
            print(f"  {k} = {_format_value(v)}", file=out)
        if _text(f.attrs.get("format", "")) != FORMAT:
            print(f"  (not marked format={FORMAT!r}; reading anyway)", file=out)

        print("groups:", file=out)
        for name, g in f.items():
            kind = "group" if isinstance(g, h5py.Group) else f"dataset {g.shape}"
            print(f"  /{name} ({kind})", file=out)

        # A series group is one whose members are all 1-D datasets (or that lists columns).
        for name, g in f.items():
            if not isinstance(g, h5py.Group) or name == "snapshots":
                continue
            datasets = [v for v in g.values() if isinstance(v, h5py.Dataset)]
            if "columns" not in g.attrs and not (
                datasets and all(d.ndim == 1 and d.dtype.kind == "f" for d in datasets)
            ):
                continue
            units = series_units(f, "/" + name)
            print(f"series /{name}:", file=out)
            for c in series_columns(f, "/" + name):
                d = g[c]
                rng = f"  [{d[0]:.6g} .. {d[-1]:.6g}]" if d.shape[0] else ""
                unit = f" [{units[c]}]" if c in units else ""
                print(f"  {c}{unit}: {d.shape[0]} rows{rng}", file=out)

        names = snapshots(f)
        print(f"snapshots: {len(names)}", file=out)
        for n in names:
            g = f[n]
            count = g["id"].shape[0] if "id" in g else "?"
            print(
                f"  {n}: step {g.attrs.get('step', '?')}, time {g.attrs.get('time', float('nan')):.9g} s,"
                f" {count} particles",
                file=out,
            )

        if "scene/parameters" in f:
            print("scene parameters:", file=out)
            for k, v in f["scene/parameters"].attrs.items():
                print(f"  {k} = {_format_value(v)}", file=out)
        for name, w in walls(f).items():
            desc = ", ".join(f"{k}={_format_value(v)}" for k, v in w.items())
            print(f"wall {name}: {desc}", file=out)
        if "failure" in f.attrs:
            print(f"FAILURE: {_text(f.attrs['failure'])}", file=out)


def main(argv=None):
    parser = argparse.ArgumentParser(
        description="Inspect a Granule HDF5 output file.",
        epilog="example: /usr/bin/python3 tools/granule_h5.py summary out.h5",
    )
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("summary", help="groups, series, snapshots and scene parameters")
    p.add_argument("file", help="Granule output file (.h5)")
    args = parser.parse_args(argv)
    try:
        if args.command == "summary":
            summary(args.file)
    except GranuleH5Error as e:
        sys.exit(f"{parser.prog}: error: {e}")


if __name__ == "__main__":
    main()
