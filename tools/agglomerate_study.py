#!/usr/bin/python3
"""Run a chapter 7 study: one agglomerate test over velocities, surface energies and agglomerates (seeds).

usage: /usr/bin/python3 tools/agglomerate_study.py host|wall|compression
           [--dimension 2] [--velocities 0.05,0.1,0.2,0.4,0.6,1.0] [--gammas 1,2] [--seeds 1-5]
           [--work study] [--data DIR] [--figures DIR] [--prepare name=value ...] [--test name=value ...]
           [--jobs 1] [--granule build/granule]
       /usr/bin/python3 tools/agglomerate_study.py host|wall|compression --from-csv docs/data/agglomerate_host_2d.csv
           [--dimension 2] [--figures DIR]

For every surface energy Gamma and seed it prepares an agglomerate once
(scenarios/agglomerate_prepare.lua -D seed=S -> WORK/agglomerate_<d>d_g<Gamma>_s<S>.h5, 7.3;
a different random start per seed), then runs the test scene at every velocity
(-> WORK/<protocol>_<d>d_g<Gamma>_s<S>_v<v>.h5). Outputs that exist are reused;
delete them to run again. It then writes
  DATA/agglomerate_<protocol>_<d>d<label>_runs.csv  one row per run: final ratios (contact graph and
                       surviving-bond graph; debris by mass, 7.4, and by size: singles and bonded
                       debris, 7.6), fragments, the impact-time candidates of 7.5.1, how it ended, CPU s
  DATA/agglomerate_<protocol>_<d>d<label>.csv       per (Gamma, velocity): mean and standard error over the seeds
  FIGURES/<protocol>_<d>d_vs_velocity.png    the means with error bars (Figs. 7.23, 7.29-7.30, 7.35-7.36),
                       drawn from the second CSV alone (--from-csv redraws it without running anything)
  FIGURES/<protocol>_<d>d_vs_time.png        damage and debris (by size) vs time, first Gamma and seed
  FIGURES/<protocol>_<d>d_gamma.png          the same at the highest velocity for each Gamma (7.22-7.23)
  FIGURES/<protocol>_<d>d_clusters.png       fragments at the end, first Gamma and seed (Figs. 7.14-7.34)
  FIGURES/<protocol>_<d>d_clusters_bonds.png the same for the graph of the surviving initial bonds
and prints the table and the commands it ran.

Impact-time candidates (7.5.1: "15 us at 0.1 m/s ... 2.5 us at 1.0 m/s"), each from the
first contact with the target (the /breakage series, every 100 steps = 28 ns):
  t_first_episode   the first contact episode (force on the target non-zero)
  t_release_to_end  from the start of the test (target `gap` away) to the end of that episode
  t_first_to_last   first to last contact with the target
  t_force_10        time with the target force above 10 % of its peak
  t_compression     until the approach speed of agglomerate and target first reaches zero
  t_rebound         until the approach speed is within 5 % of the initial one of its final value
  t_damage_95       until the damage ratio reaches 95 % of its final value
  t_debris_95       until the debris ratio (by size) reaches 95 % of its final value
"""

import argparse
import csv
import math
import os
import shlex
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

TOOLS = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(TOOLS)
sys.path.insert(0, TOOLS)
import granule_h5 as g  # noqa: E402
import plot_agglomerate  # noqa: E402
import plot_breakage  # noqa: E402

SCENES = {
    "host": "scenarios/agglomerate_host_impact.lua",
    "wall": "scenarios/agglomerate_wall_impact.lua",
    "compression": "scenarios/agglomerate_compression.lua",
}
# Per-run columns from /results.
RESULTS = ["damage_ratio", "debris_ratio", "debris_ratio_bonds", "debris_ratio_by_size", "singles_ratio",
           "bonded_debris_ratio", "debris_ratio_by_size_bonds", "singles_ratio_bonds", "bonded_debris_ratio_bonds",
           "largest_fraction", "largest_fraction_bonds", "fragments", "fragments_bonds", "large", "medium", "small",
           "singles", "bonded_debris", "initial_bonds", "contact_episodes", "peak_force", "test_duration",
           "ended_by_criterion", "settle_duration", "histories_restored", "cpu_time"]
