#!/usr/bin/python3
"""The restart journal's size warning (src/lua/journal.hpp, passed_size_mark).

A scene reads a particle 4000 times, saving a checkpoint after 2000: with the
first mark at 20 kB the whole run warns at each doubling, with a call count and
size that only grow; -q warns of nothing; a restart from the checkpoint warns
only of the marks the first run passed after it, with the same counts.

    journal_warning_test.py GRANULE SOURCE_DIR
"""
import os
import re
import subprocess
import sys
import tempfile

GRANULE, SOURCE = sys.argv[1], sys.argv[2]
SCENE = os.path.join(SOURCE, "tests", "scenes", "journal_warning.lua")
ENV = dict(os.environ, GRANULE_JOURNAL_WARN_BYTES="20000", GRANULE_PROGRESS_AFTER="1e9")
WARNING = re.compile(r"warning: the restart journal .*?, (\d+) calls, .*? holds ([0-9.e+-]+) MB")


def run(args, cwd):
    # One stream, in the order written (the scene flushes its line; stderr is unbuffered).
    r = subprocess.run([GRANULE, "run", SCENE, *args], cwd=cwd, env=ENV, stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True, timeout=120)
    if r.returncode != 0:
        sys.exit(f"run {args} failed ({r.returncode}): {r.stdout}")
    return r.stdout


def warnings(text):
    return [(int(m.group(1)), float(m.group(2))) for m in WARNING.finditer(text)]


with tempfile.TemporaryDirectory() as work:
    whole = run(["-o", "out.h5"], work)
    seen = warnings(whole)
    # Each doubling once: from 20 kB to the whole journal's size.
    if not 4 <= len(seen) <= 8:
        sys.exit(f"FAIL {len(seen)} warnings in the whole run: {seen}")
    if any(b[0] <= a[0] or b[1] <= a[1] for a, b in zip(seen, seen[1:])):
        sys.exit(f"FAIL the warnings' counts do not grow: {seen}")
    if "restart journal" in run(["-o", "quiet.h5", "-q"], work):
        sys.exit("FAIL -q printed a journal warning")
    # The whole run's warnings after its checkpoint's line are the restart's.
    after = warnings(whole.split("checkpoint saved", 1)[1]) if "checkpoint saved" in whole else None
    restarted = warnings(run(["--restart", "journal_warning.chk.h5", "-o", "out.h5"], work))
    print(f"whole {seen}\nafter the checkpoint {after}\nrestart {restarted}")
    if after is None or restarted != after:
        sys.exit("FAIL the restart's warnings differ from the whole run's after its checkpoint")
print("journal warnings ok")
