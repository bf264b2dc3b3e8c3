"""A run killed by SIGKILL (no handler, no flush of its own) keeps in its output
what the scene had written more than a second before: rows appended in the
run's first steps, when it then appends none, and the first snapshot's walls.

    killed_output_test.py GRANULE SOURCE_DIR
"""
import os
import signal
import subprocess
import sys
import tempfile
import time

import h5py

GRANULE, SOURCE = sys.argv[1], sys.argv[2]
SCENE = os.path.join(SOURCE, "tests", "scenes", "killed_output.lua")
with tempfile.TemporaryDirectory() as work:
    run = subprocess.Popen([GRANULE, "run", SCENE, "-q", "-o", "killed.h5"], cwd=work,
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                           env=dict(os.environ, GRANULE_PROGRESS_AFTER="1e9"))
    line = run.stdout.readline()
    if line.strip() != "appended":
        sys.exit(f"the scene did not start: {line!r} {run.stderr.read()}")
    time.sleep(3.0)
    run.send_signal(signal.SIGKILL)
    run.wait(timeout=30)
    with h5py.File(os.path.join(work, "killed.h5"), "r") as f:
        if "burst" not in f or len(f["burst/value"]) != 10:
            sys.exit(f"the 10 rows appended about 3 s before the kill are not in the file: "
                     f"{list(f.keys())}, {len(f['burst/value']) if 'burst' in f else 0} rows")
        if list(f["burst/value"][:]) != list(range(1, 11)):
            sys.exit(f"rows {list(f['burst/value'][:])}")
        first = f["snapshots"][sorted(f["snapshots"])[0]]
        if "walls" not in first:
            sys.exit(f"the first snapshot has no walls: {list(first.keys())}")
print("killed output: the rows and the snapshot written before the last second are kept")
