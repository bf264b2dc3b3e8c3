#!/usr/bin/python3
"""Twisting resistance in a poured bed: scenarios/packing_3d.lua over
twisting_friction and fill seeds, summarised per coefficient (mean and
standard error over the seeds) as a table and a figure.

    mpirun --allow-run-as-root --oversubscribe -np 2 build/granule sweep \\
        scenarios/packing_3d.lua -D twisting_friction=0,0.05,0.2 -D seed=1,2,3,4 -o twsweep -q
    /usr/bin/python3 tools/twisting_packing_study.py twsweep/packing_3d.sweep.csv \\
        docs/data/twisting_packing.csv docs/figures/twisting_packing.png

Writes the summary table (CSV), the cases beside it (<table>_cases.csv) and
the figure; prints the Markdown table of docs/contact_models.md ("Study:
twisting in a poured bed").
"""
import csv
import math
import sys


def mean_se(values):
    n = len(values)
    mean = sum(values) / n
    if n < 2:
        return mean, float("nan")
    var = sum((v - mean) ** 2 for v in values) / (n - 1)
    return mean, math.sqrt(var / n)


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    sweep_csv, table_csv, figure = sys.argv[1:]
    with open(sweep_csv, newline="") as f:
        rows = [r for r in csv.DictReader(f)]
    bad = [r for r in rows if r["status"] != "ok" or r["settled"] not in ("1", "1.0")]
    if bad:
        sys.exit(f"{sweep_csv}: {len(bad)} case(s) not finished and settled: "
                 + ", ".join(r["case"] for r in bad))
    by_mu = {}
    for r in rows:
        by_mu.setdefault(float(r["twisting_friction"]), []).append(r)
    quantities = [("settle_time", "settle time (s)"), ("solid_fraction", "solid fraction"),
                  ("rotational_share", "rotational share of KE left"),
                  ("wall_s", "wall time (s)")]
    summary = []
    for mu in sorted(by_mu):
        group = by_mu[mu]
        line = {"twisting_friction": mu, "seeds": len(group)}
        for key, _ in quantities:
            m, se = mean_se([float(r[key]) for r in group])
            line[key] = m
            line[key + "_se"] = se
        summary.append(line)
    case_fields = ["twisting_friction", "seed", "status", "settled", "settle_time",
                   "solid_fraction", "rotational_share", "kinetic_energy", "bed_height",
                   "floor_share", "wall_share", "wall_s"]
    cases_csv = table_csv[:-4] + "_cases.csv" if table_csv.endswith(".csv") else table_csv + "_cases"
    with open(cases_csv, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=case_fields)
        w.writeheader()
        for r in rows:
            w.writerow({k: r[k] for k in case_fields})
    with open(table_csv, "w", newline="") as f:
        fields = ["twisting_friction", "seeds"] + [k for q, _ in quantities for k in (q, q + "_se")]
        w = csv.DictWriter(f, fieldnames=fields)
        w.writeheader()
        for line in summary:
            w.writerow({k: (f"{line[k]:.6g}" if isinstance(line[k], float) else line[k])
                        for k in fields})
    print("| mu_t | seeds | settle time (s) | solid fraction | rotational share of KE left | "
          "wall time (s) |")
    print("|---|---|---|---|---|---|")
    for line in summary:
        cells = [f"{line[k]:.4g} +- {line[k + '_se']:.2g}" for k, _ in quantities]
        print(f"| {line['twisting_friction']:g} | {line['seeds']} | " + " | ".join(cells) + " |")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 3, figsize=(11, 3.4))
    mus = [line["twisting_friction"] for line in summary]
    for ax, (key, label) in zip(axes, quantities[:3]):
        for r in rows:
            ax.plot(float(r["twisting_friction"]), float(r[key]), "o", color="0.7", ms=4)
        ax.errorbar(mus, [line[key] for line in summary],
                    yerr=[line[key + "_se"] for line in summary], fmt="s-", color="C0",
                    capsize=4, label="mean +- standard error")
        ax.set_xlabel("twisting friction mu_t")
        ax.set_ylabel(label)
    axes[0].legend(fontsize=8)
    fig.suptitle("packing_3d.lua, 800 beads, Hertz-Mindlin, epsd twisting (eta_r = 0.3); "
                 "grey: single seeds", fontsize=9)
    fig.tight_layout()
    fig.savefig(figure, dpi=120)


if __name__ == "__main__":
    main()
