#!/usr/bin/python3
"""The Mechanofusion studies as ensembles (docs/mechanofusion.md, "Full-length
studies"): tables from the sweeps, then figures and fits from the tables.

usage:
  /usr/bin/python3 tools/mechanofusion_ensembles.py tables WORK [--data docs/data]
  /usr/bin/python3 tools/mechanofusion_ensembles.py figures [--data docs/data] [-o docs/figures]
  /usr/bin/python3 tools/mechanofusion_ensembles.py overlaps SWEEP_DIR ... [--data docs/data]

overlaps: the scraper's tilt against the deepest contacts (sweeps of
scenarios/mechanofusion.lua over rpm and scraper_tilt, and over rpm with
scraper=false): per case the largest overlap over the run and the median over
the windows of each window's largest, per contact kind, into
docs/data/mechanofusion_scraper_tilt.csv (`figures` draws it).

tables: reads the finished case files under WORK/<study>/ for every study that
tools/mechanofusion_long.sh ran (a sweep over scenarios/mechanofusion.lua with
seeds; a study still running gives the cases finished so far) and writes
docs/data/mechanofusion_<study>.csv (one row per case: its parameters, its
wall time and every result the scene recorded). Cases already in that table
and not under WORK are kept (a study's seeds may run in different sessions;
--replace drops them); a study that shares cases with another (loading's
1500 particles are the rpm study's) borrows them from its table, marked in
the column borrowed_from.
figures: reads those tables only, so the figures and fits are made again from
what is committed. Per value of a study's parameter: the mean over the seeds
and its standard error (sample standard deviation / sqrt(seeds)); per
quantity the power-law exponent fitted to each seed's cases, reported as the
mean over the seeds +- its standard error (one seed: the fit's own standard
error from the scatter about the line). Writes the figures, and
docs/data/mechanofusion_fits.csv (study, quantity, exponent, standard error,
seeds, claim); prints one line per fit and per mean.
"""

import argparse
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from plot_mechanofusion import AREAS, AREA_LABEL, power_fit  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# Each study: the parameter it varies, the others that split it into series,
# and the claims its fits are set against (quantity, claimed exponent, where).
STUDIES = {
    "rpm": {"x": "rpm", "versus": [("gap_mean_granular_temperature", "gap_shear_rate", 2, "Eq. 5.4")],
            "claims": [("inner_normal_force", 2, "Fig. 5.3"),
                                   ("inner_tangential_force", 2, "Fig. 5.3")]
            + [(f"normal_force_per_contact_{a}", 1, "Figs. 5.11-5.12") for a in AREAS]
            + [("gap_shear_rate", 1, "Eq. 5.6"), ("gap_normal_force_per_contact", 1, "Eq. 5.10"),
               ("coating_time_estimate_one_patch_rstar", -1, "Fig. 4.33")]},
    "gap": {"x": "gap", "claims": [("normal_force_per_contact_inner_piece", -1, "Eq. 5.11, Fig. 5.13"),
                                   ("gap_normal_force_per_contact", -1, "Eq. 5.11"),
                                   ("gap_shear_rate", -1, "Eq. 5.6"),
                                   ("gap_mean_granular_temperature", -2, "Eqs. 5.4, 5.6")],
            "versus": [("gap_normal_force_per_contact", "gap_shear_rate", 1, "Eq. 5.10"),
                       ("normal_force_per_contact_inner_piece", "gap_shear_rate", 1, "Eq. 5.10"),
                       ("gap_mean_granular_temperature", "gap_shear_rate", 2, "Eq. 5.4")]},
    "stiffness": {"x": "k_load", "claims": [(f"normal_force_per_contact_{a}", 0.5, "Figs. 5.9-5.10")
                                            for a in AREAS]},
    "loading": {"x": "particles", "by": "rpm", "claims": [("inner_normal_force", None, "Fig. 4.17"),
                                                          ("inner_tangential_force", None, "Fig. 4.18")],
                # The base loading (1500 particles) at 1000, 2000 and 4000 rpm is the rpm
                # study's own cases (the same scene, seeds, settling and length): taken
                # from its table rather than run twice.
                "borrow": ("rpm", "rpm", ("1000", "2000", "4000"))},
    "coating": {"x": "rpm", "claims": []},
    "scraper": {"x": "scraper", "claims": []},
    "double": {"x": "size_scale", "claims": []},
    # The 2D section at the base speed is the rpm study's 2000 rpm case (dimension
    # 2 is the scene's default): borrowed, marked dimension = 2, not run twice.
    "slab": {"x": "dimension", "claims": [], "borrow": ("rpm", "rpm", ("2000",), {"dimension": "2"})},
}
NOT_RESULTS = {"case", "status", "rank", "wall_s", "file", "error", "borrowed_from"}


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return {"true": 1.0, "false": 0.0}.get(str(text).strip().lower(), float("nan"))


