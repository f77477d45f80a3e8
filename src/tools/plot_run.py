#!/usr/bin/env python3
"""Plots of one run from its bag: test-point displacement x/y/z and drive power vs time with the plant's Table 5
values, the product size distribution with its P80 and the product index, the concave force map and the force on
the areas P31..P111 over the last second (the paper's Figure 21), a mantle point's path (Figure 19) and the tracked
particles' paths of a coupled run (Figure 20, plot_paths.py). Titles name the config and the drive speed."""
import argparse
import itertools
import json
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import genpy  # noqa: E402
import rosbag  # noqa: E402
from plot_paths import MANTLE_PATH_S, mantle_path, particle_paths  # noqa: E402
from print_summary import PAPER  # noqa: E402  Table 5

FIG21_RINGS = (3, 5, 7, 9, 11)  # areas P31, P51, P71, P91, P111 (section 4.2.3)


def run_label(summary):
    """(title suffix, Table 5 row of the speed within 5 rpm or None) from summary.json."""
    if not summary:
        return "", None
    rpm = summary.get("drive_speed_rad_s", {}).get("mean") or 0.0
    rpm *= 60 / (2 * 3.141592653589793)
    name = os.path.basename(summary.get("config", "") or "")
    ref = next((PAPER[r] for r in PAPER if abs(r - rpm) <= 5), None)
    return f" ({name}, {rpm:.0f} rpm)" if rpm > 0 else f" ({name})", ref


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bag", required=True, action="append",
                    help="run.bag (coupled runs: holds the DEM's topics too); repeat to read node bags that were not merged")
    ap.add_argument("--summary")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    t, d, tp, p = [], [], [], []
    psd, fmap = None, None
    maps, map_t = [], []
    liners = []
    for path in a.bag:
        with rosbag.Bag(path) as bag:
            # the liners (large markers) only where mantle_path uses them: the first (its points) and the last seconds
            tail = bag.get_end_time() - MANTLE_PATH_S - 0.5 if bag.get_message_count("/crusher/liners") else 0.0
            first = next(bag.read_messages(topics=["/crusher/liners"]), None) if tail > bag.get_start_time() else None
            if first and first[2].to_sec() >= tail:
                first = None  # (it is in the tail)
            for topic, m, _ in itertools.chain(
                    [first] if first else [],
                    bag.read_messages(topics=["/crusher/test_point", "/crusher/drive", "/crusher/product",
                                              "/crusher/concave_forces"]),
                    bag.read_messages(topics=["/crusher/liners"],
                                      start_time=genpy.Time.from_sec(max(tail, bag.get_start_time())))):
                if topic == "/crusher/test_point":
                    t.append(m.header.stamp.to_sec())
                    d.append((m.displacement.x * 1e3, m.displacement.y * 1e3, m.displacement.z * 1e3))
                elif topic == "/crusher/drive":
                    tp.append(m.header.stamp.to_sec())
                    p.append(m.power * 1e-3)
                elif topic == "/crusher/liners":
                    mk = next((k for k in m.markers if k.ns == "mantle"), None)
                    if mk:
                        o, q = mk.pose.position, mk.pose.orientation
                        pts = [(v.x, v.y, v.z) for v in mk.points] if not liners else None
                        liners.append((mk.header.stamp.to_sec(), ((o.x, o.y, o.z), (q.x, q.y, q.z, q.w)), pts))
                elif topic == "/crusher/product":
                    psd = (list(m.sieve_mm), list(m.passing_pct))
                else:
                    maps.append((m.rings, m.sectors, m.window_s, list(m.mean_normal_force)))
                    map_t.append(m.header.stamp.to_sec())
    summary = json.load(open(a.summary)) if a.summary and os.path.exists(a.summary) else None
    label, ref = run_label(summary)
    if maps:  # time-weighted mean over the run of the windowed means
        rings, sectors = maps[-1][0], maps[-1][1]
        wsum = sum(w for _, _, w, _ in maps) or 1.0
        fmap = (rings, sectors, [sum(w * f[k] for _, _, w, f in maps) / wsum for k in range(rings * sectors)])
    if t:
        fig, ax = plt.subplots(3, 1, sharex=True, figsize=(8, 6))
        for i, name in enumerate("xyz"):
            ax[i].plot(t, [v[i] for v in d], lw=0.8)
            ax[i].set_ylabel(f"{name} (mm)")
        if ref:  # the plant's amplitude in x (half peak-to-peak) about the run's mean x
            x0 = sum(v[0] for v in d) / len(d)
            for sign in (1, -1):
                ax[0].axhline(x0 + sign * ref["amp"][0], color="k", ls="--", lw=0.8,
                              label="plant amplitude (Table 5)" if sign > 0 else None)
            ax[0].legend(loc="upper right", fontsize=8)
        ax[2].set_xlabel("time (s)")
        fig.suptitle("test-point displacement" + label)
        fig.savefig(os.path.join(a.out, "displacement.png"), dpi=110)
    if tp:
        fig, ax = plt.subplots(figsize=(8, 3.5))
        ax.plot(tp, p, lw=0.8, label="drive power")
        if summary and summary.get("power_kW", {}).get("mean") is not None:
            ax.axhline(summary["power_kW"]["mean"], color="C1", lw=1, label="run mean (after settle)")
        if ref:
            ax.axhline(ref["power"][0], color="k", ls="--", lw=1, label="plant (Table 5)")
        ax.set_xlabel("time (s)")
        ax.set_ylabel("drive power (kW)")
        ax.set_title("drive power" + label)
        ax.legend(loc="lower right", fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(a.out, "power.png"), dpi=110)
    if summary and summary.get("psd"):  # the product of the summary's window, as its P80 (the bag's is since t = 0)
        psd = (summary["psd"]["sieve_mm"], summary["psd"]["passing_pct"])
    if psd and psd[0]:
        fig, ax = plt.subplots(figsize=(6, 4))
        ax.semilogx(psd[0], psd[1], "o-", label="product")
        p80 = summary.get("p80_mm") if summary else None
        if p80:
            ax.axvline(p80, color="C1", lw=1, label=f"P80 {p80:.1f} mm")
        ax.plot([12, 1], [80, 3], "kv", label="product index: > 80 % at 12 mm, < 3 % at 1 mm")
        ax.set_xlabel("sieve size (mm)")
        ax.set_ylabel("cumulative passing (%)")
        ax.set_title("product" + label)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(loc="upper left", fontsize=8)
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
        ax.set_title("concave crushing force, areas P_{ring,sector}" + label)
        fig.colorbar(im, label="mean normal force (kN)")
        fig.savefig(os.path.join(a.out, "concave_forces.png"), dpi=110)
    if maps and maps[-1][0] >= max(FIG21_RINGS):  # Figure 21: F_n on P31..P111 over the last second
        sectors = maps[-1][1]
        last = [(tm, m) for tm, m in zip(map_t, maps) if tm >= map_t[-1] - 1.0]
        fig, ax = plt.subplots(figsize=(8, 3.5))
        for ring in FIG21_RINGS:
            ax.plot([tm for tm, _ in last], [m[3][(ring - 1) * sectors] * 1e-3 for _, m in last], lw=1,
                    label=f"P{ring}1")
        ax.set_xlabel("time (s)")
        ax.set_ylabel("normal force (kN)")
        ax.set_title("crushing force on the areas P31..P111 (Figure 21)" + label)
        ax.legend(fontsize=8, ncol=5)
        fig.tight_layout()
        fig.savefig(os.path.join(a.out, "force_history.png"), dpi=110)
    mantle_path(liners, a.out, label)
    particle_paths(os.path.join(a.out, "trajectories.csv"), a.out, label)


if __name__ == "__main__":
    main()
