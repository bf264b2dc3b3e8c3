#!/usr/bin/python3
"""A restart continues the run that wrote its checkpoint, or is refused by name.

Cases of tests/scenes/restart_trust.lua, each in a folder of its own:
- pairs: a scene that makes one group per key of a string-keyed table, in pairs()
  order, makes them in the same order in every process (Lua's own order changes with
  its per-process hash seed), and its restart prints what the whole run printed;
- args: a call given other values at the restart than in the run that wrote the
  checkpoint (a count read from the environment) is refused, naming the call;
- module: a module the scene requires, changed after the checkpoint, is refused;
- mesh: a mesh written to a file os.tmpname names restarts (the name is journaled);
- pcall: a scene that catches its runs' errors still stops on SIGTERM (status 143);
- prerun: a signal before the first step writes no checkpoint and says so;
- replay_stop: a signal while a restart replays the past says to continue from the same
  checkpoint, which then continues;
- views: a restart whose replayed past reads sim:arrays() warns that the values kept
  from them differ;
- second: a second simulation used after the checkpoint's point is refused (the restart
  rebuilds it without its particles);
- history: a restart from a checkpoint before the output got contact histories, after the
  whole run ended, writes them again and ends with the whole run's file;
- other_file: an output file another run wrote anew since the checkpoint is refused;
- mesh_file: a mesh file edited since the checkpoint is refused;
- attach: a diagnostic that follows contacts, attached after the checkpoint's point to a
  bed in contact, counts in the restart what it counts in the whole run.
- last_step: the last step's results a script reads between runs (recorded contacts,
  the walls' reactions, stats()' tallies), read after a checkpoint written between runs,
  are in the restart what they were in the whole run (2D and 3D).

    restart_trust_test.py GRANULE SOURCE_DIR
"""
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

GRANULE, SOURCE = sys.argv[1], sys.argv[2]
SCENE = os.path.join(SOURCE, "tests", "scenes", "restart_trust.lua")
ENV = dict(os.environ, GRANULE_PROGRESS_AFTER="1e9")


def run(cwd, case, *extra, env=None):
    return subprocess.run([GRANULE, "run", SCENE, "-D", f"case={case}", "-q", *extra], cwd=cwd,
                          env=env or ENV, capture_output=True, text=True, timeout=120)


def fail(what, r):
    sys.exit(f"{what} (status {r.returncode})\nstdout: {r.stdout}\nstderr: {r.stderr}")


def signal_after(cwd, case, line, signum, delay, *extra, env=None):
    """Runs the case until it prints `line`, waits `delay` s, sends `signum`; returns
    the status and everything it printed (stdout from that line on, stderr)."""
    p = subprocess.Popen([GRANULE, "run", SCENE, "-D", f"case={case}", "-q", *extra], cwd=cwd,
                         env=env or ENV, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         text=True)
    first = p.stdout.readline()
    if first.strip() != line:
        p.kill()
        sys.exit(f"{case}: expected {line!r}, got {first!r}")
    time.sleep(delay)
    p.send_signal(signum)
    out, err = p.communicate(timeout=120)
    return p.returncode, first + out, err


def whole_run(d, case, env=None):
    """The case run whole, from its start; any failure ends the test."""
    r = run(d, case, env=env)
    if r.returncode != 0:
        fail(f"{case}: the whole run failed", r)
    return r


def same_as_whole(d, case):
    """The restart's file (<case>_restarted.h5) equals the whole run's (whole.h5), bit for
    bit (compare_runs.py); any difference ends the test."""
    compare = subprocess.run([sys.executable, os.path.join(SOURCE, "tests", "scenes",
                                                          "compare_runs.py"),
                              os.path.join(d, "whole.h5"), os.path.join(d, f"{case}_restarted.h5")],
                             capture_output=True, text=True)
    if compare.returncode != 0:
        sys.exit(f"{case}: the restarted file differs from the whole run's:\n{compare.stdout}"
                 f"{compare.stderr}")


def case_folder(work, name):
    path = os.path.join(work, name)
    os.makedirs(path)
    return path


def pairs_case(work):
    d = case_folder(work, "pairs")
    whole = [run(d, "pairs") for _ in range(3)]
    for r in whole:
        if r.returncode != 0:
            fail("pairs: the whole run failed", r)
    if len({r.stdout for r in whole}) != 1:
        sys.exit("pairs: three processes printed different lines:\n" +
                 "\n".join(r.stdout for r in whole))
    order = whole[0].stdout.splitlines()[0].split()[1:]
    if order != sorted(order):
        sys.exit(f"pairs: string keys not in byte order: {order}")
    r = run(d, "pairs", "--restart", "trust.chk.h5")
    if r.returncode != 0 or r.stdout != whole[0].stdout:
        fail(f"pairs: the restart did not print the whole run's lines {whole[0].stdout!r}", r)
    print("pairs: one order in every process; the restart prints the whole run's lines")


