#!/usr/bin/python3
"""`granule sweep` end to end, on tests/scenes/sweep_case.lua (a sphere in free
flight, whose results are closed-form functions of its parameters).

    sweep_test.py serial GRANULE SOURCE_DIR WORK_DIR
    sweep_test.py mpi GRANULE SOURCE_DIR WORK_DIR MPIRUN

serial: the product of the values, the summary against x = v t, m = pi d^3 rho / 6,
p = m v; a Lua error, a crash (SIGSEGV) and a time step the engine refuses, each
reported while the other cases finish;
a rerun skips finished cases but reruns one whose mark is missing and one whose file
was cut short; a changed fixed value reruns everything; Ctrl-C stops the sweep with a
summary and a rerun finishes it; --list and --case-timeout; bad command lines exit 2.
mpi: `mpirun -np 2` shares the cases between both ranks and the summary is complete.
resume: a sweep killed outright (SIGKILL, as a lost node) mid-case, its case having
written a periodic checkpoint, is rerun: the case continues from the checkpoint (less
wall time, its log appended) and its results are the uninterrupted sweep's, bit for bit;
the finished case's checkpoint is removed.
rebuilt: the program file replaced while the sweep runs; the cases still to start
run on the sweep's own program.
Prints "sweep_test <mode> ok" at the end; any failed check raises.
"""
import csv
import math
import os
import shutil
import signal
import subprocess
import sys
import time

import h5py

MODE, GRANULE, SOURCE, WORK = sys.argv[1:5]
SCENE = os.path.join(SOURCE, "tests", "scenes", "sweep_case.lua")
RADIUS, DENSITY = 1e-3, 2500.0  # the scene's defaults


def sweep(*args, launcher=(), env=None):
    p = subprocess.run(list(launcher) + [GRANULE, "sweep", SCENE] + list(args),
                       capture_output=True, text=True, env=env, timeout=120)
    return p.returncode, p.stdout + p.stderr


def table(directory, scene="sweep_case"):
    with open(os.path.join(directory, scene + ".sweep.csv")) as f:
        return list(csv.DictReader(f))


def check(condition, message, output=""):
    if not condition:
        sys.exit(f"FAILED: {message}\n{output}")


def close(a, b, rel=1e-9):
    return abs(a - b) <= rel * max(abs(a), abs(b))


def check_results(row, radius=RADIUS):
    """The closed forms the scene must reproduce, for a case that finished."""
    v, t = float(row["speed"]), float(row.get("duration") or 0.01)
    mass = math.pi * (2 * radius) ** 3 * DENSITY / 6  # SPEC 2: m = pi d^3 rho / 6
    check(close(float(row["distance"]), v * t), f"case {row['case']}: distance {row['distance']} != v t = {v * t}")
    check(close(float(row["flight_time"]), t), f"case {row['case']}: flight time {row['flight_time']} != {t}")
    check(close(float(row["mass"]), mass), f"case {row['case']}: mass {row['mass']} != {mass}")
    check(close(float(row["momentum"]), mass * v), f"case {row['case']}: momentum {row['momentum']} != m v")
    check(close(float(row["result_speed"]), v) and row["result_status"] == "1",
          f"case {row['case']}: results named as a parameter and as status kept beside them: {row}")


