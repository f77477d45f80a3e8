#!/usr/bin/env python3
"""Prints a run's summary.json as a Table-5-style table next to the paper's figures."""
import json
import sys

PAPER = {  # Table 5 of Cheng et al. (2020): EXP and SIM, 400 and 600 rpm
    400: {"amp": (5.46, 5.25), "power": (76.8, 73.8), "tph": (80.8, 84.4), "se": (0.95, 0.87)},
    600: {"amp": (5.74, 5.57), "power": (146.2, 128.7), "tph": (51.8, 63.7), "se": (2.82, 2.02)},
}


STEADY_CYCLES = 20  # fewer whole drive cycles after the settle: the figures are marked "not steady"


def fmt(v, nd=2, mark=""):
    return "n/a" if v is None else f"{v:.{nd}f}{mark}"


def main(path):
    s = json.load(open(path))
    # cycle statistics of a run too short for one whole drive cycle after the settle are not zeros: n/a
    cycles = s["power_kW"].get("cycles", 1)

    def cyc(stat):
        return stat if cycles > 0 else None

    rpm = (s.get("drive_speed_rad_s", {}).get("mean") or 0) * 60 / (2 * 3.141592653589793)
    ref = PAPER.get(min(PAPER, key=lambda r: abs(r - rpm))) if rpm > 0 else None
    psd = s.get("psd")
    rows = [
        ("amplitude x, mean (mm)", cyc(s["amplitude_x_mm"]["mean"]), "amp"),
        ("amplitude x, std (mm)", cyc(s["amplitude_x_mm"]["std"]), None),
        ("amplitude y, mean (mm)", cyc(s["amplitude_y_mm"]["mean"]), None),
        ("amplitude z, mean (mm)", cyc(s["amplitude_z_mm"]["mean"]), None),
        ("power draw, mean (kW)", cyc(s["power_kW"]["mean"]), "power"),
        ("power draw, std (kW)", cyc(s["power_kW"]["std"]), None),
        ("throughput (t/h)", s.get("throughput_tph"), "tph"),
        ("specific energy (kWh/t)", cyc(s.get("specific_energy_kWh_per_t")), "se"),
    ]
    drive = f"{rpm:.0f} rpm" if cycles > 0 else "n/a"
    print(f"\nRun summary ({s.get('config', '')}, load {s.get('load', '')}, drive {drive}, "
          f"{s['simulated_s']:.2f} s simulated in {s['wall_s']:.1f} s)")
    mark = " *" if 0 < cycles < STEADY_CYCLES or (cycles == 0 and s.get("throughput_tph") is not None) else ""
    if cycles == 0:
        print("no whole drive cycle after the settle yet: amplitude, power and specific energy are n/a")
    if mark:
        print(f"* not steady: {cycles} whole drive cycle(s) after the settle, fewer than {STEADY_CYCLES}; "
              "run longer (--duration) for figures to compare with the plant")
    head = "EXP / paper SIM" + (f" ({min(PAPER, key=lambda r: abs(r - rpm))} rpm)" if ref else "")
    print(f"{'quantity':<28}{'this run':>12}   {head}")
    for name, v, key in rows:
        paper = f"{ref[key][0]} / {ref[key][1]}" if (ref and key) else ""
        print(f"{name:<28}{fmt(v, mark=mark if v is not None else ''):>12}   {paper}")
    if psd:  # summary.json's own figures (run_metrics: P80 interpolated between sieves), not recomputed here
        print(f"{'P80 (mm)':<28}{fmt(s.get('p80_mm'), mark=mark):>12}")
        print(f"{'passing 12 mm (%)':<28}{fmt(s.get('passing_12mm_pct'), mark=mark):>12}   index: > 80")
        print(f"{'passing 1 mm (%)':<28}{fmt(s.get('passing_1mm_pct'), mark=mark):>12}   index: < 3")

if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: print_summary.py summary.json")
    main(sys.argv[1])
