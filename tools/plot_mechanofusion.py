#!/usr/bin/python3
"""Figures and power-law fits of the Mechanofusion studies (docs/mechanofusion.md).

usage:
  /usr/bin/python3 tools/plot_mechanofusion.py study mechanofusion_rpm.h5 [-o DIR]
  /usr/bin/python3 tools/plot_mechanofusion.py series mechanofusion_rpm_case3.h5 [-o DIR]
  /usr/bin/python3 tools/plot_mechanofusion.py peaks mechanofusion_rpm_case3.h5 [-o DIR]
  /usr/bin/python3 tools/plot_mechanofusion.py patterns mechanofusion_scraper.h5 [-o DIR]

study: reads /cases and /profiles written by scenarios/mechanofusion_study.lua,
recognises the study from its name (/scene/parameters study) and draws its
figures; fits F = a x^b by least squares on the logarithms and prints one
line per fit:  fit study=rpm quantity=inner_normal_force exponent=1.93 +- 0.1 ...
series: the areas' forces, collisions and collision ratios against time
(Figs. 4.20-4.25) and the inner piece's force series, from one case's file.
patterns: the pictures study=scraper drew (<stem>_with_*.png, <stem>_without_*.png)
side by side in time order (Figs. 4.6-4.7); give the study's .h5 file.
peaks: the per-area histograms of the largest contact force and of the
impact velocity derived from it (Figs. 7.1-7.8), from one case's file.
Writes PNGs (default: next to the input) and prints their paths.
"""

import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import granule_h5 as g  # noqa: E402

AREAS = ["inner_piece", "scraper", "input", "free_diffusion"]
AREA_LABEL = {"inner_piece": "1 inner piece", "scraper": "2 scraper", "input": "3 input",
              "free_diffusion": "4 free diffusion"}
KEY_OF = {v: k for k, v in AREA_LABEL.items()}


def power_fit(x, y):
    """Least squares of log y = log a + b log x: returns (b, standard error of b, a)."""
    x, y = np.asarray(x, float), np.abs(np.asarray(y, float))
    ok = (x > 0) & (y > 0) & np.isfinite(y)
    x, y = np.log(x[ok]), np.log(y[ok])
    if len(x) < 2:
        return float("nan"), float("nan"), float("nan")
    A = np.vstack([x, np.ones_like(x)]).T
    coef, res, _, _ = np.linalg.lstsq(A, y, rcond=None)
    b, loga = coef
    if len(x) > 2:
        resid = y - A @ coef
        s2 = resid @ resid / (len(x) - 2)
        se = np.sqrt(s2 / np.sum((x - x.mean()) ** 2))
    else:
        se = float("nan")
    return float(b), float(se), float(np.exp(loga))


def read_cases(path):
    with g.open_run(path) as f:
        cases = g.series(f, "/cases")
        profiles = g.series(f, "/profiles") if "profiles" in f else None
        params = g.parameters(f)
    return cases, profiles, params


def report_fit(study, quantity, x, y, claim, fits):
    b, se, a = power_fit(x, y)
    fits.append((study, quantity, b, se, claim))
    print(f"fit study={study} quantity={quantity} exponent={b:.3f} +- {se:.3f} prefactor={a:.4g} "
          f"points={len(x)} claim={claim}")
    return b, se, a


