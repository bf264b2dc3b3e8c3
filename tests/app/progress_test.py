#!/usr/bin/env python3
"""The progress line of sim:run, in a batch log and on a terminal.

In a pipe: a line of its own ("progress: ... ETA ...") at each tenth of the run, no
carriage returns or escape codes; with --progress S, lines S seconds apart (timed as
they arrive); with -q and no --progress, none. On a terminal (script(1)): the line is
erased before each of the scene's prints, so no print starts behind a progress line.

Usage: progress_test.py GRANULE SOURCE_DIR WORK_DIR
"""
import os
import re
import shutil
import subprocess
import sys
import time


def fail(message, text=""):
    print(f"FAILED: {message}\n--- output\n{text}")
    sys.exit(1)


def run_timed(command, env):
    """Runs command; returns [(seconds since start, stderr line)] and its exit status."""
    start = time.monotonic()
    p = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env)
    lines = []
    for raw in p.stderr:
        lines.append((time.monotonic() - start, raw.decode()))
    return lines, p.wait()


def main():
    granule, source, work = sys.argv[1:4]
    os.makedirs(work, exist_ok=True)
    os.chdir(work)
    scene = os.path.join(source, "tests", "scenes", "progress_print.lua")
    env = dict(os.environ, GRANULE_PROGRESS_AFTER="0")

    # A pipe: every tenth of the run, each its own line.
    lines, rc = run_timed([granule, "run", scene, "-D", "steps=1000000"], env)
    text = "".join(l for _, l in lines)
    if rc != 0:
        fail(f"exit status {rc}", text)
    if "\r" in text or "\033" in text:
        fail("a pipe got carriage returns or escape codes", repr(text))
    shown = [l for _, l in lines if l.startswith("progress: ")]
    percents = [float(re.search(r"([0-9.]+)%", l).group(1)) for l in shown]
    tenths = [int(p // 10) for p in percents]
    if len(shown) < 3 or any(b <= a for a, b in zip(tenths, tenths[1:])) or min(tenths) < 1:
        fail(f"lines at tenths {tenths} (percent {percents}): want at least 3, one per tenth", text)
    if not all(re.search(r"steps/s  ETA [0-9]+:[0-9]{2}", l) for l in shown):
        fail("a progress line without its ETA", text)
    if percents[-1] != 100.0:
        fail(f"the last line says {percents[-1]} %, not 100 %", text)

    # --progress S: lines S seconds of wall time apart, as they arrive.
    every = 0.4  # several lines even when the run is fast (about 2.5 s on a quiet core)
    lines, rc = run_timed([granule, "run", scene, "-D", "steps=6000000", "-q", "--progress", str(every)], env)
    times = [t for t, l in lines if l.startswith("progress: ")]
    text = "".join(l for _, l in lines)
    gaps = [b - a for a, b in zip(times, times[1:])]
    if rc != 0 or len(times) < 2 or min(gaps) < every - 0.15:
        fail(f"--progress {every}: lines at {times} s (gaps {gaps})", text)

    # -q alone: no progress lines.
    lines, rc = run_timed([granule, "run", scene, "-D", "steps=1000000", "-q"], env)
    if any(l.startswith("progress") for _, l in lines):
        fail("-q printed progress lines", "".join(l for _, l in lines))

    # A terminal: the scene's prints never start behind the progress line.
    script = shutil.which("script")
    if script:
        command = f"env GRANULE_PROGRESS_AFTER=0 {granule} run {scene} -D steps=1000000 -D print_every=50000"
        # Bytes: text mode would turn each \r into a line break.
        out = subprocess.run([script, "-qec", command, "/dev/null"], capture_output=True,
                             timeout=120).stdout.decode()
        behind_a_line, prints = 0, 0
        for line in out.split("\n"):
            for m in re.finditer("SCENE-PRINT", line):
                prints += 1
                before = line[:m.start()]
                if "ETA" in before:
                    behind_a_line += 1  # a progress line was drawn on this line first...
                    if before[before.rfind("\r") + 1:] not in ("", "\033[K"):  # ...and not erased
                        fail(f"a print shares its line with the progress line: {line!r}", out)
        if prints < 10 or behind_a_line == 0:
            fail(f"{prints} prints, {behind_a_line} after a progress line: the case did not arise", out)
    print(f"progress_test ok: tenths {tenths}, --progress gaps {min(gaps):.2f}-{max(gaps):.2f} s")


if __name__ == "__main__":
    main()
