#!/usr/bin/env python3
"""A sweep's figures in the form of the paper's Figures 22-24 and its section 4.3 trends, checked.
Usage: plot_sweep.py DIR (a `crusher sweep` output: DIR/sweep.csv, DIR/cases/NAME/summary.json).
The paper's panels: (a) against the drive speed at the fixed-cone mass of the plant (24 t), (b) against the mass at
600 rpm; here the grid's values nearest to those, the other slices drawn thin. The plant's Table 5 points (400 and
600 rpm at 24.1 t) are marked; the plant's size distribution is not in the paper's text: its product index is."""
import csv
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from print_summary import PAPER  # noqa: E402  Table 5: {rpm: {key: (EXP, SIM)}}

SPEED, MASS = "mbd.drive.speed_rpm", "mbd.fixed_cone.mass_kg"
PLANT_MASS_KG = 24124.4  # Table 1
SLICE = {MASS: PLANT_MASS_KG, SPEED: 600.0}  # the paper's: (a) at 24 t, (b) at 600 rpm


def label(key):
    return {SPEED: "drive speed (rpm)", MASS: "fixed-cone mass (t)"}.get(key, key)


def shown(key, v):
    return np.asarray(v) / 1000.0 if key == MASS else np.asarray(v)


def read(out):
    with open(os.path.join(out, "sweep.csv")) as f:
        rows = [r for r in csv.DictReader(f) if r["status"] == "ok"]
    for r in rows:
        s = json.load(open(os.path.join(out, "cases", r["case"], "summary.json")))
        r["psd"] = s.get("psd")
        for k, v in list(r.items()):
            if isinstance(v, str) and k not in ("status", "case"):
                r[k] = float(v) if v != "" else np.nan
    return rows


