#!/usr/bin/python3
"""Runs the corpus of malformed scenes and corrupt checkpoints (ctest: corpus.malformed).

    /usr/bin/python3 tests/corpus/run_corpus.py build/granule [--jobs 2] [--timeout 20] [--only REGEX]

Every case must end the way a user can act on: exit status 1 or 2 (not 0,
not a signal, not a timeout), a message on stderr that matches the case's
expect regex (the scene file and line, or the parameter or field), no NaN
or inf in any float dataset or attribute of any HDF5 file the run wrote, and
nothing written outside the case's own temporary directory.

Scene cases are tests/corpus/scenes/*.lua (written by make_scenes.py); their
header carries `-- expect: REGEX` and optionally `-- args: -D name=value`.
The regex is searched in stderr line by line ('.' does not cross a line;
[\\s\\S]* does). Checkpoint cases are made at test time by
make_checkpoints.py from a valid checkpoint that checkpoint_scene.lua writes,
and each is run as `granule run checkpoint_scene.lua --restart BAD.h5`.

Cases named in pending.txt wait for a fix elsewhere: they are run and
reported, and their failures do not fail the corpus; one that passes is named
on a line of its own, to be deleted from the list (not a failure: a case whose
defect is undefined behaviour, such as a checkpoint index read out of bounds,
may pass on one run and crash on the next).
"""
import argparse
import concurrent.futures
import os
import re
import shlex
import signal
import subprocess
import sys
import tempfile
import time

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, HERE)
import make_checkpoints  # noqa: E402


def scene_case(path):
    name = os.path.basename(path)[:-4]
    expect, args, what = None, [], ""
    with open(path) as f:
        for number, line in enumerate(f, 1):
            if not line.startswith("--"):
                break
            if number == 1:
                what = line[2:].strip()
            m = re.match(r"--\s*expect:\s*(.*\S)", line)
            if m:
                expect = m.group(1)
            m = re.match(r"--\s*args:\s*(.*\S)", line)
            if m:
                args = shlex.split(m.group(1))
    if expect is None:
        raise SystemExit(f"{path}: no '-- expect: REGEX' line in its header")
    return dict(name=name, kind="scene", what=what, expect=expect, command=["run", path] + args)


def h5_non_finite(path):
    """The first float dataset or attribute in `path` holding NaN or inf, or None."""
    found = []

    def floats_bad(value):
        a = np.asarray(value)
        return a.dtype.kind in "fc" and a.size > 0 and not np.all(np.isfinite(a))

    def attrs(name, obj):
        for key, value in obj.attrs.items():
            try:
                if floats_bad(value):
                    found.append(f"{name} attribute {key}")
            except TypeError:
                pass

    def visit(name, obj):
        attrs(name, obj)
        if isinstance(obj, h5py.Dataset) and obj.dtype.kind in "fc" and obj.size > 0:
            if not np.all(np.isfinite(obj[()])):
                found.append(name)

    try:
        with h5py.File(path, "r") as f:
            attrs("/", f)
            f.visititems(visit)
    except OSError:
        return None  # not HDF5 (a corrupt input copied in, or a half-written file): nothing to read
    return found[0] if found else None


def tree(root):
    out = {}
    for base, _, files in os.walk(root):
        for name in files:
            p = os.path.join(base, name)
            try:
                out[p] = os.stat(p).st_mtime_ns
            except OSError:
                pass
    return out


