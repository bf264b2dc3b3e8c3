#!/usr/bin/python3
"""Run a chapter 7 study: one agglomerate test over impact velocities and surface energies.

usage: /usr/bin/python3 tools/agglomerate_study.py host|wall|compression
           [--dimension 2] [--velocities 0.05,0.1,0.2,0.4,0.6,1.0] [--gammas 1,2]
           [--work study] [--figures DIR] [--prepare count=217 ...] [--test name=value ...]
           [--jobs 1] [--granule build/granule]

For every surface energy Gamma it prepares an agglomerate once
(scenarios/agglomerate_prepare.lua -> WORK/agglomerate_<d>d_g<Gamma>.h5, 7.3), then
runs the test scene (scenarios/agglomerate_<protocol>.lua) at every velocity
(-> WORK/<protocol>_<d>d_g<Gamma>_v<v>.h5). Outputs that exist are reused; delete
them to run again. It then writes
  WORK/<protocol>_<d>d.csv             final ratios, fragment counts, impact duration,
                                       how each run ended, CPU seconds per test (from /results)
  FIGURES/<protocol>_<d>d_vs_velocity.png  damage and debris at the end vs velocity
                                       (Figs. 7.23, 7.29-7.30, 7.35-7.36), impact duration
  FIGURES/<protocol>_<d>d_vs_time.png  damage and debris vs time, first Gamma (Figs. 7.15-7.21)
  FIGURES/<protocol>_<d>d_gamma.png    the same at the highest velocity for each Gamma (7.22-7.23)
  FIGURES/<protocol>_<d>d_clusters.png fragments at the end, first Gamma (Figs. 7.14-7.34)
  FIGURES/<protocol>_<d>d_clusters_bonds.png  the same for the graph of the surviving initial bonds
and prints the table and the commands it ran.
"""

import argparse
import csv
import os
import shlex
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

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
COLUMNS = ["gamma", "velocity", "damage_ratio", "debris_ratio", "debris_ratio_bonds", "largest_fraction",
           "largest_fraction_bonds", "fragments", "large", "medium", "small", "fines", "singles", "initial_bonds",
           "impact_duration", "contact_episodes", "peak_force", "test_duration", "ended_by_criterion",
           "settled_by_criterion", "cpu_time"]


def number_list(text):
    try:
        return [float(x) for x in text.split(",") if x.strip()]
    except ValueError:
        raise SystemExit(f"error: not a comma-separated list of numbers: {text!r}")


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