def serial():
    out_dir = os.path.join(WORK, "sweep_serial")
    shutil.rmtree(out_dir, ignore_errors=True)
    args = ["-D", "speed=1,2,3,4,5", "-D", "duration=0.01,0.02", "-D", "fail_speed=3", "-D", "crash_speed=4",
            "-D", "unstable_speed=5", "-o", out_dir]
    rc, out = sweep(*args)
    check(rc == 1, f"a sweep with failed cases exits 1, got {rc}", out)
    rows = table(out_dir)
    check(len(rows) == 10, f"5 speeds x 2 durations = 10 cases, the summary has {len(rows)}", out)
    # The last -D varies fastest: (1, 0.01), (1, 0.02), (2, 0.01), ...
    check([(r["speed"], r["duration"]) for r in rows] ==
          [(v, t) for v in "12345" for t in ("0.01", "0.02")], "cases in product order", out)
    for r in rows:
        v = float(r["speed"])
        if v == 5:
            check(r["status"] == "failed" and "above the stability limit" in r["error"],
                  f"case {r['case']}: the engine's refusal is reported, got {r}", out)
        elif v == 3:
            check(r["status"] == "failed" and "speed 3 is the one told to fail" in r["error"],
                  f"case {r['case']}: the Lua error is reported, got {r}", out)
        elif v == 4:
            check(r["status"] == "failed" and "signal 11" in r["error"],
                  f"case {r['case']}: the crash is reported, got {r}", out)
        else:
            check(r["status"] == "ok", f"case {r['case']} finished despite the others, got {r}", out)
            check_results(r)
            with h5py.File(os.path.join(out_dir, r["file"]), "r") as f:
                check(f["sweep_case"].attrs["complete"] == 1, f"{r['file']} is marked finished")
    check("told to fail" in out and "signal 11" in out, "failures are reported as they happen", out)
    with h5py.File(os.path.join(out_dir, "sweep_case.sweep.h5"), "r") as f:
        speeds = sorted(f["sweep/speed"][:])
        check(speeds == [1, 1, 2, 2], f"the HDF5 summary holds the 4 finished cases, got {speeds}")
        check(f["sweep/distance"].shape == (4,), "the HDF5 summary has the results as columns")
        check(sorted(f["sweep/result_speed"][:]) == [1, 1, 2, 2] and list(f["sweep/case"][:]) == [0, 1, 2, 3],
              "a result named as a parameter or as case keeps its own column in /sweep")
        units = {c: f["sweep"][c].attrs.get("units") for c in ("speed", "wall_seconds", "case")}
        check(units == {"speed": "m/s", "wall_seconds": "s", "case": "-"},
              f"/sweep's columns carry the parameters' declared units, got {units}")
    with open(os.path.join(out_dir, "sweep_case.sweep.md")) as f:
        check(f.read().count("| ok |") == 4, "the markdown summary lists the finished cases")

    # --list names every case and its file, marks the finished ones, runs nothing.
    rc, out = sweep(*args, "--list")
    check(rc == 0 and out.count("(finished)") == 4 and len(out.splitlines()) == 10,
          "--list shows the 10 cases, 4 of them finished", out)

    # Rerun: finished cases are skipped, a case whose mark is missing (killed after the run,
    # before the mark) and one whose file is cut short (killed while writing) run again.
    ok = [r for r in rows if r["status"] == "ok"]
    paths = {r["case"]: os.path.join(out_dir, r["file"]) for r in ok}
    unmarked, cut = ok[1]["case"], ok[2]["case"]
    with h5py.File(paths[unmarked], "a") as f:
        del f["sweep_case"]
    size = os.path.getsize(paths[cut])
    with open(paths[cut], "r+b") as f:
        f.truncate(size // 2)
    before = {c: os.path.getmtime(p) for c, p in paths.items()}
    rc, out = sweep(*args)
    check(rc == 1 and "(2 finished earlier)" in out, f"the rerun skips the 2 intact cases, rc {rc}", out)
    rows = table(out_dir)
    for r in rows:
        if r["case"] in (unmarked, cut):
            check(r["status"] == "ok", f"case {r['case']} ran again, got {r}", out)
            check_results(r)
        elif r["case"] in paths:
            check(r["status"] == "reused", f"case {r['case']} was skipped, got {r}", out)
            check(os.path.getmtime(paths[r["case"]]) == before[r["case"]], f"case {r['case']} was not rewritten")
            check_results(r)
        else:
            check(r["status"] == "failed", f"case {r['case']} is tried again and fails again, got {r}", out)

    # Another value of a fixed parameter is another case: nothing is reused.
    rc, out = sweep(*args, "-D", "radius=2e-3")
    check(rc == 1 and "(0 finished earlier)" in out, "a changed fixed value reruns every case", out)
    for r in table(out_dir):
        if r["status"] == "ok":
            check_results(r, radius=2e-3)

    # Ctrl-C (SIGINT to the sweep, passed on to its running case) stops the sweep: the summary
    # is still written, the running case is "interrupted", the rest "not run", the status 130;
    # running the same command again finishes them all.
    stop_dir = os.path.join(WORK, "sweep_interrupted")
    shutil.rmtree(stop_dir, ignore_errors=True)
    stop_args = [GRANULE, "sweep", SCENE, "-D", "speed=1,2,3", "-D", "busy=0.6", "-o", stop_dir]
    p = subprocess.Popen(stop_args, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    first_log = os.path.join(stop_dir, "sweep_case_speed=1.log")
    for _ in range(600):  # until the first case has started (up to 30 s on a loaded machine)
        if os.path.exists(first_log) and "threads" in open(first_log).read():
            break
        time.sleep(0.05)
    time.sleep(0.1)
    p.send_signal(signal.SIGINT)
    out = p.communicate(timeout=60)[0]
    check(p.returncode == 130, f"an interrupted sweep exits 130, got {p.returncode}", out)
    status = [r["status"] for r in table(stop_dir)]
    check(status == ["interrupted", "not run", "not run"], f"statuses after Ctrl-C: {status}", out)
    p = subprocess.run(stop_args, capture_output=True, text=True, timeout=60)
    status = [r["status"] for r in table(stop_dir)]
    check(p.returncode == 0 and status == ["ok"] * 3, f"the rerun finishes them all: {status}",
          p.stdout + p.stderr)

    # --case-timeout stops a case that runs too long; the sweep goes on. (A fresh folder:
    # a rerun would continue the stopped case from its checkpoint.)
    shutil.rmtree(os.path.join(WORK, "sweep_timeout"), ignore_errors=True)
    rc, out = sweep("-D", "speed=1,2", "-D", "busy=20", "-D", "fail_speed=2", "--case-timeout", "0.5",
                    "-o", os.path.join(WORK, "sweep_timeout"))
    rows = table(os.path.join(WORK, "sweep_timeout"))
    check(rc == 1 and "--case-timeout" in rows[0]["error"] and float(rows[0]["wall_s"]) < 15,
          f"a case over --case-timeout is stopped and reported: {rows[0]}", out)
    check("told to fail" in rows[1]["error"], "the next case still runs after a timeout", out)

    # A sweep with nothing failing exits 0.
    rc, out = sweep("-D", "speed=5", "-o", os.path.join(WORK, "sweep_single"), "-q")
    check(rc == 0 and "1 of 1 cases finished" in out, f"one case, no failure: exit 0, got {rc}", out)

    # Bad command lines: exit 2, a message naming the parameter, no case run.
    for bad, message in ((["-D", "sped=1,2"], "no parameter 'sped' (did you mean 'speed'?)"),
                         (["-D", "speed=1,,2"], "value 2 of 'speed' is empty"),
                         (["-D", "speed=1", "-D", "speed=2"], "-D speed given twice"),
                         (["-D", "speed=1,fast"], "'speed' expects a number"),
                         (["-D", "speed=1,1"], "'speed' lists 1 twice"),
                         (["-D", "speed=1,2,1.0"], "'speed' lists 1 and 1.0, the same number")):
        rc, out = sweep(*bad, "-o", os.path.join(WORK, "sweep_bad"))
        check(rc == 2 and message in out, f"{' '.join(bad)}: exit 2 with '{message}', got {rc}", out)
    check(not os.path.exists(os.path.join(WORK, "sweep_bad")), "a refused sweep runs nothing")
    p = subprocess.run([GRANULE, "sweep", "no_such_scene.lua", "-D", "speed=1"], capture_output=True, text=True)
    check(p.returncode == 2 and "cannot open scene file 'no_such_scene.lua'" in p.stderr,
          "a missing scene is named", p.stderr)


def mpi(mpirun):
    out_dir = os.path.join(WORK, "sweep_mpi")
    shutil.rmtree(out_dir, ignore_errors=True)
    env = dict(os.environ)
    # Open MPI in a container, maybe as root, two ranks on however many cores: allowed,
    # shared memory between ranks without ptrace-based single copy.
    for k, v in (("OMPI_ALLOW_RUN_AS_ROOT", "1"), ("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1"),
                 ("OMPI_MCA_rmaps_base_oversubscribe", "1"), ("OMPI_MCA_btl", "self,vader"),
                 ("OMPI_MCA_btl_vader_single_copy_mechanism", "none")):
        env.setdefault(k, v)
    # Each case waits 0.3 s of wall time, so that both ranks are asked for work.
    rc, out = sweep("-D", "speed=1,2,3,4,5,6", "-D", "hold=0.3", "-o", out_dir, launcher=[mpirun, "-np", "2"],
                    env=env)
    check(rc == 0, f"mpirun -np 2 sweep exits 0, got {rc}", out)
    check("2 ranks" in out, "the sweep runs on 2 ranks", out)
    rows = table(out_dir)
    check(len(rows) == 6 and all(r["status"] == "ok" for r in rows), "all 6 cases finished", out)
    ranks = sorted({r["rank"] for r in rows})
    check(ranks == ["0", "1"], f"both ranks ran cases, got ranks {ranks}", out)
    for r in rows:
        check_results(r)


def resume():
    drum = os.path.join(SOURCE, "scenarios", "tutorial_drum.lua")
    common = ["-D", "duration=1.5"]

    def run_sweep(directory, *extra):
        return subprocess.Popen([GRANULE, "sweep", drum, *common, "-o", directory, *extra],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                start_new_session=True)

    ref_dir, cut_dir = os.path.join(WORK, "sweep_resume_ref"), os.path.join(WORK, "sweep_resume_cut")
    for d in (ref_dir, cut_dir):
        shutil.rmtree(d, ignore_errors=True)
    p = run_sweep(ref_dir, "--checkpoint-every", "0")
    out = p.communicate(timeout=120)[0]
    check(p.returncode == 0, f"the uninterrupted sweep exits 0, got {p.returncode}", out)
    started = time.time()
    p = run_sweep(cut_dir, "--checkpoint-every", "0.3")
    checkpoint = os.path.join(cut_dir, "tutorial_drum.checkpoint.h5")
    deadline = time.time() + 60
    while not os.path.exists(checkpoint) and p.poll() is None and time.time() < deadline:
        time.sleep(0.05)
    check(os.path.exists(checkpoint), "the case writes its checkpoint into the sweep's directory")
    time.sleep(0.5)  # past a second checkpoint, into the run
    os.killpg(p.pid, signal.SIGKILL)
    p.wait()
    # The killed part's wall time up to its last checkpoint counts in the case's wall_s.
    parts = checkpoint + ".wall_s"
    check(os.path.exists(parts), "the case's part start is kept beside its checkpoint")
    with open(parts) as f:
        before, began = map(float, f.read().split())
    killed_part = os.path.getmtime(checkpoint) - began
    check(before == 0 and started - 1 <= began and killed_part > 0.2,
          f"the first part began at {began - started:.3f} s, checkpointed {killed_part:.3f} s in")
    listed = subprocess.run([GRANULE, "sweep", drum, *common, "-o", cut_dir, "--list"], capture_output=True,
                            text=True).stdout
    check("continues from" in listed, "--list says the case continues from its checkpoint", listed)
    # The checkpoint, continued by a sweep whose fixed value differs (the same file
    # names: only varying values name files), is set aside: the case runs from its
    # start rather than fail at every rerun on the restart's refusal.
    other_dir = os.path.join(WORK, "sweep_resume_other")
    shutil.rmtree(other_dir, ignore_errors=True)
    os.makedirs(other_dir)
    shutil.copy(checkpoint, other_dir)
    other = subprocess.run([GRANULE, "sweep", drum, "-D", "duration=0.3", "-o", other_dir],
                           capture_output=True, text=True, timeout=120)
    check(other.returncode == 0 and "not continuing" in other.stderr and
          os.path.exists(os.path.join(other_dir, "tutorial_drum.checkpoint.h5.set-aside")),
          f"a checkpoint of other -D values is set aside and the case runs (exit {other.returncode})",
          other.stdout + other.stderr)
    p = run_sweep(cut_dir, "--checkpoint-every", "0.3")
    # A second sweep into the same folder while the first runs is refused.
    deadline = time.time() + 30
    while not os.path.exists(os.path.join(cut_dir, ".granule-sweep.lock")) and time.time() < deadline:
        time.sleep(0.05)
    time.sleep(0.2)
    second = subprocess.run([GRANULE, "sweep", drum, *common, "-o", cut_dir], capture_output=True,
                            text=True, timeout=60)
    check(second.returncode != 0 and "another granule sweep" in second.stderr,
          f"a second sweep into a folder in use is refused (exit {second.returncode})",
          second.stdout + second.stderr)
    out = p.communicate(timeout=120)[0]
    check(p.returncode == 0, f"the rerun finishes the case, got exit {p.returncode}", out)
    check("continued from its checkpoint" in out, "the case went on from its checkpoint", out)
    wall = float(table(cut_dir, "tutorial_drum")[0]["wall_s"])
    check(wall > killed_part and not os.path.exists(parts),
          f"the continued case's wall_s ({wall:.3f} s) counts the killed part's {killed_part:.3f} s")
    with h5py.File(os.path.join(ref_dir, "tutorial_drum.h5"), "r") as a, \
            h5py.File(os.path.join(cut_dir, "tutorial_drum.h5"), "r") as b:
        ra, rb = dict(a["results"].attrs), dict(b["results"].attrs)
        check(ra.keys() == rb.keys() and all((ra[k] == rb[k]).all() for k in ra),
              f"the continued case's results are the uninterrupted one's, bit for bit: {ra} vs {rb}")
        check((a["series/time"][:] == b["series/time"][:]).all(), "and so are its series' times")
    check(not os.path.exists(checkpoint), "a finished case's checkpoint is removed")
    with open(os.path.join(cut_dir, "tutorial_drum.log")) as f:
        log = f.read()
    # The killed run's header stays, followed by the rerun's "continuing from" line
    # (where the kill fell depends on the machine's load: before or after the first stage).
    head, _, rest = log.partition("continuing from")
    check("granule: particles:" in head and rest, "the continued case's log is appended, not replaced", log)
    # A finished case of the scene as it was is not a finished case of an edited one.
    edited = os.path.join(WORK, "sweep_resume_edit", "tutorial_drum.lua")
    os.makedirs(os.path.dirname(edited), exist_ok=True)
    shutil.copy(drum, edited)
    listed = subprocess.run([GRANULE, "sweep", edited, *common, "-o", cut_dir, "--list"],
                            capture_output=True, text=True).stdout
    check("(finished)" in listed, "the same scene's finished case is listed as finished", listed)
    with open(edited, "a") as f:
        f.write("-- edited\n")
    listed = subprocess.run([GRANULE, "sweep", edited, *common, "-o", cut_dir, "--list"],
                            capture_output=True, text=True).stdout
    check("another version of the scene" in listed, "an edited scene's case runs again", listed)


def rebuilt():
    """The program replaced while a sweep runs (a rebuild during a long study): the
    cases still to start run on the sweep's own program, not the new file."""
    directory = os.path.join(WORK, "sweep_rebuilt")
    shutil.rmtree(directory, ignore_errors=True)
    os.makedirs(directory)
    program = os.path.join(directory, "granule")
    shutil.copy2(GRANULE, program)
    drum = os.path.join(SOURCE, "scenarios", "tutorial_drum.lua")
    out_dir = os.path.join(directory, "out")
    p = subprocess.Popen([program, "sweep", drum, "-D", "duration=0.3,0.31,0.32", "-o", out_dir,
                          "--threads", "1"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    first_log = os.path.join(out_dir, "tutorial_drum_duration=0.3.log")
    deadline = time.time() + 60
    while not os.path.exists(first_log) and p.poll() is None and time.time() < deadline:
        time.sleep(0.02)
    check(p.poll() is None, "the sweep is still running its first case when the program is replaced")
    # What a rebuild does: the old file removed, another program at its path.
    os.remove(program)
    with open(program, "w") as f:
        f.write("#!/bin/sh\necho 'not the sweep program' >&2\nexit 3\n")
    os.chmod(program, 0o755)
    out = p.communicate(timeout=120)[0]
    check(p.returncode == 0, f"the sweep finishes every case, got exit {p.returncode}", out)
    rows = table(out_dir, "tutorial_drum")
    check(len(rows) == 3 and all(r["status"] == "ok" for r in rows),
          f"all three cases finished: {[r.get('status') for r in rows]}", out)
    for r in rows:
        with open(os.path.join(out_dir, r["file"].replace(".h5", ".log"))) as f:
            log = f.read()
        check("not the sweep program" not in log, f"case {r['file']} ran the replacing file", log)


if MODE == "serial":
    serial()
elif MODE == "resume":
    resume()
elif MODE == "mpi":
    mpi(sys.argv[5])
elif MODE == "rebuilt":
    rebuilt()
else:
    sys.exit(f"unknown mode {MODE}")
print(f"sweep_test {MODE} ok")