def args_case(work):
    d = case_folder(work, "args")
    whole_run(d, "args", env=dict(ENV, GRANULE_TRUST_COUNT="10"))
    r = run(d, "args", "--restart", "trust.chk.h5", env=dict(ENV, GRANULE_TRUST_COUNT="11"))
    if r.returncode == 0 or "sim:fill, was given other values than in that run" not in r.stderr:
        fail("args: a call given other values at the restart was not refused by name", r)
    r = run(d, "args", "--restart", "trust.chk.h5", env=dict(ENV, GRANULE_TRUST_COUNT="10"))
    if r.returncode != 0 or "args done" not in r.stdout:
        fail("args: the restart with the same values failed", r)
    print("args: other values refused, the same values continue")


def module_case(work):
    d = case_folder(work, "module")
    helper = os.path.join(d, "trust_helper.lua")
    with open(helper, "w") as f:
        f.write("return { count = 10 }\n")
    whole_run(d, "module")
    with open(helper, "w") as f:
        f.write("return { count = 10 } -- edited\n")
    r = run(d, "module", "--restart", "trust.chk.h5")
    if r.returncode == 0 or "trust_helper.lua that the scene required changed" not in r.stderr:
        fail("module: a changed module was not refused by name", r)
    print("module: a module changed since the checkpoint is refused")


def mesh_case(work):
    d = case_folder(work, "mesh")
    whole = whole_run(d, "mesh")
    r = run(d, "mesh", "--restart", "trust.chk.h5")
    if r.returncode != 0 or r.stdout != whole.stdout:
        fail(f"mesh: the restart did not print the whole run's line {whole.stdout!r}", r)
    print("mesh: a mesh file named by os.tmpname restarts (the name is journaled)")


def pcall_case(work):
    d = case_folder(work, "pcall")
    status, out, err = signal_after(d, "pcall", "stage 1", signal.SIGTERM, 1.0)
    # The scene's own Lua goes on to its end; its engine calls after the stop fail.
    later = [line for line in out.splitlines() if line.startswith(("stage 2 ", "stage 3 "))]
    if status != 143 or len(later) != 2 or \
            not all("sim:run: the scene was stopped" in line for line in later):
        sys.exit(f"pcall: a caught SIGTERM did not stop the scene's runs (status "
                 f"{status})\nstdout: {out}\nstderr: {err}")
    print("pcall: a scene that catches its run's stop runs no more and ends with status 143")


def prerun_case(work):
    d = case_folder(work, "prerun")
    status, _, err = signal_after(d, "prerun", "busy", signal.SIGINT, 0.3, "--checkpoint",
                                  "pre.chk.h5")
    if status != 130 or "no checkpoint was written" not in err:
        sys.exit(f"prerun: status {status}, stderr: {err}")
    if os.path.exists(os.path.join(d, "pre.chk.h5")):
        sys.exit("prerun: a checkpoint was written before the first step")
    print("prerun: a stop before the first step writes no checkpoint and says so")


def replay_stop_case(work):
    d = case_folder(work, "replay_stop")
    whole_run(d, "replay_stop")
    status, _, err = signal_after(d, "replay_stop", "busy", signal.SIGINT, 0.3, "--restart",
                                  "trust.chk.h5", env=dict(ENV, GRANULE_TRUST_LOOP="1e10"))
    if status != 130 or "continue from trust.chk.h5 again" not in err:
        sys.exit(f"replay_stop: status {status}, stderr: {err}")
    r = run(d, "replay_stop", "--restart", "trust.chk.h5")
    if r.returncode != 0 or "replay_stop done" not in r.stdout:
        fail("replay_stop: the same checkpoint did not continue afterwards", r)
    print("replay_stop: a stop while a restart replays says to continue from the same file")


def views_case(work):
    d = case_folder(work, "views")
    whole_run(d, "views")
    r = run(d, "views", "--restart", "trust.chk.h5")
    if r.returncode != 0 or "warning: restart:" not in r.stderr or "sim:arrays()" not in r.stderr:
        fail("views: no warning that the replayed past read sim:arrays()", r)
    print("views: the restart warns that the replay read sim:arrays()")


def second_case(work):
    d = case_folder(work, "second")
    whole_run(d, "second")
    r = run(d, "second", "--restart", "trust.chk.h5")
    if r.returncode == 0 or "not the scene's first simulation" not in r.stderr:
        fail("second: a second simulation used after the checkpoint was not refused", r)
    print("second: a second simulation used after the checkpoint's point is refused")


