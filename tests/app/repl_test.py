#!/usr/bin/env python3
"""The REPL keeps what a user does at its prompt.

A scene that closes its output is run in `granule repl ... -o FILE`; then at the prompt:
sim:snapshot() writes into FILE (the scene's sim:close() only flushed it), Ctrl-C during a
long sim:run returns to the prompt with "run interrupted at t = ... s, state kept" and a
checkpoint beside FILE, the state goes on from there, and reading a misspelt global is an
error naming it and the nearest name. The file is checked with h5py afterwards.

Usage: repl_test.py GRANULE SOURCE_DIR WORK_DIR
"""
import os
import re
import signal
import subprocess
import sys
import threading
import time

import h5py


def fail(message, out="", err=""):
    print(f"FAILED: {message}\n--- stdout\n{out}\n--- stderr\n{err}")
    sys.exit(1)


def main():
    granule, source, work = sys.argv[1:4]
    os.makedirs(work, exist_ok=True)
    os.chdir(work)
    out_file = "repl_keep_test.h5"
    checkpoint = "repl_keep_test.checkpoint.h5"
    for f in (out_file, checkpoint):
        if os.path.exists(f):
            os.remove(f)
    scene = os.path.join(source, "scenarios", "mechanofusion_demo.lua")
    p = subprocess.Popen(
        [granule, "repl", scene, "-D", "duration=0.0002", "-D", "particles=60", "-o", out_file, "-q"],
        stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, bufsize=1)
    stdout_lines, stderr_lines = [], []

    def pump(stream, into):
        for line in stream:
            into.append(line)

    threads = [threading.Thread(target=pump, args=(p.stdout, stdout_lines), daemon=True),
               threading.Thread(target=pump, args=(p.stderr, stderr_lines), daemon=True)]
    for t in threads:
        t.start()

    def send(line):
        p.stdin.write(line + "\n")
        p.stdin.flush()

    def wait_for(lines, pattern, seconds=60):
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            for line in list(lines):
                if re.search(pattern, line):
                    return line
            time.sleep(0.05)
        fail(f"no line matching {pattern!r}", "".join(stdout_lines), "".join(stderr_lines))

    # After the scene (which called sim:close()): a snapshot at the prompt goes to -o.
    send('sim:snapshot(); print(string.format("first t=%.17g", sim:time()))')
    first_t = float(wait_for(stdout_lines, r"^first t=").split("=")[1])
    # A run far too long to finish: stopped by Ctrl-C once it is stepping.
    send('print("running"); r = sim:run { duration = 100 }; print("returned", r.interrupted)')
    wait_for(stdout_lines, r"^running")
    time.sleep(1.5)
    p.send_signal(signal.SIGINT)
    stopped = wait_for(stderr_lines, r"run interrupted at t = ")
    wait_for(stdout_lines, r"^returned\ttrue")
    send('sim:snapshot(); print(string.format("after t=%.17g", sim:time()))')
    after_t = float(wait_for(stdout_lines, r"^after t=").split("=")[1])
    send("simulatoin")
    p.stdin.close()
    rc = p.wait(timeout=120)
    for t in threads:
        t.join(timeout=10)
    out, err = "".join(stdout_lines), "".join(stderr_lines)

    if "state kept" not in stopped or checkpoint not in stopped:
        fail(f"the interrupt message is {stopped!r}", out, err)
    t_said = float(re.search(r"at t = ([0-9.eE+-]+) s", stopped).group(1))
    if not after_t > first_t or abs(t_said - after_t) > 1e-9 * max(1.0, after_t):
        fail(f"state after the interrupt: t = {after_t}, said {t_said}, before {first_t}", out, err)
    if not re.search(r"simulatoin is not defined \(did you mean simulation\?\)", out):
        fail("reading a misspelt global does not say so", out, err)
    errors = [line for line in out.splitlines() if line.startswith("error:")]
    if len(errors) != 1:
        fail(f"expected one error (the misspelt name), got {errors}", out, err)
    if rc != 1:
        fail(f"exit status {rc}, expected 1 (one error at the prompt, the interrupt is none)", out, err)
    if not os.path.exists(checkpoint):
        fail(f"no checkpoint {checkpoint} beside {out_file}", out, err)
    with h5py.File(checkpoint, "r") as c:
        step = int(c["checkpoint/integers/meta"][2])
    with h5py.File(out_file, "r") as f:
        snaps = f["snapshots"]
        times = [float(snaps[k].attrs["time"]) for k in sorted(snaps)]
        steps = [int(snaps[k].attrs["step"]) for k in sorted(snaps)]
    # The prompt's two snapshots are in the file: one at the scene's end, one after the stop.
    if not any(t == first_t for t in times) or not any(t == after_t for t in times):
        fail(f"snapshot times {times} lack the prompt's {first_t} and {after_t}", out, err)
    if step not in steps:
        fail(f"the checkpoint's step {step} is not the state kept (snapshot steps {steps})", out, err)
    print(f"repl_test ok: interrupted at t = {after_t:.6g} s, {len(times)} snapshots, checkpoint step {step}")


if __name__ == "__main__":
    main()
