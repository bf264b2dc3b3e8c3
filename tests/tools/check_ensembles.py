#!/usr/bin/python3
"""tools/mechanofusion_ensembles.py's bookkeeping on made-up tables: a table keeps
the cases it holds that WORK lacks, a study borrows another's shared cases once
(never a case it ran itself; the slab study borrows the 2D cases with the
column it varies set), and exponents are fitted only to seeds that have
every value of the study. Prints "ensembles check ok"; any failed check exits 1.
usage: check_ensembles.py SOURCE_DIR WORK_DIR"""
import csv
import os
import shutil
import sys
import types

source, work = sys.argv[1:3]
sys.path.insert(0, os.path.join(source, "tools"))
import mechanofusion_ensembles as me  # noqa: E402

data = os.path.join(work, "ensembles_data")
shutil.rmtree(data, ignore_errors=True)
os.makedirs(os.path.join(work, "ensembles_work", "loading"), exist_ok=True)
os.makedirs(data)


def fail(message):
    sys.exit(f"FAILED: {message}")


def write(path, rows):
    columns = sorted({c for r in rows for c in r})
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, columns)
        w.writeheader()
        w.writerows(rows)


# The rpm study's table: 1500 particles at 1000-4000 rpm, seeds 1-2.
rpm_rows = [{"case": f"mechanofusion_seed={s}_rpm={r}.h5", "seed": str(s), "rpm": str(r), "particles": "1500",
             "inner_normal_force": str(1e-4 * r / 1000)} for s in (1, 2) for r in (500, 1000, 2000, 4000)]
write(os.path.join(data, "mechanofusion_rpm.csv"), rpm_rows)
# The loading table from an earlier session: one case, not under WORK this time.
old = {"case": "mechanofusion_seed=1_rpm=1000_particles=500.h5", "seed": "1", "rpm": "1000", "particles": "500",
       "inner_normal_force": "2e-5"}
write(os.path.join(data, "mechanofusion_loading.csv"), [old])
# This WORK's finished cases (what finished_cases() reads from the case files).
ran = [{"case": f"mechanofusion_seed=1_rpm=1000_particles={n}.h5", "seed": "1", "rpm": "1000",
        "particles": str(n), "inner_normal_force": str(4e-5 * n / 1000)} for n in (1000, 2000)]
me.finished_cases = lambda directory: [dict(r) for r in ran] if directory.endswith("loading") else []
me.tables(types.SimpleNamespace(work=os.path.join(work, "ensembles_work"), data=data, replace=False))
rows = me.read_csv(os.path.join(data, "mechanofusion_loading.csv"))
cases = sorted(r["case"] for r in rows)
if "mechanofusion_seed=1_rpm=1000_particles=500.h5" not in cases:
    fail("the earlier session's case was dropped")
borrowed = [r for r in rows if r.get("borrowed_from") == "rpm"]
if sorted((r["seed"], r["rpm"]) for r in borrowed) != [(s, r) for s in ("1", "2") for r in ("1000", "2000", "4000")]:
    fail(f"borrowed {[(r['seed'], r['rpm']) for r in borrowed]}, not the six cases at 1000-4000 rpm")
if len(rows) != 3 + 6 or len(set(cases)) != len(cases):
    fail(f"{len(rows)} rows ({len(set(cases))} distinct), not 3 run + 6 borrowed")
# Run again: nothing doubles (the borrowed rows are taken afresh, not kept and borrowed again).
me.tables(types.SimpleNamespace(work=os.path.join(work, "ensembles_work"), data=data, replace=False))
if len(me.read_csv(os.path.join(data, "mechanofusion_loading.csv"))) != 9:
    fail("a second `tables` changed the row count")
# --replace: WORK's cases and the borrowed ones only.
me.tables(types.SimpleNamespace(work=os.path.join(work, "ensembles_work"), data=data, replace=True))
if len(me.read_csv(os.path.join(data, "mechanofusion_loading.csv"))) != 2 + 6:
    fail("--replace kept the earlier session's case")
# The slab study runs only the 3D slab; its 2D cases are the rpm study's 2000 rpm
# ones, marked dimension = 2 (the scene's default, which the rpm study did not vary).
os.makedirs(os.path.join(work, "ensembles_work", "slab"), exist_ok=True)
slab_ran = [{"case": f"mechanofusion_seed={s}.h5", "seed": str(s), "dimension": "3",
             "inner_normal_force": "3e-4"} for s in (1, 2)]
me.finished_cases = lambda directory: [dict(r) for r in slab_ran] if directory.endswith("slab") else []
me.tables(types.SimpleNamespace(work=os.path.join(work, "ensembles_work"), data=data, replace=False))
slab = me.read_csv(os.path.join(data, "mechanofusion_slab.csv"))
pairs = sorted((r["seed"], r["dimension"], r.get("borrowed_from", "")) for r in slab)
if pairs != [("1", "2", "rpm"), ("1", "3", ""), ("2", "2", "rpm"), ("2", "3", "")]:
    fail(f"slab rows {pairs}: not seeds 1-2 in 3D run and in 2D borrowed at 2000 rpm")
if any(r["rpm"] != "2000" for r in slab if r.get("borrowed_from")):
    fail("the slab borrowed a case at another speed than 2000 rpm")
# Exponents: a seed with only part of the values is left out of the mean.
import numpy as np  # noqa: E402
xs = np.array([1.0, 2.0, 4.0])
seeds = {1: ([1.0, 2.0, 4.0], [1.0, 4.0, 16.0]), 2: ([1.0, 2.0, 4.0], [1.0, 4.0, 16.0]),
         3: ([1.0, 2.0], [1.0, 1.0])}
b, se, n = me.exponent(xs, np.array([1.0, 4.0, 16.0]), seeds)
if n != 2 or abs(b - 2) > 1e-9:
    fail(f"exponent {b} from {n} seeds: the partial seed was fitted")
print("ensembles check ok")
