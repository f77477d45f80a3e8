#!/usr/bin/env python3
"""Plots of one run from its bag: test-point displacement x/y/z and drive power vs time, and (when the
DEM was attached) the product size distribution and the concave force map."""
import argparse
import json
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import rosbag  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bag", required=True, action="append",
                    help="run.bag (coupled runs: holds the DEM's topics too); repeat to read node bags that were not merged")
    ap.add_argument("--summary")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    t, d, tp, p = [], [], [], []
    psd, fmap = None, None
    maps = []
    for path in a.bag:
        with rosbag.Bag(path) as bag:
            for topic, m, _ in bag.read_messages(topics=["/crusher/test_point", "/crusher/drive",
                                                         "/crusher/product", "/crusher/concave_forces"]):
                if topic == "/crusher/test_point":
                    t.append(m.header.stamp.to_sec())
                    d.append((m.displacement.x * 1e3, m.displacement.y * 1e3, m.displacement.z * 1e3))
                elif topic == "/crusher/drive":
                    tp.append(m.header.stamp.to_sec())
                    p.append(m.power * 1e-3)
                elif topic == "/crusher/product":
                    psd = (list(m.sieve_mm), list(m.passing_pct))
                else:
                    maps.append((m.rings, m.sectors, m.window_s, list(m.mean_normal_force)))
    if maps:  # time-weighted mean over the run of the windowed means
        rings, sectors = maps[-1][0], maps[-1][1]
        wsum = sum(w for _, _, w, _ in maps) or 1.0
        fmap = (rings, sectors, [sum(w * f[k] for _, _, w, f in maps) / wsum for k in range(rings * sectors)])
    if t:
        fig, ax = plt.subplots(3, 1, sharex=True, figsize=(8, 6))
        for i, name in enumerate("xyz"):
            ax[i].plot(t, [v[i] for v in d], lw=0.8)
            ax[i].set_ylabel(f"{name} (mm)")
        ax[2].set_xlabel("time (s)")
        fig.suptitle("test-point displacement")
        fig.savefig(os.path.join(a.out, "displacement.png"), dpi=110)
    if tp:
        fig, ax = plt.subplots(figsize=(8, 3.5))
        ax.plot(tp, p, lw=0.8)
        ax.set_xlabel("time (s)")
        ax.set_ylabel("drive power (kW)")
        fig.tight_layout()
        fig.savefig(os.path.join(a.out, "power.png"), dpi=110)
    if psd and psd[0]:
        fig, ax = plt.subplots(figsize=(6, 4))
        ax.semilogx(psd[0], psd[1], "o-")
        ax.set_xlabel("sieve size (mm)")
        ax.set_ylabel("cumulative passing (%)")
        ax.grid(True, which="both", alpha=0.3)
        fig.tight_layout()
        fig.savefig(os.path.join(a.out, "psd.png"), dpi=110)
    if fmap and fmap[2]:
        rings, sectors, f = fmap
        grid = [[f[r * sectors + s] * 1e-3 for s in range(sectors)] for r in range(rings)]
        fig, ax = plt.subplots(figsize=(6, 6))
        im = ax.imshow(grid, aspect="auto", cmap="viridis")
        ax.set_xlabel("sector")
        ax.set_ylabel("ring (top to bottom)")
        ax.set_xticks(range(sectors), [str(k + 1) for k in range(sectors)])
        ax.set_yticks(range(rings), [str(k + 1) for k in range(rings)])
        ax.set_title("concave crushing force, areas P_{ring,sector}")
        fig.colorbar(im, label="mean normal force (kN)")
        fig.savefig(os.path.join(a.out, "concave_forces.png"), dpi=110)
    if a.summary and os.path.exists(a.summary):
        json.load(open(a.summary))  # validates that the summary is readable JSON


if __name__ == "__main__":
    main()
