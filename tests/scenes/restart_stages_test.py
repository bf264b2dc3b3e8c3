#!/usr/bin/python3
"""Restart of multi-stage scenes, end to end through the program.

For each scene: one run that is never stopped; then, for each stage and each
signal (SIGINT, SIGTERM), a run interrupted inside that stage (the test waits
for the stage's start to be printed, then signals; a signal that misses the
stage, or comes after the run ended, is tried again sooner), which must exit with
128 + the signal's number and leave a checkpoint taken inside the stage; and
its restart, which must print the same lines on stdout as the whole run and
leave an output file identical to the whole run's, bit for bit
(compare_runs.py: every snapshot, series, result and diagnostic).

    restart_stages_test.py GRANULE SOURCE_DIR
"""
import os
import re
import signal
import subprocess
import sys
import tempfile
import threading
import time

GRANULE, SOURCE = sys.argv[1], sys.argv[2]
COMPARE = os.path.join(SOURCE, "tests", "scenes", "compare_runs.py")
SIGNALS = [("SIGINT", signal.SIGINT, 130), ("SIGTERM", signal.SIGTERM, 143)]


def checkpoint_step(path):
    import h5py
    with h5py.File(path, "r") as f:
        return int(f["checkpoint"].attrs["step"])


# Every run writes out.h5 in a folder of its own, so that the lines a scene prints
# about its file are the same in every run.
def folder(work, tag):
    path = os.path.join(work, tag)
    os.makedirs(path, exist_ok=True)
    return path


ENV = dict(os.environ, GRANULE_PROGRESS_AFTER="1e9")


def run_whole(scene, args, work):
    cwd = folder(work, "whole")
    out = os.path.join(cwd, "out.h5")
    r = subprocess.run([GRANULE, "run", scene, *args, "-o", "out.h5"], cwd=cwd, env=ENV,
                       capture_output=True, text=True, timeout=300)
    if r.returncode != 0:
        sys.exit(f"the whole run failed ({r.returncode}): {r.stderr}")
    return out, r.stdout, r.stderr


def interrupt(scene, args, work, tag, trigger, delay, signum):
    """Runs until `trigger` (a regex) appears on stdout or stderr, waits `delay` s, signals."""
    cwd = folder(work, tag)
    out = os.path.join(cwd, "out.h5")
    p = subprocess.Popen([GRANULE, "run", scene, *args, "-o", "out.h5"], cwd=cwd,
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=ENV)
    seen = threading.Event()
    texts = {"stdout": [], "stderr": []}

    def read(stream, name):
        for line in stream:
            texts[name].append(line)
            if re.search(trigger, line):
                seen.set()

    readers = [threading.Thread(target=read, args=(p.stdout, "stdout")),
               threading.Thread(target=read, args=(p.stderr, "stderr"))]
    for t in readers:
        t.start()
    if not seen.wait(120):
        p.kill()
        sys.exit(f"{tag}: '{trigger}' never appeared")
    time.sleep(delay)
    p.send_signal(signum)
    status = p.wait(120)
    for t in readers:
        t.join()
    return out, status, "".join(texts["stdout"]), "".join(texts["stderr"])


