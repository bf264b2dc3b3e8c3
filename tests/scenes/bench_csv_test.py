#!/usr/bin/python3
"""tools/bench/compare.py's CSV on small cases (a 5 x 5 x 4 box, a 2D chamber
of 60 particles): one row per run with the columns docs/performance.md lists,
the Granule rows' stage seconds consistent with their wall time, rows appended
by a second command, and a file with other columns refused.

    bench_csv_test.py GRANULE_BINARY
"""
import csv
import os
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
COMPARE = os.path.join(ROOT, "tools", "bench", "compare.py")
STAGES = ["neighbour_s", "contacts_s", "diagnostics_s", "integrate_s", "hooks_s"]
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAILED: " + what)


def compare(granule, work, *args):
    cmd = [sys.executable, COMPARE, "--granule", granule, "--work", work] + list(args)
    return subprocess.run(cmd, capture_output=True, text=True, timeout=300)


def main():
    granule = os.path.abspath(sys.argv[1])
    with tempfile.TemporaryDirectory() as work:
        box = compare(granule, work, "--case", "box3d", "--box-side", "5", "--box-layers", "4", "--steps", "4000",
                      "--threads", "1,2", "--repeat", "2")
        check(box.returncode == 0, f"box3d run exits 0 (got {box.returncode}: {box.stderr[-500:]})")
        mf = compare(granule, work, "--case", "mechanofusion2d", "--mf-particles", "60", "--mf-settle", "0.0005",
                     "--steps", "1000", "--threads", "1")
        check(mf.returncode == 0, f"mechanofusion2d run exits 0 (got {mf.returncode}: {mf.stderr[-500:]})")
        path = os.path.join(work, "bench_results.csv")
        with open(path, newline="") as f:
            reader = csv.DictReader(f)
            header, rows = reader.fieldnames, list(reader)
        for column in ["case", "program", "threads", "steps", "particles", "pair_contacts", "wall_s",
                       "particle_steps_per_s", "walls_s", "sums_s", "pair_wait_s"] + STAGES:
            check(column in header, f"column {column}")
        ours = [r for r in rows if r["program"].startswith("granule")]
        box_rows = [r for r in ours if r["case"] == "box3d"]
        mf_rows = [r for r in ours if r["case"] == "mechanofusion2d"]
        # 2 thread counts x 2 rounds, and on two cores also two MPI ranks (where
        # mpirun is here); 2 laws x 1 thread count: each run once.
        expected = [("granule linear", "1", "1"), ("granule linear", "1", "2"), ("granule linear", "2", "1"),
                    ("granule linear", "2", "2")]
        if shutil.which("mpirun"):
            expected += [("granule linear (mpirun)", "2", "1"), ("granule linear (mpirun)", "2", "2")]
        got = sorted((r["program"], r["threads"], r["round"]) for r in box_rows)
        check(got == sorted(expected), f"one box row per run and round: {got}")
        check(sorted(r["program"] for r in mf_rows) == ["granule linear", "granule walton_braun"],
              f"one 2D row per law: {[r['program'] for r in mf_rows]}")
        for r in box_rows:
            check(r["particles"] == "100" and r["steps"] == "200", f"box: 100 spheres, 200 steps: {r}")
            check(float(r["pair_contacts"]) > 100, f"box: the lattice's spheres touch: {r['pair_contacts']}")
        for r in mf_rows:
            check(r["particles"] == "60" and r["steps"] == "1000", f"2D: 60 particles, 1000 steps: {r}")
        for r in ours:
            wall = float(r["wall_s"])
            stages = [float(r[k]) for k in STAGES + ["walls_s", "sums_s", "pair_wait_s"]]
            check(wall > 0 and min(stages) >= 0, f"times positive: {r}")
            # The stages are timed inside the steps the wall clock spans.
            check(sum(float(r[k]) for k in STAGES) <= wall * 1.001, f"stages within the wall time: {r}")
            check(float(r["walls_s"]) + float(r["sums_s"]) <= float(r["contacts_s"]) * 1.001,
                  f"walls and sums are parts of the contact stage: {r}")
            expected = int(r["particles"]) * int(r["steps"]) / wall
            check(abs(float(r["particle_steps_per_s"]) / expected - 1) < 1e-4, f"particle-steps/s: {r}")
            check(r["threads"] == "2" or float(r["sums_s"]) == 0, f"one thread keeps no deferred sums: {r}")
        if shutil.which("lmp") is None:
            check("not found: LAMMPS" in mf.stdout, "says LAMMPS is missing")
        with open(os.path.join(work, "other.csv"), "w") as f:
            f.write("x,y\n1,2\n")
        bad = compare(granule, work, "--case", "box3d", "--box-side", "5", "--box-layers", "4", "--csv",
                      os.path.join(work, "other.csv"))
        check(bad.returncode != 0 and "other.csv" in bad.stderr, f"a CSV with other columns refused: {bad.stderr}")
    if failures:
        sys.exit(f"{len(failures)} check(s) failed")
    print(f"bench_csv ok: {len(rows)} rows")


if __name__ == "__main__":
    main()
