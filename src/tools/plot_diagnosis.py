#!/usr/bin/python3
"""Plots for the mismatch diagnosis: overlay_<i>.png (recording, model before and after the fitted
effect, per channel) and residual_spectrum.png (residual power by harmonic order of the drive
frequency, before and after, per channel); for a summary recording (diagnose --summary), summary.png (plant,
model before and after, per compared quantity and speed). Usage: plot_diagnosis.py DIR (written by diagnose)."""
import glob
import json
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

# Every channel a recording may hold; a plot shows those compared (a set point or a channel not recorded
# has no model curve: diagnosis.json "inputs").
CH = ["x_m", "y_m", "z_m", "ax_m_s2", "ay_m_s2", "az_m_s2", "power_W", "speed_rad_s"]
LABEL = {"x_m": "x (mm)", "y_m": "y (mm)", "z_m": "z (mm)", "ax_m_s2": "ax (m/s^2)", "ay_m_s2": "ay (m/s^2)",
         "az_m_s2": "az (m/s^2)", "power_W": "power (kW)", "speed_rad_s": "speed (rad/s)"}
SCALE = {"x_m": 1e3, "y_m": 1e3, "z_m": 1e3, "ax_m_s2": 1.0, "ay_m_s2": 1.0, "az_m_s2": 1.0, "power_W": 1e-3,
         "speed_rad_s": 1.0}


def summary_plot(d, diag):
    qs = sorted(diag["uncertainty_pct"])
    rows = list(zip(diag["before"], diag["after"]))
    fig, axes = plt.subplots(1, len(qs), figsize=(4 * len(qs), 4), squeeze=False)
    for ax, q in zip(axes[0], qs):
        x = np.arange(len(rows))
        plant = [b["plant"].get(q, np.nan) for b, _ in rows]
        err = [abs(p) * diag["uncertainty_pct"][q] / 100 for p in plant]
        before = [b["model"].get(q, np.nan) for b, _ in rows]
        after = [a["model"].get(q, np.nan) for _, a in rows]
        ax.bar(x - 0.27, plant, 0.27, yerr=err, color="k", alpha=0.6, label="plant (1 sigma)")
        ax.bar(x, before, 0.27, color="r", label="model before")
        ax.bar(x + 0.27, after, 0.27, color="b", label="model after")
        ax.set_xticks(x)
        ax.set_xticklabels(["%.0f rpm" % b["speed_rpm"] for b, _ in rows])
        ax.set_title(q, fontsize=9)
    axes[0][0].legend(fontsize=7)
    fig.suptitle("diagnosis: %s" % diag["effect"], fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(d, "summary.png"), dpi=90)
    plt.close(fig)


def main(d):
    with open(os.path.join(d, "diagnosis.json")) as f:
        diag = json.load(f)
    if diag.get("input") == "summary":
        summary_plot(d, diag)
        return
    names = [c["dataset"] for c in diag["metrics"]["before"]["train"] + diag["metrics"]["before"]["heldout"]]
    for path in sorted(glob.glob(os.path.join(d, "overlay_*.csv"))):
        i = int(os.path.basename(path)[8:-4])
        a = np.genfromtxt(path, delimiter=",", names=True)
        chs = [c for c in CH if "rec_" + c in a.dtype.names]
        fig, axes = plt.subplots(len(chs), 1, figsize=(9, 2.2 * len(chs) + 0.5), sharex=True, squeeze=False)
        axes = axes[:, 0]
        for ax, c in zip(axes, chs):
            s = SCALE[c]
            ax.plot(a["t_s"], a["rec_" + c] * s, "k.", ms=1.5, label="recording")
            ax.plot(a["t_s"], a["before_" + c] * s, "r-", lw=1, label="model before")
            ax.plot(a["t_s"], a["after_" + c] * s, "b--", lw=1, label="model after (%s)" % diag["effect"])
            ax.set_ylabel(LABEL[c])
        axes[0].legend(loc="upper right", fontsize=7)
        axes[-1].set_xlabel("t (s)")
        title = names[i] if i < len(names) else path
        fig.suptitle("%s%s" % (title, " (held out)" if i >= len(diag["metrics"]["before"]["train"]) else " (training)"))
        fig.tight_layout()
        fig.savefig(os.path.join(d, "overlay_%d.png" % i), dpi=90)
        plt.close(fig)
    before = diag["metrics"]["before"]["train"] + diag["metrics"]["before"]["heldout"]
    after = diag["metrics"]["after"]["train"] + diag["metrics"]["after"]["heldout"]
    chs = [c for c in CH if any(c in b["channels"] for b in before)]
    fig, axes = plt.subplots(len(chs), len(before), figsize=(5 * len(before), 2.2 * len(chs) + 0.5), squeeze=False)
    for j, (b, a) in enumerate(zip(before, after)):
        for k, c in enumerate(chs):
            ax = axes[k][j]
            if c not in b["channels"] or c not in a["channels"]:
                ax.set_axis_off()
                continue
            noise = b["channels"][c]["noise_std"] ** 2
            pb = np.array(b["channels"][c]["order_residual_power"]) / noise
            pa = np.array(a["channels"][c]["order_residual_power"]) / noise
            x = np.arange(len(pb))
            ax.bar(x - 0.2, pb, 0.4, color="r", label="before")
            ax.bar(x + 0.2, pa, 0.4, color="b", label="after")
            ax.set_yscale("log")
            ax.set_xticks(x)
            ax.set_xticklabels([str(o) for o in range(len(pb) - 1)] + ["7-12"])
            ax.set_ylabel("%s\nresidual power / noise var" % c, fontsize=8)
            if k == 0:
                ax.set_title(b["dataset"], fontsize=9)
                ax.legend(fontsize=7)
            if k == len(chs) - 1:
                ax.set_xlabel("harmonic order of the drive frequency")
    fig.tight_layout()
    fig.savefig(os.path.join(d, "residual_spectrum.png"), dpi=90)
    plt.close(fig)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