def loglog_panel(ax, x, ys, labels, study, quantity_prefix, claim, fits, xlabel, ylabel, ref=None):
    markers = "osd^v<>"
    for k, (y, label) in enumerate(zip(ys, labels)):
        y = np.abs(np.asarray(y))
        key = KEY_OF.get(label, label)
        b, se, a = report_fit(study, f"{quantity_prefix}{key}", x, y, claim, fits)
        line, = ax.loglog(x, y, markers[k % len(markers)], label=f"{label}: x^{b:.2f}")
        xs = np.geomspace(min(x), max(x), 50)
        if np.isfinite(b):
            ax.loglog(xs, a * xs ** b, "-", color=line.get_color(), lw=1)
    if ref is not None:
        # The claimed law through the geometric middle of the first series.
        y0 = np.abs(np.asarray(ys[0]))
        xm = np.exp(np.mean(np.log(x)))
        ym = np.exp(np.mean(np.log(y0[y0 > 0]))) if np.any(y0 > 0) else 1
        xs = np.geomspace(min(x), max(x), 50)
        ax.loglog(xs, ym * (xs / xm) ** ref, "k--", lw=0.8, label=f"claim x^{ref:g}")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.legend(fontsize=7)
    ax.grid(True, which="both", alpha=0.3)


def out_path(args, stem, suffix):
    d = args.output or os.path.dirname(os.path.abspath(args.file))
    os.makedirs(d, exist_ok=True)
    return os.path.join(d, f"{stem}_{suffix}.png")


def save(fig, path, dpi=110):
    fig.tight_layout()
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    print(path)


