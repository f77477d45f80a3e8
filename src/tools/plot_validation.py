#!/usr/bin/env python3
"""Plots validation.json (src/tools/validate.cpp): Table 5's four headline quantities at 400 and 600 rpm, the
plant (EXP), the paper's simulation (SIM) and ours side by side; calibrated values hatched; with rock_spread (validate
--rock-spread) ours carries 2 jackknife standard errors of the rock's sampling as an error bar."""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(path, png):
    v = json.load(open(path))
    rows = {r["quantity"]: r for r in v["rows"]}
    spread = {r["quantity"]: r for r in v.get("rock_spread", {}).get("std", [])}
    keys = [("amplitude_x_mm_mean", "amplitude x (mm)"), ("power_kW_mean", "power (kW)"),
            ("throughput_tph", "throughput (t/h)"), ("specific_energy_kWh_per_t", "specific energy (kWh/t)")]
    fig, axes = plt.subplots(1, 4, figsize=(14, 3.8))
    for ax, (k, label) in zip(axes, keys):
        r = rows[k]
        for i, rpm in enumerate((400, 600)):
            vals = [r[f"exp{rpm}"], r[f"sim{rpm}"], r[f"ours{rpm}"]]
            for j, (val, name, col) in enumerate(zip(vals, ("plant", "paper SIM", "ours"), ("k", "0.6", "tab:red"))):
                if val is None:
                    continue
                hatch = "//" if name == "ours" and rpm == 400 and r["calibrated400"] else None
                sd = spread.get(k, {}).get(f"std{rpm}") if name == "ours" else None
                ax.bar(i * 4 + j, val, color=col, hatch=hatch, edgecolor="w" if hatch else None,
                       label=name if i == 0 else None, yerr=2 * sd if sd is not None else None, capsize=4)
        ax.set_xticks([1, 5])
        ax.set_xticklabels(["400 rpm", "600 rpm"])
        ax.set_title(label)
    axes[0].legend(fontsize=8)
    bars = f"; bars: 2 standard errors of the rock's sampling ({v['rock_spread']['pourings']} pourings)" if spread else ""
    fig.suptitle(f"Table 5 against the {v['load']} mode (hatched: calibrated at 400 rpm; 600 rpm is a prediction{bars})",
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(png, dpi=110)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