TIMES = ["t_first_episode", "t_release_to_end", "t_first_to_last", "t_force_10", "t_compression", "t_rebound", "t_damage_95",
         "t_debris_95"]
RUN_COLUMNS = ["gamma", "seed", "velocity"] + RESULTS + TIMES
# Averaged over the seeds (mean and standard error).
SUMMARY = ["damage_ratio", "debris_ratio", "debris_ratio_bonds", "debris_ratio_by_size", "singles_ratio",
           "bonded_debris_ratio", "debris_ratio_by_size_bonds", "bonded_debris_ratio_bonds", "largest_fraction",
           "largest_fraction_bonds", "fragments", "fragments_bonds", "large", "medium"] + TIMES
SUMMARY_COLUMNS = ["gamma", "velocity", "n"] + [f"{c}_{s}" for c in SUMMARY for s in ("mean", "se")] + \
    ["ended_by_criterion_all", "cpu_time_total"]


def number_list(text):
    try:
        return [float(x) for x in text.split(",") if x.strip()]
    except ValueError:
        raise SystemExit(f"error: not a comma-separated list of numbers: {text!r}")


def seed_list(text):
    """'1-5' or '1,2,7' -> [1, 2, ...]."""
    out = []
    try:
        for part in text.split(","):
            if "-" in part:
                a, b = part.split("-")
                out += list(range(int(a), int(b) + 1))
            elif part.strip():
                out.append(int(part))
    except ValueError:
        raise SystemExit(f"error: --seeds wants whole numbers such as 1-5 or 1,3,4, got {text!r}")
    if not out or min(out) < 0:
        raise SystemExit(f"error: --seeds wants whole numbers >= 0, got {text!r}")
    return out


def tag(x):
    return f"{x:g}"


def run(command, log):
    """Runs one granule command; returns its wall time. Raises on failure, showing the output."""
    start = time.time()
    done = subprocess.run(command, cwd=ROOT, capture_output=True, text=True)
    seconds = time.time() - start
    log.append((" ".join(shlex.quote(c) for c in command), seconds))
    if done.returncode != 0:
        raise SystemExit(f"error: {' '.join(command)} failed:\n{done.stdout}{done.stderr}")
    sys.stdout.write(done.stdout)
    sys.stdout.flush()
    return seconds


def save_small(fig, path, dpi):
    """Saves a PNG with an adaptive palette where Pillow is available: these
    figures have few colours, and docs/figures keeps each under ~200 KB."""
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    try:
        from PIL import Image
    except ImportError:
        return
    with Image.open(path) as image:
        small = image.convert("RGB").quantize(colors=64)
    small.save(path, optimize=True)


def complete(path):
    """An output to reuse: it exists and its run got to writing /results (an interrupted one did not)."""
    if not os.path.exists(path):
        return False
    try:
        with g.open_run(path) as f:
            return "results" in f and len(f["results"].attrs) > 0
    except Exception:  # a file cut short is not HDF5 at all
        return False


def impact_times(data, results):
    """The impact-time candidates [s] of one run from its /breakage series (NaN where undefined)."""
    t = data["time"]
    nan = float("nan")
    out = {k: nan for k in TIMES}
    start = results.get("contact_start", -1)
    if start < 0:
        return out
    out["t_first_episode"] = results.get("impact_duration", nan)
    out["t_release_to_end"] = start + out["t_first_episode"]
    last = results.get("last_contact", -1)
    out["t_first_to_last"] = last - start if last >= start else nan
    force = data["target_force"]
    if force.max() > 0:
        dt = np.median(np.diff(t)) if len(t) > 1 else 0.0
        out["t_force_10"] = float(np.count_nonzero(force > 0.1 * force.max()) * dt)
    after = t >= start
    if "approach_speed" in data:
        u = data["approach_speed"]
        u0 = u[0]
        closing = np.nonzero(after & (u <= 0))[0]
        if len(closing):
            out["t_compression"] = float(t[closing[0]] - start)
        final = u[-1]
        near = np.abs(u - final) <= 0.05 * abs(u0)
        # The first time from which the approach speed stays within 5 % of its final value.
        away = np.nonzero(~near)[0]
        k = away[-1] + 1 if len(away) else 0
        if k < len(t):
            out["t_rebound"] = float(max(t[k] - start, 0.0))
    for key, column in (("t_damage_95", "damage_ratio"), ("t_debris_95", "debris_ratio_by_size")):
        if column not in data:
            continue
        y = data[column]
        if y[-1] > 0:
            reached = np.nonzero(y >= 0.95 * y[-1])[0]
            out[key] = float(max(t[reached[0]] - start, 0.0))
    return out


