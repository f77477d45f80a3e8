#!/usr/bin/python3
"""Plots of a piston-die run (written by `piston_die`): pressure-compression loops with the fitted law
(virgin loading p = E s^n and the hysteretic unloading of src/mbd/bed_law.hpp) and the product PSDs.
usage: plot_piston_die.py DIR   (reads DIR/piston_die.csv, DIR/psd.csv, DIR/psd_fit.csv, DIR/flow_material.yaml;
writes DIR/piston_die.png, DIR/psd.png; with --reloads also DIR/piston_die_reloads.png from
DIR/piston_die_reloads.csv and DIR/piston_die_reload_curves.csv)"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import yaml  # noqa: E402


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def loops(out, law):
    rows = read_csv(os.path.join(out, "piston_die.csv"))
    groups = {}
    for r in rows:
        groups.setdefault(r["s_max"], []).append((float(r["s"]), float(r["p_MPa"]), r["phase"]))
    fig, ax = plt.subplots(figsize=(7, 5))
    E, n, reb = law["modulus_MPa"], law["exponent"], law["rebound"]
    for k, (smax, pts) in enumerate(sorted(groups.items(), key=lambda g: float(g[0]))):
        c = "C%d" % k
        s = [p[0] for p in pts]
        p = [p[1] for p in pts]
        ax.plot(s, p, c + "-", lw=1, label="DEM, s_max %s" % smax)
        D = max(s)
        er = D - reb * D
        se = np.linspace(er, D, 50)
        ax.plot(se, E * D ** n * ((se - er) / (reb * D)) ** n, c + ":", lw=1.5)
    sl = np.linspace(0, max(float(g) for g in groups) if groups else 0.3, 100)
    ax.plot(sl, E * sl ** n, "k--", lw=1.5, label="fit p = %.3g s^%.2f MPa, rebound %.3f" % (E, n, reb))
    ax.set_xlabel("compression ratio s = stroke / bed height")
    ax.set_ylabel("piston pressure p (MPa)")
    ax.set_title("Piston-die loading and unloading (dotted: fitted unloading)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "piston_die.png"), dpi=120)
    plt.close(fig)


def psd(out):
    path = os.path.join(out, "psd.csv")
    if not os.path.exists(path):
        return
    fits = {}
    fp = os.path.join(out, "psd_fit.csv")
    if os.path.exists(fp):
        for r in read_csv(fp):
            fits.setdefault(r["s_max"], []).append((float(r["sieve_mm"]), float(r["passing_pct"])))
    groups = {}
    for r in read_csv(path):
        groups.setdefault(r["s_max"], []).append((float(r["sieve_mm"]), float(r["passing_pct"])))
    fig, ax = plt.subplots(figsize=(7, 5))
    for k, (name, pts) in enumerate(groups.items()):
        c = "k" if name == "feed" else "C%d" % (k - 1)
        ax.semilogx([p[0] for p in pts], [p[1] for p in pts], c + "o-", ms=4,
                    label="feed" if name == "feed" else "DEM product, s_max %s" % name)
        if name in fits:
            ax.semilogx([p[0] for p in fits[name]], [p[1] for p in fits[name]], c + ":", lw=1.5)
    ax.set_xlabel("square-mesh sieve size (mm)")
    ax.set_ylabel("cumulative passing (%)")
    ax.set_title("Piston-die product PSDs (dotted: fitted breakage event)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3, which="both")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "psd.png"), dpi=120)
    plt.close(fig)


def reloads(out):
    """Each bed's pressings (the first from the loose pour, then its reloads: pushed down the die first with
    --shift-mm, swept with --sweep), one panel per pouring and s_max, the loop energy of each in its label."""
    curves, table = (os.path.join(out, f) for f in ("piston_die_reload_curves.csv", "piston_die_reloads.csv"))
    if not (os.path.exists(curves) and os.path.exists(table)):
        return
    rows = {(r["pouring"], r["s_max"], r["pressing"]): r for r in read_csv(table)}
    beds = {}
    for r in read_csv(curves):
        beds.setdefault((r["pouring"], r["seed"], r["s_max"]), {}).setdefault(r["pressing"], []).append(
            (float(r["s"]), float(r["p_MPa"])))
    cols = min(3, len(beds))
    rows_n = (len(beds) + cols - 1) // cols
    fig, axes = plt.subplots(rows_n, cols, figsize=(6 * cols, 4.5 * rows_n), squeeze=False)
    for ax in axes.flat[len(beds):]:
        ax.set_visible(False)
    for ax, ((pouring, seed, smax), pressings) in zip(axes.flat, sorted(beds.items())):
        for k, pts in sorted(pressings.items(), key=lambda kv: int(kv[0])):
            r = rows.get((pouring, smax, k), {})
            moved = float(r.get("shift_mm", 0) or 0)
            label = "first" if k == "0" else "reload %s%s" % (k, ", pushed %g mm first" % moved if moved else "")
            label += ": loop %.2f J/kg" % float(r.get("loop_J_kg", "nan"))
            if float(r.get("sweep_J_kg", 0) or 0):
                label += " + %.2f sideways" % float(r["sweep_J_kg"])
            ax.plot([p[0] for p in pts], [p[1] for p in pts], "C%d-" % int(k), lw=1, label=label)
        ax.set_xlabel("compression ratio s (from the loose bed's height)")
        ax.set_ylabel("piston pressure p (MPa)")
        ax.set_title("Seed %s, s_max %s: the same bed pressed again" % (seed, smax))
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "piston_die_reloads.png"), dpi=120)
    plt.close(fig)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    with open(os.path.join(out, "flow_material.yaml")) as f:
        mat = yaml.safe_load(f)["flow_material"]
    loops(out, mat["pressure"])
    psd(out)
    reloads(out)


if __name__ == "__main__":
    main()
