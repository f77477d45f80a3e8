#!/usr/bin/python3
"""How full the crushing chamber is, band by band in height, from a coupled run's bag.

Usage: scripts/bed_profile.py CONFIG.yaml RUN.bag [--band-mm 50]

Reads the last /crusher/particles message (SPHERE_LIST markers, world frame) and the liner profiles of
CONFIG (mbd.chamber, liner frames with the origin at O1; the liners' few-mm motion is ignored) and prints,
per horizontal band: the particle count, the mean sphere diameter, and the volume fraction of spheres in
the annulus between the straight-line liner profiles. Marker radii are binned, so volumes are approximate.
A packed bed of rock is at 0.5-0.6; the paper's rocks are packed at 0.82 inside (section 2.4.1).
"""
import argparse
import math
import sys

import numpy as np
import config_yaml
from bag_tools import open_bag


def radius_at(zs, rs, z):
    """Liner radius at height z (m) on the piecewise-linear profile, None outside it."""
    pts = sorted(zip(zs, rs))
    for (z0, r0), (z1, r1) in zip(pts, pts[1:]):
        if z0 <= z <= z1:
            return r0 + (r1 - r0) * (z - z0) / (z1 - z0)
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("config")
    ap.add_argument("bag")
    ap.add_argument("--band-mm", type=float, default=50.0)
    a = ap.parse_args()
    try:
        ch = config_yaml.load(a.config)["mbd"]["chamber"]
        mz = [v / 1e3 for v in ch["mantle_z_mm"]]
        mr = [v / 1e3 for v in ch["mantle_r_mm"]]
        cz = [v / 1e3 for v in ch["concave_z_mm"]]
        cr = [v / 1e3 for v in ch["concave_r_mm"]]
    except (OSError, KeyError, TypeError, ValueError) as e:
        sys.exit(f"bed_profile: {a.config}: no mbd.chamber.{{mantle,concave}}_{{z,r}}_mm ({e})")
    last = None
    with open_bag(a.bag, "bed_profile") as b:
        for _, msg, _ in b.read_messages(topics=["/crusher/particles"]):
            last = msg
    if last is None:
        sys.exit(f"bed_profile: {a.bag} has no /crusher/particles message")
    z, r = [], []
    for m in last.markers:
        if m.type != 7:  # SPHERE_LIST
            continue
        for p in m.points:
            z.append(p.z)
            r.append(m.scale.x / 2)
    z, r = np.array(z), np.array(r)
    vol = 4.0 / 3.0 * math.pi * r**3
    h = a.band_mm / 1e3
    print(f"{len(z)} particles; bands of {a.band_mm:.0f} mm; volume fraction between the liners")
    print("   z from    z to  particles  mean d (mm)  volume fraction")
    top = max(cz) + h
    for k in range(int(math.ceil((top - min(cz)) / h)) + 1):
        z1 = top - k * h
        z0 = z1 - h
        sel = (z > z0) & (z <= z1)
        zm = 0.5 * (z0 + z1)
        rc, rm = radius_at(cz, cr, zm), radius_at(mz, mr, zm)
        if rc is None:
            frac = "-"
        else:
            ann = math.pi * (rc**2 - (rm or 0.0) ** 2) * h
            frac = f"{vol[sel].sum() / ann:.3f}"
        d = f"{2e3 * r[sel].mean():.1f}" if sel.any() else "-"
        print(f"{z0:9.3f} {z1:7.3f} {int(sel.sum()):10d} {d:>12} {frac:>16}")


if __name__ == "__main__":
    main()