def run_row(path, gamma, seed, v):
    with g.open_run(path) as f:
        results = {k: float(v) for k, v in f["results"].attrs.items()} if "results" in f else {}
        data = g.series(f, "/breakage")
    row = {"gamma": gamma, "seed": seed, "velocity": v}
    for c in RESULTS:
        row[c] = results.get(c, float("nan"))
    row.update(impact_times(data, results))
    return row


def summarize(rows, gammas, velocities):
    out = []
    for gamma in gammas:
        for v in velocities:
            mine = [r for r in rows if r["gamma"] == gamma and r["velocity"] == v]
            if not mine:
                continue
            s = {"gamma": gamma, "velocity": v, "n": len(mine)}
            for c in SUMMARY:
                x = np.array([r[c] for r in mine], dtype=float)
                x = x[np.isfinite(x)]
                s[f"{c}_mean"] = float(x.mean()) if len(x) else float("nan")
                s[f"{c}_se"] = float(x.std(ddof=1) / math.sqrt(len(x))) if len(x) > 1 else float("nan")
            s["ended_by_criterion_all"] = int(all(r["ended_by_criterion"] == 1 for r in mine))
            s["cpu_time_total"] = float(sum(r["cpu_time"] for r in mine))
            out.append(s)
    return out


def write_csv(path, columns, rows):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=columns)
        w.writeheader()
        for row in rows:
            w.writerow({k: (f"{row[k]:.6g}" if isinstance(row[k], float) else row[k]) for k in columns})


def read_summary(path):
    with open(path) as f:
        return [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]