def history_case(work):
    d = case_folder(work, "history")
    whole_run(d, "history")
    os.replace(os.path.join(d, "history.h5"), os.path.join(d, "whole.h5"))
    whole_run(d, "history")  # the file as the first run left it: contact histories in it
    r = run(d, "history", "--restart", "trust.chk.h5")
    if r.returncode != 0 or "history done" not in r.stdout:
        fail("history: the restart after the whole run ended failed", r)
    same_as_whole(d, "history")
    print("history: a restart after the run ended writes the contact histories again")


def other_file_case(work):
    d = case_folder(work, "other_file")
    whole_run(d, "other_file")
    whole_run(d, "other_file", env=dict(ENV, GRANULE_TRUST_CHECKPOINT="second.chk.h5"))
    r = run(d, "other_file", "--restart", "trust.chk.h5")
    if r.returncode == 0 or "not the file the checkpoint's run wrote" not in r.stderr \
            or "written anew by another run" not in r.stderr or "warning" in r.stderr:
        fail("other_file: a restart into another run's file was not refused, or not cleanly", r)
    if os.path.exists(os.path.join(d, "other_restarted.h5")):
        sys.exit("other_file: the refused restart left its copy of the file behind")
    print("other_file: an output another run wrote since the checkpoint is refused")


def mesh_file_case(work):
    d = case_folder(work, "mesh_file")

    def floor(z):
        with open(os.path.join(d, "trust_floor.obj"), "w") as f:
            f.write(f"v -0.01 -0.01 {z}\nv 0.01 -0.01 {z}\nv 0.01 0.01 {z}\nv -0.01 0.01 {z}\n"
                    "f 1 2 3\nf 1 3 4\n")
    floor(0)
    whole_run(d, "mesh_file")
    floor(-1e-4)
    r = run(d, "mesh_file", "--restart", "trust.chk.h5")
    if r.returncode == 0 or "is not the mesh the checkpoint was written with" not in r.stderr:
        fail("mesh_file: a mesh file edited since the checkpoint was not refused", r)
    floor(0)
    r = run(d, "mesh_file", "--restart", "trust.chk.h5")
    if r.returncode != 0 or "mesh_file done" not in r.stdout:
        fail("mesh_file: the restart with the mesh as it was failed", r)
    print("mesh_file: a mesh file edited since the checkpoint is refused")


def attach_case(work):
    d = case_folder(work, "attach")
    whole = whole_run(d, "attach")
    shutil.copyfile(os.path.join(d, "attach.h5"), os.path.join(d, "whole.h5"))
    r = run(d, "attach", "--restart", "trust.chk.h5")
    if r.returncode != 0 or r.stdout != whole.stdout:
        fail(f"attach: the restart did not print the whole run's line {whole.stdout!r}", r)
    same_as_whole(d, "attach")
    print("attach: a diagnostic attached after the checkpoint counts as in the whole run")


def last_step_case(work):
    for dimension in ("2", "3"):
        d = case_folder(work, f"last_step_{dimension}d")
        whole = run(d, "last_step", "-D", f"dimension={dimension}")
        if whole.returncode != 0:
            fail(f"last_step: the whole {dimension}D run failed", whole)
        if " 0 contacts" in whole.stdout or "stats 0 " in whole.stdout:
            fail(f"last_step: the {dimension}D scene's bed has no pair contacts", whole)
        r = run(d, "last_step", "-D", f"dimension={dimension}", "--restart", "trust.chk.h5")
        if r.returncode != 0 or r.stdout != whole.stdout:
            fail(f"last_step: the {dimension}D restart did not read the whole run's last step "
                 f"{whole.stdout!r}", r)
    # The same over two MPI ranks: the checkpoint is the gathered scene's.
    mpirun = shutil.which("mpirun")
    if mpirun:
        d = case_folder(work, "last_step_ranks")
        over = [mpirun, "--allow-run-as-root", "--oversubscribe", "-np", "2", GRANULE, "run", SCENE,
                "-D", "case=last_step", "-D", "dimension=3", "-q"]
        whole = subprocess.run(over, cwd=d, env=ENV, capture_output=True, text=True, timeout=300)
        if whole.returncode != 0 or " 0 contacts" in whole.stdout:
            fail("last_step: the whole run on 2 ranks failed or found no contacts", whole)
        r = subprocess.run(over + ["--restart", "trust.chk.h5"], cwd=d, env=ENV, capture_output=True,
                           text=True, timeout=300)
        if r.returncode != 0 or r.stdout != whole.stdout:
            fail(f"last_step: the restart on 2 ranks did not read the whole run's last step "
                 f"{whole.stdout!r}", r)
    print("last_step: the last step's contacts, reactions and tallies are read after a restart")


with tempfile.TemporaryDirectory() as work:
    for case in (pairs_case, args_case, module_case, mesh_case, pcall_case, prerun_case,
                 replay_stop_case, views_case, second_case, history_case, other_file_case,
                 mesh_file_case, attach_case, last_step_case):
        case(work)
print("restart trust: all passed")