def check_case(name, scene, args, checkpoint, stages):
    """stages: (stage name, trigger regex, delay s, function(step) -> bool: inside the stage)."""
    failures = 0
    with tempfile.TemporaryDirectory() as work:
        whole, whole_stdout, _ = run_whole(scene, args, work)
        for signame, signum, expected in SIGNALS:
            for stage, trigger, delay, inside in stages:
                tag = f"{stage}_{signame}"
                chk = os.path.join(work, tag, checkpoint)
                step = None
                for attempt in range(4):  # the signal must land inside the stage
                    if os.path.exists(chk):
                        os.remove(chk)
                    out, status, _, err = interrupt(scene, args, work, tag, trigger, delay, signum)
                    if status == 0:  # the run ended before the signal came: a miss, sooner next time
                        delay = delay / 2
                        continue
                    if status != expected:
                        print(f"FAIL {name} {tag}: exit status {status}, expected {expected}\n{err}")
                        failures += 1
                        break
                    if not os.path.exists(chk):
                        print(f"FAIL {name} {tag}: no checkpoint {checkpoint}\n{err}")
                        failures += 1
                        break
                    step = checkpoint_step(chk)
                    if inside(step):
                        break
                    delay = delay / 2
                else:
                    where = f"last at step {step}" if step is not None else "the run ended first"
                    print(f"FAIL {name} {tag}: four signals missed the stage ({where})")
                    failures += 1
                    continue
                if status != expected or not os.path.exists(chk):
                    continue
                if "checkpoint written to" not in err:
                    print(f"FAIL {name} {tag}: the interrupt message lacks the checkpoint:\n{err}")
                    failures += 1
                cwd = folder(work, f"{tag}_resumed")
                resumed = os.path.join(cwd, "out.h5")
                r = subprocess.run([GRANULE, "run", scene, *args, "--restart", chk, "-o", "out.h5"],
                                   cwd=cwd, env=ENV, capture_output=True, text=True, timeout=300)
                if r.returncode != 0:
                    print(f"FAIL {name} {tag}: the restart failed ({r.returncode}):\n{r.stderr}")
                    failures += 1
                    continue
                if r.stdout != whole_stdout:
                    print(f"FAIL {name} {tag} (interrupted at step {step}): printed lines differ:\n--- whole\n{whole_stdout}"
                          f"--- restarted\n{r.stdout}")
                    failures += 1
                    continue
                c = subprocess.run(["/usr/bin/python3", COMPARE, whole, resumed],
                                   capture_output=True, text=True)
                if c.returncode != 0:
                    print(f"FAIL {name} {tag}: outputs differ: {c.stdout}{c.stderr}")
                    failures += 1
                    continue
                print(f"ok {name} {tag}: interrupted at step {step}, restarted: {c.stdout.strip()}")
    return failures


def check_twice(name, scene, args, checkpoint, first, second):
    """A run interrupted, its restart interrupted in turn, and that restart's
    checkpoint continued: the third run ends as the run never stopped does (a
    restarted run's own checkpoints journal what it did after the restart).
    first, second: (trigger regex, delay s) of the two interruptions."""
    with tempfile.TemporaryDirectory() as work:
        whole, whole_stdout, _ = run_whole(scene, args, work)
        chk, extra = None, []
        for k, (trigger, delay) in enumerate([first, second]):
            tag = f"twice{k}"
            _, status, _, err = interrupt(scene, args + extra, work, tag, trigger, delay,
                                          signal.SIGTERM)
            chk = os.path.join(work, tag, checkpoint)
            if status != 143 or not os.path.exists(chk):
                print(f"FAIL {name} twice: interruption {k + 1} gave status {status}:\n{err}")
                return 1
            extra = ["--restart", chk]
        cwd = folder(work, "twice_resumed")
        r = subprocess.run([GRANULE, "run", scene, *args, *extra, "-o", "out.h5"], cwd=cwd,
                           env=ENV, capture_output=True, text=True, timeout=300)
        if r.returncode != 0 or r.stdout != whole_stdout:
            print(f"FAIL {name} twice: the second restart failed ({r.returncode}) or printed "
                  f"other lines:\n{r.stderr}\n--- whole\n{whole_stdout}--- restarted\n{r.stdout}")
            return 1
        c = subprocess.run(["/usr/bin/python3", COMPARE, whole, os.path.join(cwd, "out.h5")],
                           capture_output=True, text=True)
        if c.returncode != 0:
            print(f"FAIL {name} twice: outputs differ: {c.stdout}{c.stderr}")
            return 1
        print(f"ok {name} twice: interrupted, its restart interrupted, restarted: {c.stdout.strip()}")
    return 0


