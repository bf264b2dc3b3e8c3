#!/usr/bin/python3
"""A run killed at any moment after a checkpoint, even in the middle of a write
to its output file, restarts from that checkpoint into the same file and ends
as a run never stopped: the same lines printed, the output identical bit for
bit (compare_runs.py).

HDF5 changes a file's metadata in place, so a kill between two of its writes
can leave a file whose links point past its recorded end; the restart puts the
file back from its journal (src/io/journalled_file.hpp) before continuing it.
The kill falls on chosen writes: GRANULE_KILL_AT_JOURNALLED_WRITE=N makes the
program kill itself in its N-th write (or truncation) after a checkpoint, half
of the file's bytes written (odd N) or half of the journal record that saves
them (even N). Kills land on every one of the first 71 writes (where, without
the journal, kills at writes 21-22 and 55-68 left a file the restart could not
continue), then more and more sparsely up to the run's end; every third
restart is killed again while it cuts the file back.

Under mpirun (a third argument: mpirun's path) the scene runs on two ranks:
rank 0 puts the file back and cuts it while rank 1 copies it into its scratch
folder, which must happen first; fewer kill points, compared with an
uninterrupted run on two ranks.

With --without-journal the journal is deleted before each restart (the program
without it, as before it kept one) and the script reports how many kill points
leave a file the restart cannot continue or continues wrongly, exiting 0.

    killed_restart_test.py GRANULE SOURCE_DIR [MPIRUN] [--without-journal]
"""
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

WITHOUT_JOURNAL = "--without-journal" in sys.argv
ARGV = [a for a in sys.argv if a != "--without-journal"]
GRANULE, SOURCE = ARGV[1], ARGV[2]
MPIRUN = ARGV[3] if len(ARGV) > 3 else None
COMPARE = os.path.join(SOURCE, "tests", "scenes", "compare_runs.py")
SCENE = os.path.join(SOURCE, "tests", "scenes", "restart_stages.lua")
ARGS = ["-D", "stage_steps=900", "-D", "checkpoint_every=250", "-D", "snapshot_every=2e-4",
        "-D", "checkpoint=run.chk.h5"]
ENV = dict(os.environ, GRANULE_PROGRESS_AFTER="1e9")
KILL = "GRANULE_KILL_AT_JOURNALLED_WRITE"


def run(cwd, extra=(), kill_at=None, args=ARGS):
    command = [GRANULE, "run", SCENE, *args, *extra, "-o", "out.h5"]
    env = dict(ENV)
    if MPIRUN:
        # Two ranks; rank 0 alone (the one writing the file) kills itself mid-write,
        # and mpirun then ends rank 1.
        kill = ["-x", f"{KILL}={kill_at}"] if kill_at is not None else []
        command = [MPIRUN, "--allow-run-as-root", "--oversubscribe", "-np", "1", *kill, *command,
                   ":", "-np", "1", *command]
    elif kill_at is not None:
        env[KILL] = str(kill_at)
    return subprocess.run(command, cwd=cwd, env=env, capture_output=True, text=True, timeout=300)


def was_killed(result):
    """Died of SIGKILL (under mpirun, which exits with a status of its own, a rank's)."""
    if MPIRUN:
        return result.returncode != 0 and "signal 9" in result.stdout + result.stderr
    return result.returncode == -signal.SIGKILL


def same_output(a, b):
    r = subprocess.run(["/usr/bin/python3", COMPARE, a, b], capture_output=True, text=True)
    return r.returncode == 0, r.stdout + r.stderr


