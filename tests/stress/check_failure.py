#!/usr/bin/env python3
"""Reads the output of a failed run (tests/stress/failures.lua): the failure is
recorded at the root and on the last snapshot, and that snapshot holds every
particle with a finite state (the state the run had when it stopped).

    check_failure.py FILE EXPECTED_PARTICLES TEXT_IN_MESSAGE
"""
import sys

import h5py
import numpy as np

path, expected, text = sys.argv[1], int(sys.argv[2]), sys.argv[3]
with h5py.File(path, "r") as f:
    failure = f.attrs.get("failure")
    if failure is None:
        sys.exit(f"{path}: no 'failure' attribute at the root")
    failure = failure.decode() if isinstance(failure, bytes) else str(failure)
    if text not in failure:
        sys.exit(f"{path}: failure '{failure}' does not mention '{text}'")
    names = sorted(f["snapshots"].keys())
    last = f["snapshots"][names[-1]]
    if "failure" not in last.attrs:
        sys.exit(f"{path}: the last snapshot does not carry the failure")
    count = len(last["id"])
    if count != expected:
        sys.exit(f"{path}: the failure snapshot holds {count} particles, expected {expected}")
    for name in ("position", "velocity"):
        if not np.all(np.isfinite(last[name][()])):
            sys.exit(f"{path}: non-finite {name} in the failure snapshot")
    print(f"{path}: failure recorded with {count} finite particles at step {last.attrs['step']}: ok")