def study_figures(args):
    cases, profiles, params = read_cases(args.file)
    study = str(params.get("study", "")) if params else ""
    stem = os.path.splitext(os.path.basename(args.file))[0]
    short = " (short runs)" if str(params.get("short", "")).lower() in ("true", "1") else ""
    fits = []
    if study == "rpm":
        rpm = cases["rpm"]
        fig, ax = plt.subplots(1, 2, figsize=(10, 4))
        loglog_panel(ax[0], rpm, [cases["inner_normal_force"], cases["inner_tangential_force"]],
                     ["normal", "tangential"], study, "inner_", 2, fits, "chamber speed [rpm]",
                     "mean force on the inner piece [N]", ref=2)
        ax[0].set_title("Figs. 4.16 / 5.3: force on the inner piece" + short, fontsize=9)
        loglog_panel(ax[1], rpm, [cases[f"normal_force_per_contact_{a}"] for a in AREAS],
                     [AREA_LABEL[a] for a in AREAS], study, "contact_normal_", 1, fits,
                     "chamber speed [rpm]", "mean normal force per contact [N]", ref=1)
        ax[1].set_title("Figs. 4.32 / 5.11-5.12: inter-particle force per area" + short, fontsize=9)
        save(fig, out_path(args, stem, "forces"))
        fig, ax = plt.subplots(figsize=(5, 4))
        loglog_panel(ax, rpm, [cases[f"normal_force_per_particle_{a}"] for a in AREAS],
                     [AREA_LABEL[a] for a in AREAS], study, "particle_normal_", 1, fits,
                     "chamber speed [rpm]", "mean normal force per particle [N]", ref=1)
        save(fig, out_path(args, stem, "per_particle"))
        fig, ax = plt.subplots(figsize=(5, 4))
        loglog_panel(ax, rpm, [cases["coating_time_estimate"]], ["coating_time"], study, "", -1,
                     fits, "chamber speed [rpm]", "minimum coating time estimate [s]", ref=-1)
        ax.set_title("Fig. 4.33: coating time" + short, fontsize=9)
        save(fig, out_path(args, stem, "coating"))
    elif study == "loading":
        fig, ax = plt.subplots(1, 2, figsize=(10, 4))
        for k, (col, title) in enumerate([("inner_normal_force", "Fig. 4.17: normal"),
                                          ("inner_tangential_force", "Fig. 4.18: tangential")]):
            for rpm in np.unique(cases["rpm"]):
                sel = cases["rpm"] == rpm
                x, y = cases["particles"][sel], np.abs(cases[col][sel])
                b, se, a = report_fit(study, f"{col}_{rpm:g}rpm", x, y, "increases", fits)
                ax[k].plot(x, y, "o-", label=f"{rpm:g} rpm: N^{b:.2f}")
            ax[k].set_xlabel("loading [particles]")
            ax[k].set_ylabel("mean force on the inner piece [N]")
            ax[k].set_title(title + short, fontsize=9)
            ax[k].legend(fontsize=7)
            ax[k].grid(True, alpha=0.3)
        save(fig, out_path(args, stem, "forces"))
    elif study in ("gap", "stiffness"):
        key, claim, label = {"gap": ("gap", -1, "gap H [m]"),
                             "stiffness": ("k_load", 0.5, "loading stiffness K1 [N/m]")}[study]
        x = cases[key]
        fig, ax = plt.subplots(1, 2, figsize=(10, 4))
        loglog_panel(ax[0], x, [cases[f"normal_force_per_contact_{a}"] for a in AREAS],
                     [AREA_LABEL[a] for a in AREAS], study, "contact_normal_", claim, fits, label,
                     "mean normal force per contact [N]", ref=claim)
        loglog_panel(ax[1], x, [cases[f"normal_force_per_particle_{a}"] for a in AREAS],
                     [AREA_LABEL[a] for a in AREAS], study, "particle_normal_", claim, fits, label,
                     "mean normal force per particle [N]", ref=claim)
        title = {"gap": "Figs. 4.34 / 5.13: force per area vs gap",
                 "stiffness": "Figs. 5.9-5.10: force per area vs stiffness"}[study]
        ax[0].set_title(title + short, fontsize=9)
        save(fig, out_path(args, stem, "forces"))
        if study == "gap":
            fig, ax = plt.subplots(figsize=(5, 4))
            ax.plot(x * 1e3, cases["coating_time_estimate"], "o-")
            ax.set_xlabel("gap [mm]")
            ax.set_ylabel("minimum coating time estimate [s]")
            ax.set_title("Fig. 4.35: coating time vs gap" + short, fontsize=9)
            ax.grid(True, alpha=0.3)
            save(fig, out_path(args, stem, "coating"))
    elif study == "double":
        fig, ax = plt.subplots(1, 2, figsize=(10, 4))
        w = 0.38
        pos = np.arange(len(AREAS))
        for k, kind in enumerate(["normal", "tangential"]):
            for j in range(len(cases["case"])):
                vals = [cases[f"{kind}_force_per_contact_{a}"][j] for a in AREAS]
                ax[k].bar(pos + (j - 0.5) * w, vals, w,
                          label=f"size x{cases['size_scale'][j]:g}, {int(cases['particles'][j])} particles")
            ax[k].set_xticks(pos)
            ax[k].set_xticklabels([AREA_LABEL[a] for a in AREAS], fontsize=8)
            ax[k].set_ylabel(f"mean {kind} force per contact [N]")
            ax[k].legend(fontsize=7)
            ax[k].set_title(f"Figs. 5.4-5.7: {kind}, original vs double-sized" + short, fontsize=9)
        for a in AREAS:
            r = cases[f"normal_force_per_contact_{a}"]
            if len(r) >= 2 and r[0] > 0:
                print(f"ratio study=double area={a} normal_double_over_original={r[1] / r[0]:.3f} claim=1")
        save(fig, out_path(args, stem, "forces"))
    if profiles is not None and study in ("scraper", "slab", "double", "rpm"):
        profile_figure(args, cases, profiles, study, stem, short)
    write_fits(args, stem, fits)


def profile_figure(args, cases, profiles, study, stem, short):
    quantities = [("rotational_ke", "rotational KE (4.10) [J/m^3]", "Figs. 4.8-4.9 / A.2"),
                  ("deviatoric_ke", "deviatoric KE (4.11, polar mean) [J/m^3]", "Figs. 4.10-4.11 / A.4"),
                  ("pressure", "pressure (4.12) [Pa]", "Figs. 4.12-4.13 / A.6"),
                  ("collision_work_rate", "collision work rate (4.13) [W/m^3]", "Figs. 4.14-4.15"),
                  ("solid_fraction", "solid fraction [-]", ""),
                  ("deviatoric_ke_cartesian", "deviatoric KE, Cartesian mean [J/m^3]", "4.11 as printed")]
    fig, axes = plt.subplots(2, 3, figsize=(13, 7))
    for ax, (q, label, figs) in zip(axes.flat, quantities):
        for j, c in enumerate(cases["case"]):
            sel = profiles["case"] == c
            zone = profiles["zone"][sel]
            name = case_label(cases, j, study)
            ax.plot(zone, profiles[q][sel], "o-", label=name)
        ax.set_xlabel("zone (1 = centre, 7 = wall)")
        ax.set_ylabel(label, fontsize=8)
        ax.set_title(figs + short, fontsize=8)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=6)
    save(fig, out_path(args, stem, "zones"))