def restart_beside_live_run(work):
    """A restart started while the run that wrote the checkpoint still writes its
    output is refused before it touches the file, and so is a new run into that
    file (the live run's journal kept); the run ends as if alone."""
    longer = ["-D", "stage_steps=12000", "-D", "checkpoint_every=2000", "-D", "snapshot_every=2e-4",
              "-D", "checkpoint=run.chk.h5"]
    alone = os.path.join(work, "alone")
    os.makedirs(alone)
    reference = run(alone, args=longer)
    cwd = os.path.join(work, "live")
    os.makedirs(cwd)
    command = [GRANULE, "run", SCENE, *longer, "-o", "out.h5"]
    live = subprocess.Popen(command, cwd=cwd, env=ENV, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    checkpoint = os.path.join(cwd, "run.chk.h5")
    deadline = time.time() + 120
    while not os.path.exists(checkpoint) and live.poll() is None and time.time() < deadline:
        time.sleep(0.02)
    second = run(cwd, ["--restart", "run.chk.h5"], args=longer)
    # A new run into the same file: refused, the live run's journal kept.
    fresh = run(cwd, args=[a.replace("run.chk.h5", "other.chk.h5") for a in longer])
    journal_kept = os.path.exists(os.path.join(cwd, "out.h5.journal"))
    out, err = live.communicate(timeout=300)
    failures = 0
    if fresh.returncode == 0 or "open for writing elsewhere" not in fresh.stderr or \
            not journal_kept:
        print(f"FAIL: a new run into the live run's file: exit {fresh.returncode}, journal kept "
              f"{journal_kept}\n{fresh.stderr}")
        failures += 1
    if live.returncode is None or second.returncode == 0 or \
            "being written by another process" not in second.stderr:
        print(f"FAIL: a restart beside the live run: exit {second.returncode}\n{second.stderr}")
        failures += 1
    ok, why = same_output(os.path.join(alone, "out.h5"), os.path.join(cwd, "out.h5"))
    if live.returncode != 0 or out != reference.stdout or not ok:
        print(f"FAIL: the live run, beside a refused restart: exit {live.returncode}, {why}\n{err}")
        failures += 1
    return failures


def main():
    failures, kills = 0, 0
    largest = (0, 0)  # the largest journal seen after a kill, and its file's size (bytes)
    with tempfile.TemporaryDirectory() as work:
        whole_dir = os.path.join(work, "whole")
        os.makedirs(whole_dir)
        whole = run(whole_dir)
        if whole.returncode != 0:
            sys.exit(f"the whole run failed ({whole.returncode}): {whole.stderr}")
        if os.path.exists(os.path.join(whole_dir, "out.h5.journal")):
            print("FAIL: a run that ended cleanly left its journal")
            failures += 1
        if MPIRUN:
            points = [3, 22, 59, 64, 100000]
        else:
            points = list(range(1, 72))
            while points[-1] < 100000:
                points.append(int(points[-1] * 1.3) + 1)
        ran_through = False
        for n in points:
            cwd = os.path.join(work, f"kill_{n}")
            os.makedirs(cwd)
            killed = run(cwd, kill_at=n)
            if killed.returncode == 0:
                ran_through = True  # fewer writes than n after the first checkpoint
                break
            if not was_killed(killed):
                print(f"FAIL kill at write {n}: exit status {killed.returncode}\n{killed.stderr}")
                failures += 1
                continue
            kills += 1
            if not os.path.exists(os.path.join(cwd, "run.chk.h5")):
                print(f"FAIL kill at write {n}: no checkpoint before the kill")
                failures += 1
                continue
            # Every third point: the restart is killed too, on its first writes (cutting
            # the file back to the checkpoint), then restarted again.
            if n % 3 == 0:
                again = run(cwd, ["--restart", "run.chk.h5"], kill_at=1 + n % 4)
                if not was_killed(again):
                    print(f"FAIL kill at write {n}, restart killed: exit {again.returncode}\n"
                          f"{again.stderr}")
                    failures += 1
                    continue
                kills += 1
            journal = os.path.join(cwd, "out.h5.journal")
            if os.path.exists(journal):
                largest = max(largest, (os.path.getsize(journal), os.path.getsize(
                    os.path.join(cwd, "out.h5"))))
                if WITHOUT_JOURNAL:
                    os.remove(journal)
            resumed = run(cwd, ["--restart", "run.chk.h5"])
            if resumed.returncode != 0:
                print(f"FAIL kill at write {n}: the restart exits {resumed.returncode}\n"
                      f"{resumed.stderr}")
                failures += 1
                continue
            if resumed.stdout != whole.stdout:
                print(f"FAIL kill at write {n}: the restart prints\n{resumed.stdout}\n"
                      f"the whole run\n{whole.stdout}")
                failures += 1
            ok, why = same_output(os.path.join(whole_dir, "out.h5"), os.path.join(cwd, "out.h5"))
            if not ok:
                print(f"FAIL kill at write {n}: the output differs from the whole run's: {why}")
                failures += 1
            shutil.rmtree(cwd)
        if not ran_through:
            print("FAIL: no kill point lay past the run's last write")
            failures += 1
        if not MPIRUN and not WITHOUT_JOURNAL:
            failures += restart_beside_live_run(work)
    if WITHOUT_JOURNAL:
        print(f"without the journal: {failures} of {kills} kill points fail")
        return
    if failures or kills < (4 if MPIRUN else 15):
        sys.exit(f"{failures} failures, {kills} kills")
    print(f"killed restarts identical ({kills} kills{' on 2 ranks' if MPIRUN else ''}; "
          f"journal up to {largest[0] / 1e3:.0f} kB beside a {largest[1] / 1e3:.0f} kB file)")


main()