def check_between_runs(name, scene, args, checkpoint, trigger, delay, step):
    """A signal while the scene's own Lua code runs between two runs: exit 143 with a
    checkpoint of the scene as the first run left it (at `step`), and its restart
    ends as the run never stopped does."""
    with tempfile.TemporaryDirectory() as work:
        whole, whole_stdout, _ = run_whole(scene, args, work)
        _, status, _, err = interrupt(scene, args, work, "between", trigger, delay, signal.SIGTERM)
        chk = os.path.join(work, "between", checkpoint)
        if status != 143 or not os.path.exists(chk) or "checkpoint written to" not in err:
            print(f"FAIL {name} between runs: status {status}, checkpoint "
                  f"{'kept' if os.path.exists(chk) else 'missing'}:\n{err}")
            return 1
        if checkpoint_step(chk) != step:
            print(f"FAIL {name} between runs: checkpoint at step {checkpoint_step(chk)}, not {step}")
            return 1
        cwd = folder(work, "between_resumed")
        r = subprocess.run([GRANULE, "run", scene, *args, "--restart", chk, "-o", "out.h5"],
                           cwd=cwd, env=ENV, capture_output=True, text=True, timeout=300)
        c = subprocess.run(["/usr/bin/python3", COMPARE, whole, os.path.join(cwd, "out.h5")],
                           capture_output=True, text=True)
        if r.returncode != 0 or r.stdout != whole_stdout or c.returncode != 0:
            print(f"FAIL {name} between runs: the restart ({r.returncode}) differs:\n{r.stderr}"
                  f"{c.stdout}{c.stderr}")
            return 1
        print(f"ok {name} between runs: stopped in Lua at step {step}, restarted: {c.stdout.strip()}")
    return 0


def check_refusals(scene, args):
    """A restart with other -D values, or of an edited scene, is refused by name."""
    failures = 0
    with tempfile.TemporaryDirectory() as work:
        cwd = folder(work, "run")
        subprocess.run([GRANULE, "run", scene, *args, "-o", "out.h5", "--quiet"], cwd=cwd,
                       env=ENV, capture_output=True, text=True, timeout=300, check=True)
        chk = os.path.join(cwd, "stages.chk.h5")
        other = [a.replace("stage_steps=", "stage_steps=1") for a in args]
        r = subprocess.run([GRANULE, "run", scene, *other, "--restart", chk, "-o", "r.h5"],
                           cwd=cwd, env=ENV, capture_output=True, text=True, timeout=300)
        if r.returncode == 0 or "parameter 'stage_steps' differs" not in r.stderr:
            print(f"FAIL refusal: a restart with other -D values ran ({r.returncode}): {r.stderr}")
            failures += 1
        else:
            print("ok refusal: other -D values")
        # The scene's default given explicitly (the first run left it out) is the same run.
        r = subprocess.run([GRANULE, "run", scene, *args, "-D", "checkpoint_every=5e3", "--restart",
                            chk, "-o", "d.h5", "--quiet"], cwd=cwd, env=ENV, capture_output=True,
                           text=True, timeout=300)
        if r.returncode != 0:
            print(f"FAIL refusal: a restart giving a default explicitly was refused: {r.stderr}")
            failures += 1
        else:
            print("ok: a restart may give a default explicitly")
        # The first run's output moved away: the restart fails as a restart, wherever in
        # the scene (a callback's call) its journal ended, and not as that callback's error.
        os.rename(os.path.join(cwd, "out.h5"), os.path.join(cwd, "moved.h5"))
        r = subprocess.run([GRANULE, "run", scene, *args, "--restart", chk, "-o", "out.h5"],
                           cwd=cwd, env=ENV, capture_output=True, text=True, timeout=300)
        error = [line for line in r.stderr.splitlines() if line.startswith("error:")]
        if (r.returncode == 0 or not error or not error[0].startswith("error: restart:")
                or "out.h5 of the run that wrote the checkpoint is missing" not in error[0]
                or "callback" in r.stderr):
            print(f"FAIL refusal: a restart without the first run's output ({r.returncode}): "
                  f"{r.stderr}")
            failures += 1
        else:
            print(f"ok refusal: the first run's output missing: {error[0]}")
        os.rename(os.path.join(cwd, "moved.h5"), os.path.join(cwd, "out.h5"))
        edited = os.path.join(cwd, os.path.basename(scene))
        lines = open(scene).read().split("\n")
        lines[20] += "  -- edited"
        open(edited, "w").write("\n".join(lines))
        r = subprocess.run([GRANULE, "run", edited, *args, "--restart", chk, "-o", "r.h5"],
                           cwd=cwd, env=ENV, capture_output=True, text=True, timeout=300)
        if r.returncode == 0 or "changed since" not in r.stderr or "line 21" not in r.stderr:
            print(f"FAIL refusal: a restart of an edited scene ran ({r.returncode}): {r.stderr}")
            failures += 1
        else:
            print("ok refusal: an edited scene")
    return failures


