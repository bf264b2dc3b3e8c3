#!/usr/bin/python3
"""Angle of repose against mu_r from the lines repose_rolling.lua prints.

    plot_repose.py ANGLES.txt OUT.png
"""
import re
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

angles = {}
pattern = re.compile(r"mu_r = ([0-9.eE+-]+) .*seed (\d+): angle ([0-9.eE+-]+) deg")
for line in open(sys.argv[1]):
    m = pattern.search(line)
    if m:
        angles.setdefault(float(m.group(1)), []).append(float(m.group(3)))
if not angles:
    sys.exit(f"{sys.argv[1]}: no 'repose_rolling: ... angle' lines")
mus = sorted(angles)
mean = [np.mean(angles[m]) for m in mus]
sem = [np.std(angles[m], ddof=1) / np.sqrt(len(angles[m])) if len(angles[m]) > 1 else 0
       for m in mus]
print("| mu_r | seeds | angle (deg) | standard error |")
print("|---|---|---|---|")
for m, a, e in zip(mus, mean, sem):
    print(f"| {m:g} | {len(angles[m])} | {a:.1f} | {e:.1f} |")
fig, ax = plt.subplots(figsize=(4.5, 3.2))
ax.errorbar(mus, mean, yerr=sem, marker="o", capsize=3)
ax.set_xlabel("rolling friction mu_r")
ax.set_ylabel("angle of repose (deg)")
ax.set_title("2D column collapse, 200 spheres (repose_rolling.lua)", fontsize=9)
fig.tight_layout()
fig.savefig(sys.argv[2], dpi=120)