def run_case(granule, c, work, timeout):
    wd = os.path.join(work, c["name"])
    os.makedirs(wd, exist_ok=True)
    inputs = set(os.listdir(wd))
    command = [granule] + c["command"] + ["-o", os.path.join(wd, "out.h5"), "--quiet"]
    start = time.monotonic()
    proc = subprocess.Popen(command, cwd=wd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, start_new_session=True,
                            env=dict(os.environ, OMP_NUM_THREADS="1", OMP_WAIT_POLICY="PASSIVE"))
    try:
        out, err = proc.communicate(timeout=timeout)
        status = proc.returncode
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        out, err = proc.communicate()
        status = None
    seconds = time.monotonic() - start
    err = err.decode(errors="replace")
    problems = []
    if status is None:
        problems.append(f"timed out after {timeout} s")
    elif status < 0:
        problems.append(f"killed by signal {-status} ({signal.Signals(-status).name})")
    elif status not in (1, 2):
        problems.append(f"exit status {status}, expected 1 or 2")
    if status is not None and not re.search(c["expect"], err, re.MULTILINE):
        problems.append(f"stderr does not match /{c['expect']}/")
    for base, _, files in os.walk(wd):
        for name in files:
            path = os.path.join(base, name)
            if os.path.relpath(path, wd) in inputs:
                continue
            if name.endswith(".h5"):
                bad = h5_non_finite(path)
                if bad:
                    problems.append(f"{os.path.relpath(path, wd)}: non-finite values in {bad}")
    return dict(case=c, status=status, seconds=seconds, problems=problems, stderr=err)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("granule")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--timeout", type=float, default=20)
    ap.add_argument("--only", help="run only the cases whose name matches this regex")
    ap.add_argument("--keep", action="store_true", help="keep the temporary directory")
    a = ap.parse_args()
    granule = os.path.abspath(a.granule)
    scenes_dir = os.path.join(HERE, "scenes")
    pending = set()
    with open(os.path.join(HERE, "pending.txt")) as f:
        for line in f:
            line = line.split("#", 1)[0].strip()
            if line:
                pending.add(line)

    started = time.monotonic()
    watched = [HERE]  # the scenes and checkpoint scene: a case writes only in its own directory
    before = {root: tree(root) for root in watched}
    work = tempfile.mkdtemp(prefix="granule_corpus_")
    cases = [scene_case(os.path.join(scenes_dir, n)) for n in sorted(os.listdir(scenes_dir)) if n.endswith(".lua")]
    setup_failures = []
    try:
        cases += make_checkpoints.cases(granule, HERE, work, setup_failures)
        if a.only:
            cases = [c for c in cases if re.search(a.only, c["name"])]
        unknown = pending - {c["name"] for c in cases}
        if unknown and not a.only:
            setup_failures.append("pending.txt names cases that do not exist: " + ", ".join(sorted(unknown)))
        with concurrent.futures.ThreadPoolExecutor(max_workers=a.jobs) as pool:
            results = list(pool.map(lambda c: run_case(granule, c, work, a.timeout), cases))
    finally:
        after = {root: tree(root) for root in watched}
        if not a.keep:
            subprocess.run(["rm", "-rf", work])
    for root in watched:
        for path in sorted(set(after[root]) - set(before[root])):
            if not path.startswith(work):
                setup_failures.append(f"a case wrote outside its directory: {path}")
        for path in sorted(set(before[root]) & set(after[root])):
            if before[root][path] != after[root][path] and not path.startswith(work):
                setup_failures.append(f"a case changed a file outside its directory: {path}")

    passed = failed = waiting = 0
    now_passing = []
    print(f"{'case':48} {'kind':10} {'status':>7} {'s':>6}  result")
    for r in results:
        c = r["case"]
        status = "timeout" if r["status"] is None else str(r["status"])
        ok = not r["problems"]
        if c["name"] in pending:
            verdict = "passes (pending.txt may drop it)" if ok else "pending (fix elsewhere)"
            if ok:
                now_passing.append(c["name"])
                passed += 1
            else:
                waiting += 1
        else:
            verdict = "ok" if ok else "FAIL"
            if ok:
                passed += 1
            else:
                failed += 1
        print(f"{c['name']:48} {c['kind']:10} {status:>7} {r['seconds']:6.2f}  {verdict}")
        if not ok:
            for p in r["problems"]:
                print(f"    {p}")
            lines = r["stderr"].strip().splitlines()
            print("    stderr: " + (" | ".join(lines[:3]) if lines else "(empty)"))
    for s in setup_failures:
        print("FAIL: " + s)
    failed += len(setup_failures)
    if now_passing:
        print("pending cases that pass now (delete them from pending.txt): " + " ".join(now_passing))
    print(f"{len(results)} cases in {time.monotonic() - started:.1f} s; {waiting} pending on fixes elsewhere")
    print(f"{passed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