BRANCHING_SCENE = """
local p = parameters { more = { default = 0 } }
local sim = simulation { dimension = 2 }
sim:material { name = "glass", density = 2500 }
sim:contact { "glass", "glass", model = "linear", k_normal = 1e4, restitution = 0.8 }
sim:fill { region = { box = { lo = { 0, 0 }, hi = { 0.01, 0.01 } } }, count = 20, radius = 4e-4,
           material = "glass", seed = 3, overlap = false }
sim:run { steps = 100 }
if os.getenv("GRANULE_TEST_MORE") then
  sim:save_checkpoint("late.chk.h5")
  sim:run { steps = 100 }
end
print("done")
"""


def check_unreachable():
    """A checkpoint the scene never reaches (it ends first: another path, or a checkpoint
    written at the REPL's prompt) is refused by name, not passed over in silence."""
    failures = 0
    with tempfile.TemporaryDirectory() as work:
        scene = os.path.join(work, "branch.lua")
        open(scene, "w").write(BRANCHING_SCENE)
        subprocess.run([GRANULE, "run", scene, "-q"], cwd=work, check=True, capture_output=True,
                       env={**ENV, "GRANULE_TEST_MORE": "1"}, timeout=120)
        r = subprocess.run([GRANULE, "run", scene, "-q", "--restart", "late.chk.h5"], cwd=work,
                           env=ENV, capture_output=True, text=True, timeout=120)
        if r.returncode == 0 or "the scene ended before it reached the point" not in r.stderr:
            print(f"FAIL unreachable: a scene ending before its checkpoint ran ({r.returncode}): "
                  f"{r.stderr}")
            failures += 1
        else:
            print("ok unreachable: a scene that ends before the checkpoint's point")
        subprocess.run([GRANULE, "repl", scene, "-q"], cwd=work, env=ENV, capture_output=True,
                       input='sim:run { steps = 10 }\nsim:save_checkpoint("repl.chk.h5")\n',
                       text=True, timeout=120, check=True)
        r = subprocess.run([GRANULE, "run", scene, "-q", "--restart", "repl.chk.h5"], cwd=work,
                           env=ENV, capture_output=True, text=True, timeout=120)
        if r.returncode == 0 or "written at the granule repl prompt" not in r.stderr:
            print(f"FAIL unreachable: a checkpoint written at the REPL was continued "
                  f"({r.returncode}): {r.stderr}")
            failures += 1
        else:
            print("ok unreachable: a checkpoint written at the REPL's prompt")
    return failures


FEWER_CALLS_SCENE = """
local sim = simulation { dimension = 2 }
sim:material { name = "glass", density = 2500 }
sim:contact { "glass", "glass", model = "linear", k_normal = 1e4, restitution = 0.8 }
sim:fill { region = { box = { lo = { 0, 0 }, hi = { 0.01, 0.01 } } }, count = 20, radius = 4e-4,
           material = "glass", seed = 3, overlap = false }
local n, calls = 0, 0
sim:every { steps = 10, function(s)
  calls = calls + 1
  if os.getenv("GRANULE_TEST_MORE") and calls >= 10 then n = n + #s:walls() end
end }
sim:run { steps = 100 }
sim:save_checkpoint("calls.chk.h5")
sim:run { steps = 100 }
print("done")
"""


def check_fewer_calls():
    """A callback that makes fewer or more calls in the replay than in the run that wrote the
    checkpoint (its choice read something the journal does not keep: here the environment,
    in the run's last callback) is named as the scene taking another path, not as a damaged
    journal."""
    failures = 0
    with tempfile.TemporaryDirectory() as work:
        scene = os.path.join(work, "calls.lua")
        open(scene, "w").write(FEWER_CALLS_SCENE)
        more = {**ENV, "GRANULE_TEST_MORE": "1"}
        for first, restart, why in ((more, ENV, "a callback returned where in that run it went on "
                                                "to call sim:walls"),
                                    (ENV, more, "it called sim:walls where that run's callback had "
                                                "returned")):
            subprocess.run([GRANULE, "run", scene, "-q"], cwd=work, check=True,
                           capture_output=True, env=first, timeout=120)
            r = subprocess.run([GRANULE, "run", scene, "-q", "--restart", "calls.chk.h5"],
                               cwd=work, env=restart, capture_output=True, text=True, timeout=120)
            if r.returncode == 0 or "took another path" not in r.stderr or why not in r.stderr:
                print(f"FAIL other calls: not named as another path ({r.returncode}): {r.stderr}")
                failures += 1
            else:
                print(f"ok other calls: {why}")
    return failures


