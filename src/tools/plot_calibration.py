#!/usr/bin/python3
"""Plots of a BPM calibration run (written by `calibrate`): marginal means of both responses
(paper Figure 11) and force-closure curves of the DOE, confirmation and single-particle runs.
usage: plot_calibration.py DIR   (reads DIR/marginal_means.csv, DIR/curves/*.csv; writes DIR/*.png)"""
import csv
import glob
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def marginal_means(out):
    rows = read_csv(os.path.join(out, "marginal_means.csv"))
    responses = [("force_difference_kN", "Force difference F_cd (kN)", "marginal_means_force_difference.png"),
                 ("critical_compression_ratio_pct", "Critical compression ratio (%)",
                  "marginal_means_compression_ratio.png")]
    factors = []
    for r in rows:
        if r["factor"] not in factors:
            factors.append(r["factor"])
    for key, label, name in responses:
        fig, axes = plt.subplots(1, len(factors), figsize=(3 * len(factors), 3.2), sharey=True)
        for ax, fac in zip(axes, factors):
            pts = sorted(((float(r["value"]), float(r["mean"])) for r in rows
                          if r["response"] == key and r["factor"] == fac))
            ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-")
            ax.set_title(fac, fontsize=9)
            ax.grid(alpha=0.3)
        axes[0].set_ylabel("mean of " + label)
        fig.suptitle("Marginal means: " + label)
        fig.tight_layout()
        fig.savefig(os.path.join(out, name), dpi=110)
        plt.close(fig)


def curves(out):
    groups = [("doe_run_*.csv", "force_curves_doe.png", "L16 Brazilian runs"),
              ("confirmation_*.csv", "force_curves_confirmation.png", "Confirmation runs"),
              ("single_particle_*.csv", "force_curves_single_particle.png", "Single-particle compression")]
    for pattern, name, title in groups:
        files = sorted(glob.glob(os.path.join(out, "curves", pattern)),
                       key=lambda p: int("".join(c for c in os.path.basename(p) if c.isdigit()) or 0))
        if not files:
            continue
        fig, ax = plt.subplots(figsize=(6, 4))
        for f in files:
            rows = read_csv(f)
            ax.plot([float(r["closure_mm"]) for r in rows], [float(r["force_kN"]) for r in rows],
                    label=os.path.basename(f)[:-4], lw=1)
        if "confirmation" in pattern or "doe" in pattern:
            ax.axhline(14.8, color="k", ls="--", lw=0.8, label="experiment 14.8 kN")
        ax.set_xlabel("platen closure (mm)")
        ax.set_ylabel("force (kN)")
        ax.set_title(title)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=6, ncol=2)
        fig.tight_layout()
        fig.savefig(os.path.join(out, name), dpi=110)
        plt.close(fig)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    marginal_means(out)
    curves(out)


if __name__ == "__main__":
    main()