def derive(row):
    """The "two times" of 4.4.2 (chapter 4's summary: the force on a particle in the
    inner-piece and scraper areas is twice that in the others), per particle and per
    contact, and the share of impacts below 0.1 m/s (4.6), added to a case's row."""
    for kind in ("per_particle", "per_contact"):
        f = {a: number(row.get(f"normal_force_{kind}_{a}")) for a in AREAS}
        low = f["input"] + f["free_diffusion"]
        row[f"two_times_ratio_{kind}"] = f"{(f['inner_piece'] + f['scraper']) / low:.6g}" if low > 0 else "nan"
    for a in AREAS:
        over = number(row.get(f"fraction_over_100_mm_s_{a}"))
        row[f"fraction_below_100_mm_s_{a}"] = f"{1 - over:.6g}" if math.isfinite(over) else "nan"
    # Eq. 5.4 with the measured shear rate and solid fraction of the gap: the
    # granular temperature a simple shear flow of nearly elastic spheres would
    # have, T^1/2 = sqrt(J / 15 (1 - e)) d du/dy, J = 1 + pi/12 (1 + 5 / 8G)^2,
    # G = nu g0, g0 = (2 - nu) / 2 (1 - nu)^3 (5.1-5.3).
    nu, rate = number(row.get("gap_mean_solid_fraction")), number(row.get("gap_shear_rate"))
    d = 2 * (number(row.get("radius")) if math.isfinite(number(row.get("radius"))) else 0.2e-3)
    e = number(row.get("restitution")) if math.isfinite(number(row.get("restitution"))) else 0.85
    measured = number(row.get("gap_mean_granular_temperature"))
    if 0 < nu < 1 and rate > 0 and e < 1:
        g = nu * (2 - nu) / (2 * (1 - nu) ** 3)
        j = 1 + math.pi / 12 * (1 + 5 / (8 * g)) ** 2
        predicted = j / (15 * (1 - e)) * (d * rate) ** 2
        row["gap_eq_5_4_temperature"] = f"{predicted:.6g}"
        row["gap_temperature_over_eq_5_4"] = f"{measured / predicted:.6g}" if math.isfinite(measured) else "nan"
    shear, nominal = number(row.get("gap_shear_rate")), number(row.get("gap_nominal_shear_rate"))
    if nominal > 0:
        row["gap_shear_rate_over_nominal"] = f"{shear / nominal:.6g}"


def finished_cases(directory):
    """Every case file of a sweep directory that carries the sweep's mark of a
    finished case: its parameters (from the mark) and its /results. Read from
    the files, not the sweep's summary, so a study still running (whose summary
    is written only when its sweep ends) gives the cases finished so far."""
    import glob
    import h5py
    rows = []
    for path in sorted(glob.glob(os.path.join(directory, "*.h5"))):
        if path.endswith((".sweep.h5", ".checkpoint.h5")):
            continue
        try:
            with h5py.File(path, "r") as f:
                mark = f["sweep_case"].attrs if "sweep_case" in f else None
                if mark is None or int(mark.get("complete", 0)) != 1 or "results" not in f:
                    continue
                key = mark["case"].decode() if isinstance(mark["case"], bytes) else str(mark["case"])
                row = dict(item.split("=", 1) for item in key.split(";"))
                row["wall_s"] = f"{float(mark['wall_seconds']):.3f}"
                row["case"] = os.path.basename(path)
                for name, value in f["results"].attrs.items():
                    row[name] = f"{float(np.ravel(value)[0]):.10g}"
        except (OSError, KeyError, ValueError) as e:
            print(f"{path}: skipped ({e})")
            continue
        rows.append(row)
    return rows