def main():
    failures = 0
    failures += check_unreachable()
    failures += check_fewer_calls()
    stages = os.path.join(SOURCE, "tests", "scenes", "restart_stages.lua")
    # The stage scene prints each stage's start with its step; stage k spans
    # [k * stage_steps, (k + 1) * stage_steps).
    n = 30000
    args = ["-D", f"stage_steps={n}"]
    failures += check_refusals(stages, ["-D", "stage_steps=3000"])
    failures += check_case(
        "stages", stages, args, "stages.chk.h5",
        [(s, rf"^stage {s} ", 0.2, lambda step, k=k: k * n < step < (k + 1) * n)
         for k, s in enumerate(["one", "two", "three"])])
    failures += check_twice("stages", stages, args, "stages.chk.h5",
                            (r"^stage one ", 0.2), (r"^stage two ", 0.2))
    failures += check_between_runs("stages", stages, args + ["-D", "busy=30000000"],
                                   "stages.chk.h5", r"^busy$", 0.3, n)
    # The tutorial drum: settling until at rest, then turning (its stages print
    # their end on stderr); Ctrl-C's checkpoint goes to tutorial_drum.checkpoint.h5.
    drum = os.path.join(SOURCE, "scenarios", "tutorial_drum.lua")
    drum_args = ["-D", "duration=0.3"]
    with tempfile.TemporaryDirectory() as work:
        _, _, err = run_whole(drum, drum_args, work)
    settled = int(re.search(r"stage settle .* after (\d+) steps", err).group(1))
    failures += check_case(
        "tutorial_drum", drum, drum_args, "tutorial_drum.checkpoint.h5",
        [("settle", r"granule: time step", 0.15, lambda step: 0 < step < settled),
         ("rotate", r"stage settle", 0.3, lambda step: step > settled)])
    # The Mechanofusion base case with its diagnostics (areas, zones, contact peaks, wall
    # forces), settled first and then measured; interrupted while it measures.
    mf = os.path.join(SOURCE, "scenarios", "mechanofusion.lua")
    failures += check_case(
        "mechanofusion", mf, ["-D", "settle=0.002", "-D", "duration=0.006"],
        "mechanofusion.checkpoint.h5",
        [("measure", r"granule: time step", 2.0, lambda step: step > 0)])
    # Schedules (sim:schedule): the drum's spin, the powder's friction and the central
    # field ramp in C++ before every step; interrupted in the middle of the ramps.
    ramps = os.path.join(SOURCE, "tests", "hooks", "schedule_restart.lua")
    failures += check_case(
        "schedules", ramps, ["-D", "steps=60000"], "schedules.chk.h5",
        [("ramp", r"^schedules start", 0.3, lambda step: 0 < step < 60000)])
    # A mesh wall (the hopper from its STL): the mesh's contacts and their
    # histories, across the gate's opening; interrupted while it discharges.
    hopper = os.path.join(SOURCE, "scenarios", "hopper_mesh.lua")
    with tempfile.TemporaryDirectory() as tools:
        stl = os.path.join(tools, "hopper.stl")
        subprocess.run(["/usr/bin/python3", os.path.join(SOURCE, "tools", "make_hopper_stl.py"),
                        "-o", stl, "--segments", "24", "--bands", "4"], check=True,
                       capture_output=True)
        hopper_args = ["-D", f"file={stl}", "-D", "particles=150", "-D", "settle=0.08",
                       "-D", "duration=0.15"]
        with tempfile.TemporaryDirectory() as work:
            _, _, err = run_whole(hopper, hopper_args, work)
        settled = int(re.search(r"stage settle .* after (\d+) steps", err).group(1))
        failures += check_case(
            "hopper_mesh", hopper, hopper_args, "hopper_mesh.checkpoint.h5",
            [("discharge", r"stage settle", 0.05, lambda step: step > settled)])
    print(f"restart stages: {'all passed' if failures == 0 else f'{failures} failed'}")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