def case_label(cases, j, study):
    if study == "scraper":
        return "with scraper" if cases["scraper"][j] else "without scraper"
    if study == "slab":
        return f"{int(cases['dimension'][j])}D, {int(cases['particles'][j])} particles"
    if study == "double":
        return f"size x{cases['size_scale'][j]:g}"
    return f"{cases['rpm'][j]:g} rpm"


def write_fits(args, stem, fits):
    if not fits:
        return
    d = args.output or os.path.dirname(os.path.abspath(args.file))
    path = os.path.join(d, f"{stem}_fits.csv")
    with open(path, "w") as f:
        f.write("study,quantity,exponent,standard_error,claim\n")
        for s, q, b, se, c in fits:
            f.write(f"{s},{q},{b:.4f},{se:.4f},{c}\n")
    print(path)


def series_figures(args):
    stem = os.path.splitext(os.path.basename(args.file))[0]
    with g.open_run(args.file) as f:
        if "diagnostics/areas" not in f:
            raise g.GranuleH5Error(f"{args.file}: no /diagnostics/areas (attach the 'areas' diagnostic)")
        data = {name: g.series(f, f"/diagnostics/areas/{name}") for name in f["diagnostics/areas"]}
        inner = g.series(f, "/diagnostics/inner_piece_force") if "diagnostics/inner_piece_force" in f else None
    panels = [("normal_force_per_particle", "mean normal force per particle [N]", "Fig. 4.20"),
              ("tangential_force_per_particle", "mean tangential force per particle [N]", "Fig. 4.21"),
              ("collisions_boundary", "cumulative particle-boundary collisions", "Fig. 4.22"),
              ("collisions_particle", "cumulative particle-particle collisions", "Fig. 4.23"),
              ("collision_ratio_boundary", "collision ratio, boundary (4.14)", "Fig. 4.24"),
              ("collision_ratio_particle", "collision ratio, particles (4.14)", "Fig. 4.25")]
    fig, axes = plt.subplots(2, 3, figsize=(13, 7))
    for ax, (name, label, figure) in zip(axes.flat, panels):
        s = data[name]
        for a in AREAS:
            ax.plot(s["time"], s[a], label=AREA_LABEL[a])
        ax.set_xlabel("time [s]")
        ax.set_ylabel(label, fontsize=8)
        ax.set_title(figure, fontsize=9)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=6)
    save(fig, out_path(args, stem, "areas"))
    if inner is not None:
        fig, ax = plt.subplots(figsize=(6, 4))
        ax.plot(inner["time"], inner["normal_force"], label="normal")
        ax.plot(inner["time"], inner["tangential_force"], label="tangential")
        ax.set_xlabel("time [s]")
        ax.set_ylabel("force on the inner piece [N]")
        ax.set_title("4.4.1: force on the inner piece, window means", fontsize=9)
        ax.legend()
        ax.grid(True, alpha=0.3)
        save(fig, out_path(args, stem, "inner_force"))