def velocity_figure(summary, protocol, d, out):
    """Means +- standard errors against velocity, from the summary CSV's rows."""
    impacts = protocol != "compression"
    fig, axes = plt.subplots(1, 3 if impacts else 2, figsize=(12.5 if impacts else 8.5, 3.8))
    for gamma in sorted({r["gamma"] for r in summary}):
        mine = sorted((r for r in summary if r["gamma"] == gamma), key=lambda r: r["velocity"])
        vs = [r["velocity"] for r in mine]
        n = int(min(r["n"] for r in mine))

        def bars(ax, key, style, label=None, color=None, alpha=1.0):
            # No bars where no standard error is finite (one seed: n < 2, or a
            # quantity no run measured): matplotlib's errorbar fails on all-nan yerr.
            errors = [r[f"{key}_se"] for r in mine]
            if not any(math.isfinite(e) for e in errors):
                errors = None
            return ax.errorbar(vs, [r[f"{key}_mean"] for r in mine], yerr=errors,
                               fmt=style, capsize=2, label=label, color=color, alpha=alpha)
        line = bars(axes[0], "damage_ratio", "o-", f"$\\Gamma$ = {gamma:g} J/m$^2$ ({n} seeds)")
        color = line[0].get_color()
        bars(axes[1], "debris_ratio_by_size", "o-", f"$\\Gamma$ = {gamma:g}: debris, contact graph", color)
        bars(axes[1], "bonded_debris_ratio", "^:", f"$\\Gamma$ = {gamma:g}: bonded debris (7.6)", color, 0.7)
        bars(axes[1], "debris_ratio_by_size_bonds", "s--", f"$\\Gamma$ = {gamma:g}: debris, surviving bonds",
             color, 0.6)
        if impacts:
            for key, style in (("t_first_episode", "o-"), ("t_damage_95", "s--")):
                bars(axes[2], key, style, f"$\\Gamma$ = {gamma:g}: {key[2:].replace('_', ' ')}", color)
    if protocol == "wall":  # 7.6 at 1.0 m/s: damage 40 %, debris 60 %
        axes[0].plot([1.0], [0.40], "k*", markersize=10, label="dissertation 7.6")
        axes[1].plot([1.0], [0.60], "k*", markersize=10, label="dissertation 7.6")
    axes[0].set_ylabel("damage ratio at the end")
    axes[1].set_ylabel("debris ratio at the end (by size)")
    if impacts:
        axes[2].set_ylabel("impact time [s]")
        axes[2].set_xscale("log")
        axes[2].set_yscale("log")
        if protocol == "host":
            axes[2].plot([0.1, 1.0], [15e-6, 2.5e-6], "k*", markersize=10, label="dissertation 7.5.1")
        axes[2].legend(fontsize=6)
    for ax in axes:
        ax.set_xlabel("velocity [m/s]")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7)
    axes[1].legend(fontsize=6)
    fig.suptitle(f"{protocol} test, {d}D: mean $\\pm$ standard error over the agglomerates (seeds)", fontsize=10)
    fig.tight_layout()
    save_small(fig, out, 100)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("protocol", choices=sorted(SCENES))
    parser.add_argument("--dimension", type=int, default=2, choices=(2, 3))
    parser.add_argument("--velocities", default="0.05,0.1,0.2,0.4,0.6,1.0")
    parser.add_argument("--gammas", default="1,2", help="surface energies [J/m^2]")
    parser.add_argument("--seeds", default="1", help="agglomerates: seeds of the random start, e.g. 1-5")
    parser.add_argument("--work", default="study", help="folder for the HDF5 outputs")
    parser.add_argument("--data", help="folder for the CSVs (default: WORK)")
    parser.add_argument("--figures", help="folder for the figures (default: WORK)")
    parser.add_argument("--from-csv", help="draw the velocity figure from this summary CSV; run nothing")
    parser.add_argument("--label", default="", help="appended to the CSV and figure names, e.g. _g2")
    parser.add_argument("--prepare", action="append", default=[], metavar="NAME=VALUE",
                        help="a parameter of agglomerate_prepare.lua, e.g. count=60 (repeatable)")
    parser.add_argument("--test", action="append", default=[], metavar="NAME=VALUE",
                        help="a parameter of the test scene, e.g. steady_time=1e-5 (repeatable)")
    parser.add_argument("--jobs", type=int, default=1, help="runs at once (default 1)")
    parser.add_argument("--granule", default=os.path.join(ROOT, "build", "granule"))
    args = parser.parse_args(argv)
    d = args.dimension
    work = os.path.abspath(args.work)
    figures = os.path.abspath(args.figures or work)
    os.makedirs(figures, exist_ok=True)
    name = f"{args.protocol}_{d}d{args.label}"
    out_velocity = os.path.join(figures, f"{name}_vs_velocity.png")
    if args.from_csv:
        velocity_figure(read_summary(args.from_csv), args.protocol, d, out_velocity)
        print(out_velocity)
        return 0
    velocities, gammas, seeds = number_list(args.velocities), number_list(args.gammas), seed_list(args.seeds)
    data_dir = os.path.abspath(args.data or work)
    os.makedirs(work, exist_ok=True)
    log = []

    # 7.3: one agglomerate per surface energy and seed, reused by every velocity.
    agglomerates = {}
    for gamma in gammas:
        for seed in seeds:
            path = os.path.join(work, f"agglomerate_{d}d_g{tag(gamma)}_s{seed}.h5")
            agglomerates[(gamma, seed)] = path
            if not complete(path):
                command = [args.granule, "run", "scenarios/agglomerate_prepare.lua", "-D", f"dimension={d}",
                           "-D", f"surface_energy={gamma:g}", "-D", f"seed={seed}"]
                for setting in args.prepare:
                    command += ["-D", setting]
                run(command + ["-o", path, "--quiet"], log)

    cases = [(gamma, seed, v) for gamma in gammas for seed in seeds for v in velocities]

    def one(case):
        gamma, seed, v = case
        path = os.path.join(work, f"{args.protocol}_{d}d_g{tag(gamma)}_s{seed}_v{tag(v)}.h5")
        if not complete(path):
            command = [args.granule, "run", SCENES[args.protocol], "-D", f"dimension={d}",
                       "-D", f"file={agglomerates[(gamma, seed)]}", "-D", f"velocity={v:g}",
                       "-D", f"surface_energy={gamma:g}"]
            for setting in args.test:
                command += ["-D", setting]
            run(command + ["-o", path, "--quiet"], log)
        return path

    with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        paths = dict(zip(cases, pool.map(one, cases)))

    rows = [run_row(path, gamma, seed, v) for (gamma, seed, v), path in paths.items()]
    runs_csv = os.path.join(data_dir, f"agglomerate_{name}_runs.csv")
    write_csv(runs_csv, RUN_COLUMNS, rows)
    summary = summarize(rows, gammas, velocities)
    summary_csv = os.path.join(data_dir, f"agglomerate_{name}.csv")
    write_csv(summary_csv, SUMMARY_COLUMNS, summary)
    velocity_figure(read_summary(summary_csv), args.protocol, d, out_velocity)

    # Evolution in time, first Gamma and seed (debris by size, 7.4 read with 7.6).
    first = [paths[(gammas[0], seeds[0], v)] for v in velocities]
    fig, axes = plt.subplots(2, 1, sharex=True, figsize=(6.5, 5.5))
    plot_breakage.plot(axes, first, "time", "contacts", shade=False, measure="debris_ratio_by_size")
    axes[1].set_xscale("symlog", linthresh=1.0)
    axes[1].set_xlim(left=0)
    fig.tight_layout()
    out_time = os.path.join(figures, f"{name}_vs_time.png")
    save_small(fig, out_time, 100)

    # Surface energy at the highest velocity (Figs. 7.22-7.23).
    out_gamma = None
    if len(gammas) > 1:
        fig, axes = plt.subplots(2, 1, sharex=True, figsize=(6.5, 5.5))
        plot_breakage.plot(axes, [paths[(gamma, seeds[0], max(velocities))] for gamma in gammas], "time",
                           "contacts", shade=False, measure="debris_ratio_by_size")
        axes[1].set_xscale("symlog", linthresh=1.0)
        axes[1].set_xlim(left=0)
        fig.tight_layout()
        out_gamma = os.path.join(figures, f"{name}_gamma.png")
        save_small(fig, out_gamma, 100)

    # Fragments at the end, first Gamma and seed: of the contact graph (7.4) and
    # of the surviving initial bonds.
    out_clusters = []
    for graph, suffix in (("contacts", ""), ("bonds", "_bonds")):
        columns = min(3, len(first))
        lines = (len(first) + columns - 1) // columns
        fig, axes = plt.subplots(lines, columns, figsize=(3.3 * columns, 3.1 * lines), squeeze=False)
        for ax, path in zip(axes.flat, first):
            plot_agglomerate.draw(ax, path, graph=graph)
        for ax in list(axes.flat)[len(first):]:
            ax.axis("off")
        fig.tight_layout()
        out_clusters.append(os.path.join(figures, f"{name}_clusters{suffix}.png"))
        save_small(fig, out_clusters[-1], 90)

    def cell(r, key, scale=1.0):
        return f"{r[key + '_mean'] * scale:.3g}+-{r[key + '_se'] * scale:.2g}"
    print(f"{'gamma':>5} {'v':>5} {'n':>2} {'damage':>13} {'debris(size)':>13} {'bonded':>13} "
          f"{'debris(bonds)':>13} {'largest':>13} {'t_first_us':>13} {'t_dmg95_us':>13} {'ended':>5}")
    for r in summary:
        print(f"{r['gamma']:5g} {r['velocity']:5g} {r['n']:2d} {cell(r, 'damage_ratio'):>13} "
              f"{cell(r, 'debris_ratio_by_size'):>13} {cell(r, 'bonded_debris_ratio'):>13} "
              f"{cell(r, 'debris_ratio_by_size_bonds'):>13} {cell(r, 'largest_fraction'):>13} "
              f"{cell(r, 't_first_episode', 1e6):>13} {cell(r, 't_damage_95', 1e6):>13} "
              f"{'all' if r['ended_by_criterion_all'] else 'cap':>5}")
    for command, seconds in log:
        print(f"ran ({seconds:.1f} s): {command}")
    for path in [runs_csv, summary_csv, out_velocity, out_time, out_gamma] + out_clusters:
        if path:
            print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