def borrowed_rows(data, study, rows):
    """Rows of another study's table that this study shares (STUDIES[study]["borrow"]:
    the other study, the column to match, its values and optionally the columns to
    set on a borrowed row, such as the scene default that the other study did not
    vary), marked `borrowed_from`, unless this study ran the same case itself."""
    source, column, values = STUDIES[study]["borrow"][:3]
    fixed = STUDIES[study]["borrow"][3] if len(STUDIES[study]["borrow"]) > 3 else {}
    path = os.path.join(data, f"mechanofusion_{source}.csv")
    if not os.path.exists(path):
        print(f"{study}: {path} not there; nothing borrowed")
        return []
    spec = STUDIES[study]
    def key(r):
        return tuple(number(r.get(c)) for c in ("seed", spec["x"], spec.get("by") or spec["x"]))
    have = {key(r) for r in rows}
    out = []
    for r in read_csv(path):
        if str(r.get(column)).strip() not in values and f"{number(r.get(column)):g}" not in values:
            continue
        r = dict(r, **fixed)
        if key(r) in have:
            continue
        r["borrowed_from"] = source
        out.append(r)
    print(f"{study}: {len(out)} cases borrowed from {path}")
    return out


def tables(args):
    os.makedirs(args.data, exist_ok=True)
    written = 0
    for study in STUDIES:
        directory = os.path.join(args.work, study)
        if not os.path.isdir(directory):
            continue
        rows = finished_cases(directory)
        if not rows:
            print(f"{study}: no finished case yet in {directory}")
            continue
        for r in rows:
            derive(r)
        out = os.path.join(args.data, f"mechanofusion_{study}.csv")
        if os.path.exists(out) and not args.replace:
            # A table gathers its cases over sessions and machines: the cases in
            # the table that this WORK did not run (or not yet finish) are kept.
            ran = {r["case"] for r in rows}
            kept = [r for r in read_csv(out) if r.get("case") not in ran and not r.get("borrowed_from")]
            if kept:
                print(f"{study}: {len(kept)} cases kept from {out}")
            rows += kept
        if "borrow" in STUDIES[study]:
            rows += borrowed_rows(args.data, study, rows)
        rows.sort(key=lambda r: r["case"])
        columns = sorted({c for r in rows for c in r}, key=lambda c: (c != "case", c))
        with open(out, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(columns)
            for r in rows:
                w.writerow([r.get(c, "") for c in columns])
        print(f"{out}: {len(rows)} finished cases")
        written += 1
    if not written:
        sys.exit(f"no study's sweep summary under {args.work}")


def grouped(rows, x, quantity, by=None):
    """{series value: (xs, means, standard errors, counts, per-seed {seed: (xs, ys)})}"""
    out = {}
    for r in rows:
        key = number(r[by]) if by else None
        xv, yv, seed = number(r[x]), number(r.get(quantity)), number(r.get("seed", 1))
        if not math.isfinite(yv):
            continue
        s = out.setdefault(key, {})
        s.setdefault(xv, []).append((seed, yv))
    result = {}
    for key, points in out.items():
        xs = sorted(points)
        means, errors, counts = [], [], []
        seeds = {}
        for xv in xs:
            ys = np.array([y for _, y in points[xv]])
            means.append(ys.mean())
            errors.append(ys.std(ddof=1) / math.sqrt(len(ys)) if len(ys) > 1 else float("nan"))
            counts.append(len(ys))
            for seed, y in points[xv]:
                seeds.setdefault(seed, ([], []))
                seeds[seed][0].append(xv)
                seeds[seed][1].append(y)
        result[key] = (np.array(xs), np.array(means), np.array(errors), counts, seeds)
    return result


def exponent(xs, means, seeds):
    """Mean +- standard error over the seeds' own fits; one seed: the fit's error.
    Only seeds that have every value of the study are fitted: a seed still running
    (a study gathered over sessions) would fit a narrower range."""
    per_seed = [power_fit(sx, sy)[0] for sx, sy in seeds.values() if len(sx) >= 2 and len(sx) == len(xs)]
    per_seed = [b for b in per_seed if math.isfinite(b)]
    if len(per_seed) >= 2:
        return float(np.mean(per_seed)), float(np.std(per_seed, ddof=1) / math.sqrt(len(per_seed))), len(per_seed)
    b, se, _ = power_fit(xs, means)
    return b, se, len(per_seed)


def fit_figure(study, rows, spec, fits, out_dir):
    claims = spec["claims"]
    if not claims:
        return
    n = len(claims)
    cols = min(3, n)
    fig, axes = plt.subplots((n + cols - 1) // cols, cols, figsize=(4.2 * cols, 3.4 * ((n + cols - 1) // cols)),
                             squeeze=False)
    for ax, (quantity, claim, where) in zip(axes.flat, claims):
        for key, (xs, means, errors, counts, seeds) in sorted(grouped(rows, spec["x"], quantity, spec.get("by")).items(),
                                                             key=lambda kv: (kv[0] is None, kv[0])):
            if len(xs) < 2:
                continue
            b, se, nseeds = exponent(xs, means, seeds)
            label = (f"{spec['by']}={key:g}: " if key is not None else "") + f"x^{b:.2f}+-{se:.2f}"
            ax.errorbar(xs, np.abs(means), yerr=np.nan_to_num(errors), fmt="o", capsize=3, label=label)
            fits.append((study, quantity + (f" ({spec['by']}={key:g})" if key is not None else ""), b, se,
                         max(nseeds, min(counts)), "" if claim is None else f"x^{claim:g} ({where})"))
            print(f"fit study={study} quantity={fits[-1][1]} exponent={b:.3f} +- {se:.3f} seeds={fits[-1][4]} "
                  f"claim={fits[-1][5]}")
            if claim is not None:
                xm = math.exp(np.mean(np.log(xs)))
                ym = math.exp(np.mean(np.log(np.abs(means))))
                xx = np.geomspace(xs.min(), xs.max(), 20)
                ax.plot(xx, ym * (xx / xm) ** claim, "k--", lw=0.8)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(spec["x"])
        ax.set_title(quantity.replace("_", " "), fontsize=8)
        ax.legend(fontsize=6)
        ax.grid(True, which="both", alpha=0.3)
    for ax in list(axes.flat)[n:]:
        ax.axis("off")
    fig.suptitle(f"{study} study: mean over seeds +- standard error; dashed: the claimed law", fontsize=9)
    save(fig, os.path.join(out_dir, f"mechanofusion_{study}_ensemble.png"))


def versus_figure(study, rows, spec, fits, out_dir):
    """A quantity against another measured one (the force per contact against the
    measured shear rate, Eq. 5.10), every case a point, fitted over all of them."""
    pairs = spec.get("versus", [])
    if not pairs:
        return
    fig, axes = plt.subplots(1, len(pairs), figsize=(4.2 * len(pairs), 3.4), squeeze=False)
    for ax, (yq, xq, claim, where) in zip(axes.flat, pairs):
        x = np.array([number(r.get(xq)) for r in rows])
        y = np.array([number(r.get(yq)) for r in rows])
        ok = np.isfinite(x) & np.isfinite(y) & (x > 0) & (y > 0)
        if ok.sum() < 2:
            continue
        b, se, a = power_fit(x[ok], y[ok])
        fits.append((study, f"{yq} against {xq}", b, se, int(ok.sum()), f"x^{claim:g} ({where}), every case a point"))
        print(f"fit study={study} quantity={yq} against={xq} exponent={b:.3f} +- {se:.3f} points={ok.sum()}")
        values = np.array([number(r.get(spec["x"])) for r in rows])
        for v in sorted(set(values[ok])):
            sel = ok & (values == v)
            ax.loglog(x[sel], y[sel], "o", label=f"{spec['x']}={v:g}")
        xx = np.geomspace(x[ok].min(), x[ok].max(), 20)
        ax.loglog(xx, a * xx ** b, "-", lw=0.8, color="k", label=f"fit x^{b:.2f}+-{se:.2f}")
        ax.set_xlabel(xq.replace("_", " "))
        ax.set_ylabel(yq.replace("_", " "), fontsize=7)
        ax.set_title(f"claim x^{claim:g} ({where})", fontsize=8)
        ax.legend(fontsize=6)
        ax.grid(True, which="both", alpha=0.3)
    save(fig, os.path.join(out_dir, f"mechanofusion_{study}_versus.png"))


def profile_figure(study, rows, spec, out_dir, prefix, quantities, title):
    fig, axes = plt.subplots(1, len(quantities), figsize=(3.6 * len(quantities), 3.2), squeeze=False)
    for ax, q in zip(axes.flat, quantities):
        zones = sorted({int(c[len(prefix):].split("_")[0]) for c in rows[0] if c.startswith(prefix)
                        and c.endswith("_" + q) and c[len(prefix):].split("_")[0].isdigit()})
        for value in sorted({number(r[spec["x"]]) for r in rows}):
            subset = [r for r in rows if number(r[spec["x"]]) == value]
            data = np.array([[number(r.get(f"{prefix}{z}_{q}")) for z in zones] for r in subset])
            # A bin nobody visited has no velocity or temperature, not a zero one.
            counts = np.array([[number(r.get(f"{prefix}{z}_count")) for z in zones] for r in subset])
            data[~(counts > 0)] = np.nan
            with np.errstate(all="ignore"):
                mean = np.nanmean(data, axis=0)
                se = np.nanstd(data, axis=0, ddof=1) / math.sqrt(len(subset)) if len(subset) > 1 else 0 * mean
            where = np.array(zones, float)
            if prefix == "gap_bin":
                where = (where - 0.5) / len(zones)  # xi at the bin's middle
            ax.errorbar(where, mean, yerr=np.nan_to_num(se), fmt="o-", capsize=3,
                        label=f"{spec['x']}={value:g} ({len(subset)} seeds)")
        ax.set_xlabel("zone (1: innermost)" if prefix == "zone"
                      else "xi = distance from the chamber wall / local gap")
        ax.set_title(q.replace("_", " "), fontsize=8)
        if q not in ("azimuthal_velocity", "radial_velocity"):
            ax.set_yscale("log")
        ax.legend(fontsize=6)
        ax.grid(True, alpha=0.3)
    fig.suptitle(title, fontsize=9)
    save(fig, os.path.join(out_dir, f"mechanofusion_{study}_{prefix.rstrip('_')}_profiles.png"))


def save(fig, path):
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    print(path)


def means_table(study, rows, spec, quantities):
    """Mean +- standard error per value of the study's parameter, one line each."""
    for q in quantities:
        for key, (xs, means, errors, counts, _) in grouped(rows, spec["x"], q, spec.get("by")).items():
            for xv, m, e, c in zip(xs, means, errors, counts):
                tag = f" {spec['by']}={key:g}" if key is not None else ""
                print(f"mean study={study}{tag} {spec['x']}={xv:g} {q}={m:.4g} +- {e:.2g} seeds={c}")


def cost_figure(path, fits, out_dir):
    """Fig. 4.4: CPU time per simulated second against the loading (tools/mechanofusion_cost.lua)."""
    rows = read_csv(path)
    fig, ax = plt.subplots(figsize=(4.8, 3.6))
    for diagnostics, marker in (("no", "o"), ("yes", "s")):
        sub = [r for r in rows if r["diagnostics"] == diagnostics]
        if len(sub) < 2:
            continue
        n = np.array([number(r["particles"]) for r in sub])
        t = np.array([number(r["cpu_seconds_per_simulated_second"]) for r in sub])
        b, se, a = power_fit(n, t)
        fits.append(("cost", f"cpu_seconds_per_simulated_second (diagnostics {diagnostics})", b, se, 1,
                     "faster than N^2 (Fig. 4.4)"))
        print(f"fit study=cost diagnostics={diagnostics} exponent={b:.3f} +- {se:.3f}")
        ax.loglog(n, t, marker, label=f"diagnostics {diagnostics}: N^{b:.2f}+-{se:.2f}")
        ax.loglog(n, a * n ** b, "-", lw=0.8, color=ax.lines[-1].get_color())
    ax.set_xlabel("particles")
    ax.set_ylabel("CPU s per simulated s (one core)")
    ax.set_title("computing time against loading (Fig. 4.4)", fontsize=9)
    ax.legend(fontsize=7)
    ax.grid(True, which="both", alpha=0.3)
    save(fig, os.path.join(out_dir, "mechanofusion_cost.png"))


def ratio_figure(study, rows, spec, out_dir):
    """Two-valued studies (double: size_scale 2 against 1; slab: 3D against 2D): per
    seed the ratio of each force quantity, bars of the mean over the seeds +- its
    standard error, beside the 1 that the similarity argument (5.3.2, app. A) expects."""
    x = spec["x"]
    values = sorted({number(r[x]) for r in rows})
    if len(values) != 2:
        return
    low, high = values
    quantities = ([(f"normal_force_per_contact_{a}", f"per contact, {AREA_LABEL.get(a, a)}") for a in AREAS]
                  + [(f"normal_force_per_particle_{a}", f"per particle, {AREA_LABEL.get(a, a)}") for a in AREAS]
                  + [("gap_normal_force_per_contact", "per contact, gap sector"),
                     ("gap_shear_rate", "shear rate in the gap"),
                     ("inner_normal_force", "normal force on the inner piece")])
    by_seed = {}
    for r in rows:
        by_seed.setdefault(number(r.get("seed", 1)), {})[number(r[x])] = r
    labels, means, errors = [], [], []
    for q, label in quantities:
        ratios = [number(pair[high].get(q)) / number(pair[low].get(q)) for pair in by_seed.values()
                  if low in pair and high in pair and number(pair[low].get(q)) not in (0.0,)]
        ratios = [v for v in ratios if math.isfinite(v)]
        if not ratios:
            continue
        m = float(np.mean(ratios))
        e = float(np.std(ratios, ddof=1) / math.sqrt(len(ratios))) if len(ratios) > 1 else 0.0
        labels.append(label)
        means.append(m)
        errors.append(e)
        print(f"ratio study={study} {q} {x}={high:g}/{low:g} ratio={m:.3f} +- {e:.3f} seeds={len(ratios)}")
    if not labels:
        return
    fig, ax = plt.subplots(figsize=(8, 4.2))
    ax.barh(range(len(labels)), means, xerr=errors, color="tab:blue", alpha=0.7, capsize=3)
    ax.axvline(1, color="k", lw=0.8, ls="--")
    ax.set_yticks(range(len(labels)))
    ax.set_yticklabels(labels, fontsize=7)
    ax.invert_yaxis()
    ax.set_xscale("log")
    ax.set_xlabel(f"{x} = {high:g} over {x} = {low:g} (mean over seeds +- standard error)")
    ax.set_title(f"{study} study: forces against the original", fontsize=9)
    ax.grid(True, axis="x", which="both", alpha=0.3)
    save(fig, os.path.join(out_dir, f"mechanofusion_{study}_ratios.png"))


def figures(args):
    os.makedirs(args.output, exist_ok=True)
    fits = []
    found = False
    cost = os.path.join(args.data, "mechanofusion_cost.csv")
    if os.path.exists(cost):
        found = True
        cost_figure(cost, fits, args.output)
    tilt = os.path.join(args.data, "mechanofusion_scraper_tilt.csv")
    if os.path.exists(tilt):
        found = True
        tilt_figure(tilt, args.output)
    for study, spec in STUDIES.items():
        path = os.path.join(args.data, f"mechanofusion_{study}.csv")
        if not os.path.exists(path):
            continue
        found = True
        rows = read_csv(path)
        fit_figure(study, rows, spec, fits, args.output)
        versus_figure(study, rows, spec, fits, args.output)
        means_table(study, rows, spec, ["inner_normal_force", "max_overlap_ratio_fixed", "max_overlap_ratio_wall",
                                        "max_overlap_ratio_particle", "gap_shear_rate", "gap_nominal_shear_rate"]
                    + [f"coating_time_estimate_{c}" for c in ("one_patch_rstar", "two_patches_rstar",
                                                              "one_patch_r", "two_patches_r")]
                    + [f"normal_force_per_contact_{a}" for a in AREAS]
                    + [f"fraction_over_{t}_mm_s_{a}" for t in ("100", "200", "1000") for a in AREAS]
                    + [f"fraction_below_100_mm_s_{a}" for a in AREAS]
                    + ["two_times_ratio_per_particle", "two_times_ratio_per_contact",
                       "gap_temperature_over_eq_5_4", "gap_shear_rate_over_nominal", "gap_mean_solid_fraction"]
                    + [f"coating_time_{c}" for c in ("one_patch_rstar", "two_patches_rstar", "one_patch_r",
                                                     "two_patches_r")])
        if study in ("double", "slab"):
            ratio_figure(study, rows, spec, args.output)
        if study in ("scraper", "slab"):
            profile_figure(study, rows, spec, args.output, "zone",
                           ["rotational_ke", "deviatoric_ke", "pressure", "collision_work_rate", "solid_fraction"],
                           f"{study} study: zone profiles (4.3), mean over seeds +- standard error")
        if study in ("rpm", "gap"):
            profile_figure(study, rows, spec, args.output, "gap_bin",
                           ["azimuthal_velocity", "granular_temperature", "solid_fraction"],
                           f"{study} study: across the gap (sector +-10 deg), mean over seeds +- standard error")
    if not found:
        sys.exit(f"no mechanofusion_<study>.csv under {args.data}: run `tables` first")
    out = os.path.join(args.data, "mechanofusion_fits.csv")
    with open(out, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["study", "quantity", "exponent", "standard_error", "seeds", "claim"])
        for row in fits:
            w.writerow([row[0], row[1], f"{row[2]:.4f}", f"{row[3]:.4f}", row[4], row[5]])
    print(out)


def overlaps(args):
    import h5py
    out_rows = []
    for directory in args.sweeps:
        for r in read_csv(os.path.join(directory, "mechanofusion.sweep.csv")):
            if r["status"] not in ("ok", "reused"):
                continue
            with h5py.File(os.path.join(directory, r["file"]), "r") as f:
                group = f["diagnostics/overlaps/max_overlap_ratio"]
                medians = {k: float(np.median(group[k][()])) for k in ("particle", "fixed", "wall")}
            tilt = r.get("scraper_tilt") or ("none" if r.get("scraper", "true") == "false" else "70")
            out_rows.append([r["rpm"], tilt] + [r[f"max_overlap_ratio_{k}"] for k in ("fixed", "wall", "particle")]
                            + [f"{medians[k]:.6g}" for k in ("fixed", "wall", "particle")]
                            + [r["zone7_solid_fraction"], r["inner_normal_force"],
                               r["normal_force_per_particle_scraper"], r["duration"], r["settle"]])
    out = os.path.join(args.data, "mechanofusion_scraper_tilt.csv")
    with open(out, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["rpm", "scraper_tilt", "max_fixed", "max_wall", "max_particle", "window_median_fixed",
                    "window_median_wall", "window_median_particle", "outer_zone_solid_fraction",
                    "inner_normal_force", "scraper_area_force_per_particle", "measured_s", "settled_s"])
        for row in sorted(out_rows, key=lambda x: (number(x[0]), str(x[1]))):
            w.writerow(row)
    print(f"{out}: {len(out_rows)} cases")


def tilt_figure(path, out_dir):
    rows = read_csv(path)
    fig, axes = plt.subplots(1, 3, figsize=(11, 3.4))
    for ax, kind in zip(axes, ("fixed", "wall", "particle")):
        for rpm in sorted({number(r["rpm"]) for r in rows}):
            sub = sorted([r for r in rows if number(r["rpm"]) == rpm and r["scraper_tilt"] != "none"],
                         key=lambda r: number(r["scraper_tilt"]))
            tilts = [number(r["scraper_tilt"]) for r in sub]
            line, = ax.semilogy(tilts, [number(r[f"max_{kind}"]) for r in sub], "o-", label=f"{rpm:g} rpm, run max")
            ax.semilogy(tilts, [number(r[f"window_median_{kind}"]) for r in sub], "s--", color=line.get_color(),
                        label=f"{rpm:g} rpm, median window max")
            none = [r for r in rows if number(r["rpm"]) == rpm and r["scraper_tilt"] == "none"]
            if none and kind != "fixed":
                ax.axhline(number(none[0][f"max_{kind}"]), color=line.get_color(), lw=0.6, ls=":")
        ax.axhline(0.02, color="k", lw=0.8)
        ax.set_xlabel("scraper tilt to the wall's tangent (deg)")
        ax.set_ylabel("overlap / radius")
        ax.set_title({"fixed": "particle-scraper", "wall": "particle-wall", "particle": "particle-particle"}[kind]
                     + " (dotted: no scraper)", fontsize=8)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=6)
    save(fig, os.path.join(out_dir, "mechanofusion_scraper_tilt.png"))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="command", required=True)
    t = sub.add_parser("tables")
    t.add_argument("work")
    t.add_argument("--data", default=os.path.join(ROOT, "docs", "data"))
    t.add_argument("--replace", action="store_true",
                   help="write each table from WORK alone (default: keep the table's other cases)")
    f = sub.add_parser("figures")
    f.add_argument("--data", default=os.path.join(ROOT, "docs", "data"))
    f.add_argument("-o", "--output", default=os.path.join(ROOT, "docs", "figures"))
    o = sub.add_parser("overlaps")
    o.add_argument("sweeps", nargs="+")
    o.add_argument("--data", default=os.path.join(ROOT, "docs", "data"))
    args = ap.parse_args(argv)
    {"tables": tables, "figures": figures, "overlaps": overlaps}[args.command](args)


if __name__ == "__main__":
    main()