def peaks_figures(args):
    stem = os.path.splitext(os.path.basename(args.file))[0]
    with g.open_run(args.file) as f:
        grp = f["diagnostics/contact_peaks"]
        fe = np.asarray(grp.attrs["force_bin_edges"])
        ve = np.asarray(grp.attrs["velocity_bin_edges"])
        last = {}
        for name in grp:
            if "histogram" in name:
                s = g.series(f, f"/diagnostics/contact_peaks/{name}")
                cols = [k for k in s if k.startswith("bin_")]
                cols.sort(key=lambda k: int(k[4:]))
                last[name] = np.array([s[k][-1] for k in cols])
    fig, axes = plt.subplots(2, 4, figsize=(15, 6.5))
    for k, a in enumerate(AREAS):
        h = last[f"force_histogram_{a}"]
        n = max(h.sum(), 1)
        axes[0, k].bar(fe[:-1] * 1e3, h / n, width=np.diff(fe) * 1e3, align="edge")
        axes[0, k].set_xlabel("largest normal force of a contact [mN]")
        axes[0, k].set_ylabel("fraction of contacts")
        axes[0, k].set_title(f"Fig. 7.{k + 1}: {AREA_LABEL[a]} ({int(h.sum())} contacts)", fontsize=9)
        hv = last[f"velocity_histogram_{a}"]
        hm = last[f"impact_velocity_histogram_{a}"]
        axes[1, k].step(ve[:-1], hv / max(hv.sum(), 1), where="post", label="F_max / c (7.2)")
        axes[1, k].step(ve[:-1], hm / max(hm.sum(), 1), where="post", label="measured approach")
        axes[1, k].set_xlabel("relative impact velocity [m/s]")
        axes[1, k].set_ylabel("fraction of contacts")
        axes[1, k].set_title(f"Fig. 7.{k + 5}: {AREA_LABEL[a]}", fontsize=9)
        axes[1, k].legend(fontsize=7)
        axes[0, k].set_xlim(0, fe[_upper_bin(h)] * 1e3)
        axes[1, k].set_xlim(0, ve[max(_upper_bin(hv), _upper_bin(hm))])
    save(fig, out_path(args, stem, "peaks"))


def _upper_bin(h, keep=0.999):
    """Index of the bin edge below which `keep` of the counts lie (for the x range)."""
    c = np.cumsum(h)
    if c[-1] <= 0:
        return len(h)
    return min(len(h), int(np.searchsorted(c, keep * c[-1])) + 2)


def pattern_figure(args):
    import glob
    stem = os.path.splitext(args.file)[0]
    rows = [(kind, sorted(glob.glob(f"{stem}_{kind}_*ms.png"))) for kind in ("with", "without")]
    rows = [(k, files) for k, files in rows if files]
    if not rows:
        raise g.GranuleH5Error(f"no pictures {stem}_with_*ms.png or {stem}_without_*ms.png")
    cols = max(len(files) for _, files in rows)
    fig, axes = plt.subplots(len(rows), cols, figsize=(3.2 * cols, 3.4 * len(rows)), squeeze=False)
    for r, (kind, files) in enumerate(rows):
        for c in range(cols):
            ax = axes[r, c]
            ax.axis("off")
            if c < len(files):
                ax.imshow(plt.imread(files[c]))
                ms = files[c].rsplit("_", 1)[-1].replace("ms.png", "")
                ax.set_title(f"{kind} scraper, +{int(ms)} ms", fontsize=9)
    path = out_path(args, os.path.basename(stem), "patterns")
    save(fig, path, dpi=70)
    try:  # a palette image: the pictures have few colours, and the docs keep the file
        from PIL import Image
        Image.open(path).convert("RGB").quantize(colors=96).save(path, optimize=True)
    except ImportError:
        pass


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("what", choices=["study", "series", "peaks", "patterns"])
    parser.add_argument("file")
    parser.add_argument("-o", "--output", help="directory for the PNGs (default: beside the input)")
    args = parser.parse_args(argv)
    try:
        {"study": study_figures, "series": series_figures, "peaks": peaks_figures,
         "patterns": pattern_figure}[args.what](args)
    except (g.GranuleH5Error, KeyError) as e:
        print(f"plot_mechanofusion: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