def results_of(path):
    with g.open_run(path) as f:
        return {k: float(v) for k, v in f["results"].attrs.items()} if "results" in f else {}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("protocol", choices=sorted(SCENES))
    parser.add_argument("--dimension", type=int, default=2, choices=(2, 3))
    parser.add_argument("--velocities", default="0.05,0.1,0.2,0.4,0.6,1.0")
    parser.add_argument("--gammas", default="1,2", help="surface energies [J/m^2]")
    parser.add_argument("--work", default="study", help="folder for the HDF5 outputs and the CSV")
    parser.add_argument("--figures", help="folder for the figures (default: WORK)")
    parser.add_argument("--prepare", action="append", default=[], metavar="NAME=VALUE",
                        help="a parameter of agglomerate_prepare.lua, e.g. count=60 (repeatable)")
    parser.add_argument("--test", action="append", default=[], metavar="NAME=VALUE",
                        help="a parameter of the test scene, e.g. steady_time=1e-5 (repeatable)")
    parser.add_argument("--jobs", type=int, default=1, help="runs at once (default 1)")
    parser.add_argument("--granule", default=os.path.join(ROOT, "build", "granule"))
    args = parser.parse_args(argv)
    velocities, gammas = number_list(args.velocities), number_list(args.gammas)
    work = os.path.abspath(args.work)
    figures = os.path.abspath(args.figures or work)
    os.makedirs(work, exist_ok=True)
    os.makedirs(figures, exist_ok=True)
    d = args.dimension
    log = []

    # 7.3: one agglomerate per surface energy, reused by every velocity.
    agglomerates = {}
    for gamma in gammas:
        path = os.path.join(work, f"agglomerate_{d}d_g{tag(gamma)}.h5")
        agglomerates[gamma] = path
        if not os.path.exists(path):
            command = [args.granule, "run", "scenarios/agglomerate_prepare.lua", "-D", f"dimension={d}",
                       "-D", f"surface_energy={gamma:g}"]
            for setting in args.prepare:
                command += ["-D", setting]
            run(command + ["-o", path, "--quiet"], log)

    cases = [(gamma, v) for gamma in gammas for v in velocities]

    def one(case):
        gamma, v = case
        path = os.path.join(work, f"{args.protocol}_{d}d_g{tag(gamma)}_v{tag(v)}.h5")
        if not os.path.exists(path):
            command = [args.granule, "run", SCENES[args.protocol], "-D", f"dimension={d}",
                       "-D", f"file={agglomerates[gamma]}", "-D", f"velocity={v:g}",
                       "-D", f"surface_energy={gamma:g}"]
            for setting in args.test:
                command += ["-D", setting]
            run(command + ["-o", path, "--quiet"], log)
        return path

    with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        paths = dict(zip(cases, pool.map(one, cases)))

    rows = []
    for (gamma, v), path in paths.items():
        r = results_of(path)
        row = {"gamma": gamma, "velocity": v}
        for c in COLUMNS:
            if c not in row:
                row[c] = r.get(c, float("nan"))
        rows.append(row)
    table = os.path.join(work, f"{args.protocol}_{d}d.csv")
    with open(table, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS)
        w.writeheader()
        for row in rows:
            w.writerow({k: (f"{row[k]:.6g}" if isinstance(row[k], float) else row[k]) for k in COLUMNS})

    # Final ratios (and impact duration) against velocity.
    impacts = args.protocol != "compression"
    fig, axes = plt.subplots(1, 3 if impacts else 2, figsize=(12 if impacts else 8.5, 3.6))
    for gamma in gammas:
        mine = sorted((r for r in rows if r["gamma"] == gamma), key=lambda r: r["velocity"])
        vs = [r["velocity"] for r in mine]
        line, = axes[0].plot(vs, [r["damage_ratio"] for r in mine], "o-", label=f"$\\Gamma$ = {gamma:g} J/m$^2$")
        axes[1].plot(vs, [r["debris_ratio"] for r in mine], "o-", color=line.get_color(),
                     label=f"$\\Gamma$ = {gamma:g}, contact graph")
        axes[1].plot(vs, [r["debris_ratio_bonds"] for r in mine], "s--", color=line.get_color(), alpha=0.6,
                     label=f"$\\Gamma$ = {gamma:g}, surviving bonds")
        if impacts:
            axes[2].plot(vs, [r["impact_duration"] * 1e6 for r in mine], "o-", color=line.get_color())
    axes[0].set_ylabel("damage ratio at the end")
    axes[1].set_ylabel("debris ratio at the end")
    if impacts:
        axes[2].set_ylabel("first contact duration [$\\mu$s]")
        axes[2].set_xscale("log")
        axes[2].set_yscale("log")
    for ax in axes:
        ax.set_xlabel("velocity [m/s]")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7)
    axes[1].legend(fontsize=6)
    fig.suptitle(f"{args.protocol} test, {d}D", fontsize=10)
    fig.tight_layout()
    out_velocity = os.path.join(figures, f"{args.protocol}_{d}d_vs_velocity.png")
    save_small(fig, out_velocity, 100)

    # Evolution in time, first Gamma.
    first = [paths[(gammas[0], v)] for v in velocities]
    fig, axes = plt.subplots(2, 1, sharex=True, figsize=(6.5, 5.5))
    plot_breakage.plot(axes, first, "time", "contacts", shade=False)
    axes[1].set_xscale("symlog", linthresh=1.0)
    axes[1].set_xlim(left=0)
    fig.tight_layout()
    out_time = os.path.join(figures, f"{args.protocol}_{d}d_vs_time.png")
    save_small(fig, out_time, 100)

    # Surface energy at the highest velocity (Figs. 7.22-7.23).
    out_gamma = None
    if len(gammas) > 1:
        fig, axes = plt.subplots(2, 1, sharex=True, figsize=(6.5, 5.5))
        plot_breakage.plot(axes, [paths[(gamma, max(velocities))] for gamma in gammas], "time", "contacts",
                           shade=False)
        axes[1].set_xscale("symlog", linthresh=1.0)
        axes[1].set_xlim(left=0)
        fig.tight_layout()
        out_gamma = os.path.join(figures, f"{args.protocol}_{d}d_gamma.png")
        save_small(fig, out_gamma, 100)

    # Fragments at the end, first Gamma: of the contact graph (7.4) and of the
    # surviving initial bonds.
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
        out_clusters.append(os.path.join(figures, f"{args.protocol}_{d}d_clusters{suffix}.png"))
        save_small(fig, out_clusters[-1], 90)

    print(f"{'gamma':>6} {'v':>6} {'damage':>7} {'debris':>7} {'deb_bd':>7} {'largest':>7} {'frags':>5} "
          f"{'contact_us':>10} {'ended':>9} {'cpu_s':>7}")
    for r in sorted(rows, key=lambda r: (r["gamma"], r["velocity"])):
        print(f"{r['gamma']:6g} {r['velocity']:6g} {r['damage_ratio']:7.3f} {r['debris_ratio']:7.3f} "
              f"{r['debris_ratio_bonds']:7.3f} {r['largest_fraction']:7.3f} {r['fragments']:5.0f} "
              f"{r['impact_duration'] * 1e6:10.3f} {'criterion' if r['ended_by_criterion'] == 1 else 'cap':>9} "
              f"{r['cpu_time']:7.1f}")
    for command, seconds in log:
        print(f"ran ({seconds:.1f} s): {command}")
    for path in [table, out_velocity, out_time, out_gamma] + out_clusters:
        if path:
            print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