def slices(rows, x, other):
    """{other's value: (x values, rows)} sorted by x, and the paper's slice (the value nearest SLICE)."""
    if other is None:
        return {None: sorted(rows, key=lambda r: r[x])}, None
    groups = {}
    for r in rows:
        groups.setdefault(r[other], []).append(r)
    groups = {k: sorted(g, key=lambda r: r[x]) for k, g in sorted(groups.items())}
    vals = list(groups)
    want = SLICE.get(other, vals[len(vals) // 2])
    return groups, min(vals, key=lambda v: abs(v - want))


def other_of(keys, x):
    rest = [k for k in keys if k != x]
    return rest[0] if rest else None


def slice_label(other, v):
    if other is None:
        return "sweep"
    return f"{shown(other, v):g} {'t' if other == MASS else 'rpm' if other == SPEED else other}"


def plant_points(ax, x, quantity):
    """Table 5 EXP at 400 and 600 rpm (fixed cone 24.1 t) where the x axis is speed or mass."""
    if x not in (SPEED, MASS):
        return
    for rpm, marker in ((400, "s"), (600, "D")):
        xv = rpm if x == SPEED else PLANT_MASS_KG / 1000
        ax.plot([xv], [PAPER[rpm][quantity][0]], marker, color="red", ms=8, mfc="none", mew=2,
                label=f"plant {rpm} rpm, 24.1 t (Table 5)")


def curve_figure(rows, keys, col, std_col, quantity, ylabel, title, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, len(keys), figsize=(6.5 * len(keys), 4.8), squeeze=False)
    for ax, x, tag in zip(axes[0], keys, "ab"):
        other = other_of(keys, x)
        groups, main = slices(rows, x, other)
        for v, g in groups.items():
            xs, ys = shown(x, [r[x] for r in g]), [r[col] for r in g]
            if v == main:
                err = [r[std_col] for r in g] if std_col else None
                ax.errorbar(xs, ys, yerr=err, fmt="o-", color="black", lw=2, capsize=3, label=slice_label(other, v))
            else:
                ax.plot(xs, ys, "-", lw=0.8, alpha=0.6, label=slice_label(other, v))
        plant_points(ax, x, quantity)
        ax.set_xlabel(label(x))
        ax.set_ylabel(ylabel)
        ax.set_title(f"({tag}) {title} against {label(x).split(' (')[0]}")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def psd_figure(rows, keys, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker
    fig, axes = plt.subplots(1, len(keys), figsize=(6.5 * len(keys), 4.8), squeeze=False)
    for ax, x, tag in zip(axes[0], keys, "ab"):
        other = other_of(keys, x)
        groups, main = slices(rows, x, other)
        g = groups[main]
        colours = plt.cm.viridis(np.linspace(0, 0.9, len(g)))
        for r, c in zip(g, colours):
            if r["psd"]:
                ax.semilogx(r["psd"]["sieve_mm"], r["psd"]["passing_pct"], "-", color=c,
                            label=f"{shown(x, r[x]):g} {'t' if x == MASS else 'rpm' if x == SPEED else ''}")
        ax.plot([12], [80], "^", color="red", ms=9, label="plant index: > 80 % passing 12 mm")
        ax.plot([1], [3], "v", color="red", ms=9, label="plant index: < 3 % passing 1 mm")
        ax.set_xlabel("sieve size (mm)")
        ax.set_ylabel("cumulative passing (%)")
        where = f" at {slice_label(other, main)}" if other else ""
        ax.set_title(f"({tag}) product size per {label(x).split(' (')[0]}{where}")
        ax.xaxis.set_major_formatter(matplotlib.ticker.ScalarFormatter())
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def slope(xs, ys):
    ok = ~np.isnan(ys)
    return np.polyfit(xs[ok], ys[ok], 1)[0] if ok.sum() >= 2 else np.nan


SLIGHT = 0.25  # "slightly": at most 25 % change over the swept range (the plant: +5 % from 400 to 600 rpm)
TRENDS = [  # (x key, column, unit, sign, slight, what the paper says)
    (SPEED, "amplitude_x_mean_mm", "mm", +1, True, "amplitude slightly up with speed (Fig. 22a)"),
    (MASS, "amplitude_x_mean_mm", "mm", -1, False, "amplitude down as the fixed-cone mass rises (Fig. 22b)"),
    (SPEED, "specific_energy_kWh_per_t", "kWh/t", +1, False, "specific energy up with speed (Fig. 24a)"),
    (SPEED, "p80_mm", "mm", -1, False, "product finer with speed: P80 down (Fig. 23a)"),
]


def trends(rows, keys):
    """[(text, verdict)] for the paper's trends whose key was varied: the sign of the least-squares slope on the
    paper's slice (and for "slightly" a change of at most SLIGHT), the change from the first to the last value,
    and in how many of the other slices the direction holds. verdict: holds, FAILS or partly (direction only)."""
    out = []
    for x, col, unit, sign, slight, what in TRENDS:
        if x not in keys:
            continue
        other = other_of(keys, x)
        groups, main = slices(rows, x, other)
        verdict = {}
        for v, g in groups.items():
            xs, ys = np.array([r[x] for r in g]), np.array([r[col] for r in g])
            verdict[v] = (len(g) >= 2 and np.sign(slope(xs, ys)) == sign, xs, ys)
        holds, xs, ys = verdict[main]
        if len(xs) < 2:
            continue
        first, last = ys[0], ys[-1]
        rel = (last - first) / first if first else np.inf
        change = f"{first:.3g} -> {last:.3g} {unit}" + (f" ({rel * 100:+.1f} %)" if first else "")
        text = (f"{what}: {change} over {shown(x, xs[0]):g}-{shown(x, xs[-1]):g} "
                f"{'t' if x == MASS else 'rpm'}{' at ' + slice_label(other, main) if other else ''}")
        if other:
            text += f"; direction holds in {sum(h for h, _, _ in verdict.values())} of {len(verdict)} slices"
        word = "holds" if holds else "FAILS"
        if holds and slight and abs(rel) > SLIGHT:
            word, text = "partly", text + f"; more than slightly (> {SLIGHT * 100:.0f} %)"
        out.append((text, word))
    return out


def report(out, keys):
    rows = read(out)
    if not rows:
        print("[sweep] no case ok: no figures")
        return
    curve_figure(rows, keys, "amplitude_x_mean_mm", "amplitude_x_std_mm", "amp", "amplitude x (mm)",
                 "displacement amplitude", os.path.join(out, "fig22_amplitude.png"))
    psd_figure(rows, keys, os.path.join(out, "fig23_psd.png"))
    curve_figure(rows, keys, "specific_energy_kWh_per_t", None, "se", "specific energy (kWh/t)",
                 "specific energy", os.path.join(out, "fig24_specific_energy.png"))
    print(f"[sweep] figures: {out}/fig22_amplitude.png, fig23_psd.png, fig24_specific_energy.png")
    checks = trends(rows, keys)
    if checks:
        print("[sweep] the paper's trends (section 4.3):")
    for text, word in checks:
        print(f"  {word:<7}{text}")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: plot_sweep.py DIR")
    with open(os.path.join(sys.argv[1], "sweep.csv")) as f:
        header = next(csv.reader(f))
    report(sys.argv[1], header[:header.index("amplitude_x_mean_mm")])
