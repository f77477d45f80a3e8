#!/usr/bin/python3
"""Plots of a gap-slice run (written by `gap_slice`): the mantle plate's force against its travel, a panel per drive
speed with a loop per cycle, and each cycle's work beside the flow model's shipped law (each pressing from loose).
usage: plot_gap_slice.py DIR   (reads DIR/gap_slice.csv and DIR/gap_slice_trace.csv; writes DIR/gap_slice.png)"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def main(out):
    cycles = read_csv(os.path.join(out, "gap_slice.csv"))
    trace = read_csv(os.path.join(out, "gap_slice_trace.csv"))
    speeds = sorted({float(r["rpm"]) for r in cycles})
    if not speeds:
        sys.exit("plot_gap_slice.py: %s/gap_slice.csv holds no cycle" % out)
    fig, axes = plt.subplots(1, len(speeds) + 1, figsize=(5 * (len(speeds) + 1), 4.5), squeeze=False)
    axes = axes[0]
    for ax, rpm in zip(axes, speeds):
        pts = [r for r in trace if float(r["rpm"]) == rpm]
        open_gap = max((float(r["gap_mm"]) for r in pts), default=0.0)
        for k in sorted({int(r["cycle"]) for r in pts}):
            c = [r for r in pts if int(r["cycle"]) == k]
            ax.plot([open_gap - float(r["gap_mm"]) for r in c], [float(r["force_kN"]) for r in c], lw=1,
                    label="cycle %d" % k)
        ax.set_xlabel("plate travel from the open gap (mm)")
        ax.set_ylabel("force on the mantle plate (kN)")
        ax.set_title("%.0f rpm" % rpm)
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
    ax = axes[-1]
    for rpm in speeds:
        rows = [r for r in cycles if float(r["rpm"]) == rpm]
        ax.plot([int(r["cycle"]) for r in rows], [float(r["work_J_kg"]) for r in rows], "o-", label="DEM %.0f rpm" % rpm)
    law = float(cycles[0]["law_J_kg"])
    ax.axhline(law, color="k", ls=":", label="shipped law, from loose (%.2f J/kg)" % law)
    ax.set_xlabel("cycle")
    ax.set_ylabel("plate's work on the rock per cycle (J/kg)")
    ax.set_yscale("log")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "gap_slice.png"), dpi=110)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
