#!/usr/bin/env python3
"""Checks `crusher export` output against the bag it came from (values recomputed here from the messages).
  check_export.py csv RUN.bag DIR [DIR_SEMICOLON_COMMA]   every row equals its message (m -> mm, W -> kW,
      rad/s -> rpm, N -> kN), one row per message; the ';'/',' export parses back to the same numbers
  check_export.py vtk RUN.bag DIR   every /crusher/particle_state message is one .vtp holding each particle with
      its radius, fragment, velocity and force; liners as triangles of the marker points; .pvd lists every file"""
import csv
import math
import os
import sys
import xml.etree.ElementTree as ET

import numpy as np
import rosbag

EXPORTED = ("/crusher/test_point", "/crusher/drive", "/crusher/product", "/crusher/concave_forces",
            "/crusher/particle_state", "/crusher/liners")


def fail(msg):
    print("FAIL:", msg)
    sys.exit(1)


def origin_ns(bag):  # the contract: t_s counts from the earliest header stamp of the exported topics
    have = bag.get_type_and_topic_info().topics
    firsts = []
    for t in EXPORTED:
        if t in have:
            _, m, _ = next(bag.read_messages(topics=[t]))
            firsts += [k.header.stamp.to_nsec() for k in m.markers] if hasattr(m, "markers") else [m.header.stamp.to_nsec()]
    return min(firsts)


def expected_rows(bag, t0):
    """{file: (header, rows)} computed from the messages."""
    out = {}
    ts = lambda m: (m.header.stamp.to_nsec() - t0) * 1e-9
    rows = [[ts(m), m.displacement.x * 1000, m.displacement.y * 1000, m.displacement.z * 1000,
             m.velocity.x * 1000, m.velocity.y * 1000, m.velocity.z * 1000,
             m.acceleration.x, m.acceleration.y, m.acceleration.z]
            for _, m, _ in bag.read_messages(topics=["/crusher/test_point"])]
    out["test_point"] = (["t_s", "x_mm", "y_mm", "z_mm", "vx_mm_s", "vy_mm_s", "vz_mm_s", "ax_m_s2", "ay_m_s2",
                          "az_m_s2"], rows)
    rows = [[ts(m), m.speed * 30 / math.pi, m.torque / 1000, m.power / 1000, math.degrees(m.nutation_angle),
             math.degrees(m.mantle_spin)] for _, m, _ in bag.read_messages(topics=["/crusher/drive"])]
    out["drive"] = (["t_s", "speed_rpm", "torque_kNm", "power_kW", "nutation_deg", "mantle_spin_deg"], rows)
    msgs = [m for _, m, _ in bag.read_messages(topics=["/crusher/product"])]
    masses = ["mass_discharged_kg", "mass_fed_kg", "mass_in_chamber_kg", "mass_crushed_kg", "mass_fines_bed_kg",
              "mass_lost_kg"]
    out["product"] = (["t_s", "throughput_tph"] + masses + ["passing_%gmm_pct" % s for s in msgs[0].sieve_mm],
                      [[ts(m), m.throughput_tph] + [getattr(m, k) for k in masses] + list(m.passing_pct)
                       for m in msgs])
    msgs = [m for _, m, _ in bag.read_messages(topics=["/crusher/concave_forces"])]
    if msgs:
        out["concave_forces"] = (["t_s", "window_s"] + ["P%d_%d_kN" % (r, s) for r in range(1, 14) for s in range(1, 10)],
                                 [[ts(m), m.window_s] + [f / 1000 for f in m.mean_normal_force] for m in msgs])
    return out


def read_csv(path, delimiter=",", decimal="."):
    with open(path, newline="") as f:
        rows = list(csv.reader(f, delimiter=delimiter))
    return rows[0], [[float(v.replace(decimal, ".")) for v in r] for r in rows[1:]], rows[1:]


def check_csv(bag_path, d, d_locale):
    with rosbag.Bag(bag_path) as bag:
        exp = expected_rows(bag, origin_ns(bag))
    if "concave_forces" not in exp and os.path.exists(os.path.join(d, "concave_forces.csv")):
        fail("concave_forces.csv written from a bag without /crusher/concave_forces")
    for name, (header, rows) in exp.items():
        path = os.path.join(d, name + ".csv")
        if not os.path.exists(path):
            fail(f"{path} missing")
        h, got, _ = read_csv(path)
        if h != header:
            fail(f"{name}.csv header {h}, expected {header}")
        if len(got) != len(rows) or not rows:
            fail(f"{name}.csv has {len(got)} rows for {len(rows)} messages")
        for k, (g, e) in enumerate(zip(got, rows)):
            for col, a, b in zip(header, g, e):
                if not math.isclose(a, b, rel_tol=1e-11, abs_tol=1e-12):
                    fail(f"{name}.csv row {k + 1} {col} = {a!r}, the message gives {b!r}")
        if d_locale:
            h2, got2, raw = read_csv(os.path.join(d_locale, name + ".csv"), ";", ",")
            if h2 != header or got2 != got:
                fail(f"{name}.csv with ';' and decimal ',' does not parse back to the same numbers")
            if any("." in v for r in raw for v in r) or not any("," in v for r in raw for v in r):
                fail(f"{name}.csv with --decimal , has decimal points, or no decimal comma at all")
        t = [r[0] for r in got]
        if t[0] < 0 or any(b < a for a, b in zip(t, t[1:])):
            fail(f"{name}.csv: t_s is negative or goes back")
        print(f"{name}.csv: {len(got)} rows x {len(header)} columns equal to the bag's messages")


def arrays(piece, where):
    out = {}
    for da in piece.iter("DataArray"):
        kind = np.int64 if da.get("type").startswith("Int") else np.float32
        vals = np.array((da.text or "").split(), dtype=np.float64).astype(kind)
        out[da.get("Name", "Points")] = vals.reshape(-1, int(da.get("NumberOfComponents", "1")))
    if "Points" not in out:
        fail(f"{where}: no Points")
    return out


def read_pvd(d, name):
    root = ET.parse(os.path.join(d, name + ".pvd")).getroot()
    entries = [(float(e.get("timestep")), e.get("file")) for e in root.iter("DataSet")]
    for _, f in entries:
        if not os.path.isfile(os.path.join(d, f)):
            fail(f"{name}.pvd lists {f}, which is not there")
    return entries


def check_vtk(bag_path, d):
    with rosbag.Bag(bag_path) as bag:
        t0 = origin_ns(bag)
        clouds = [m for _, m, _ in bag.read_messages(topics=["/crusher/particle_state"])]
        markers = {m.markers[0].header.stamp: m for _, m, _ in bag.read_messages(topics=["/crusher/particles"])}
        liners = [m for _, m, _ in bag.read_messages(topics=["/crusher/liners"])]
    if not clouds or not liners:
        fail(f"the bag has {len(clouds)} particle_state and {len(liners)} liner messages")
    entries = read_pvd(d, "particles")
    if len(entries) != len(clouds) or len(set(f for _, f in entries)) != len(clouds):
        fail(f"particles.pvd lists {len(entries)} files for {len(clouds)} /crusher/particle_state messages")
    names = ["x", "y", "z", "radius", "fragment", "vx", "vy", "vz", "fx", "fy", "fz"]
    dt = np.dtype({"names": names, "formats": ["<f4"] * 4 + ["<i4"] + ["<f4"] * 6,
                   "offsets": [4 * k for k in range(11)], "itemsize": 44})
    for (t, f), m in zip(entries, clouds):
        if [(p.name, p.offset) for p in m.fields] != [(n, 4 * k) for k, n in enumerate(names)]:
            fail(f"/crusher/particle_state fields {[(p.name, p.offset) for p in m.fields]}")
        if abs(t - (m.header.stamp.to_nsec() - t0) * 1e-9) > 1e-9:
            fail(f"{f}: timestep {t}, the message's stamp gives {(m.header.stamp.to_nsec() - t0) * 1e-9}")
        c = np.frombuffer(bytes(m.data), dtype=dt)
        if len(c) != m.width or len(c) == 0:
            fail(f"a particle_state message holds {len(c)} points, width {m.width}")
        # The cloud holds every particle of /crusher/particles at the same moment (same centres).
        mk = markers.get(m.header.stamp)
        if mk is None:
            fail(f"no /crusher/particles message at {m.header.stamp.to_sec()} s, where particle_state has one")
        centres = np.array([[p.x, p.y, p.z] for k in mk.markers for p in k.points]).reshape(-1, 3)
        pc = np.column_stack([c["x"], c["y"], c["z"]]).astype(np.float64)
        if len(centres) != len(pc) or np.abs(np.sort(centres, axis=0) - np.sort(pc, axis=0)).max() > 1e-6:
            fail(f"particle_state at {m.header.stamp.to_sec()} s: {len(pc)} particles, the markers {len(centres)} "
                 f"(or other centres)")
        piece = ET.parse(os.path.join(d, f)).getroot().find("PolyData/Piece")
        a = arrays(piece, f)
        n = int(piece.get("NumberOfPoints"))
        if n != len(c) or int(piece.get("NumberOfVerts")) != n or len(a["Points"]) != n:
            fail(f"{f}: {n} points, the message {len(c)}")
        want = {"Points": ("x", "y", "z"), "radius": ("radius",), "fragment": ("fragment",),
                "velocity": ("vx", "vy", "vz"), "force": ("fx", "fy", "fz")}
        for key, cols in want.items():
            if key not in a:
                fail(f"{f}: no point data {key}")
            ref = np.column_stack([c[k] for k in cols])
            if a[key].shape != ref.shape or not np.array_equal(a[key], ref):
                bad = np.argwhere(a[key] != ref)[:1] if a[key].shape == ref.shape else "shape"
                fail(f"{f}: {key} differs from the message (first at {bad})")
        if not np.array_equal(a["offsets"].ravel(), np.arange(1, n + 1)):
            fail(f"{f}: vertex offsets are not one point per cell")
    # What dem_node put in the fields: fragments are rocks of several spheres, each particle moves, forces act.
    c = np.frombuffer(bytes(clouds[0].data), dtype=dt)
    nfrag = len(set(c["fragment"].tolist()))
    if not 1 < nfrag < len(c):
        fail(f"first sample: {nfrag} fragments for {len(c)} particles (rocks of bonded spheres expected)")
    if not (np.abs(c["fz"]).max() > 0 and np.abs(np.column_stack([c["vx"], c["vy"], c["vz"]])).max() > 0):
        fail("first sample: all forces or all velocities are zero")
    if not (c["radius"].min() > 0 and c["radius"].max() < 0.1):
        fail(f"radii {c['radius'].min()}..{c['radius'].max()} m")
    print(f"particles.pvd: {len(entries)} samples, each particle's radius, fragment, velocity and force as in the "
          f"bag ({len(c)} particles in {nfrag} fragments at first)")
    # Liners: each TRIANGLE_LIST marker of each sample is a series of .vtp files with the same triangles.
    series = {}
    for k in liners[0].markers:
        if k.type == 11 and k.points:
            series[k.ns] = read_pvd(d, k.ns)
    if "mantle" not in series or "concave" not in series:
        fail(f"liner series {sorted(series)}: mantle and concave expected")
    for ns, entries in series.items():
        if len(entries) != len(liners):
            fail(f"{ns}.pvd lists {len(entries)} files for {len(liners)} /crusher/liners messages")
        for (t, f), m in zip(entries, liners):
            mk = [k for k in m.markers if k.ns == ns][0]
            piece = ET.parse(os.path.join(d, f)).getroot().find("PolyData/Piece")
            a = arrays(piece, f)
            tri = a["connectivity"].reshape(-1, 3)
            if len(tri) * 3 != len(mk.points) or int(piece.get("NumberOfPolys")) != len(tri):
                fail(f"{f}: {len(tri)} triangles, the marker {len(mk.points) // 3}")
            got = a["Points"][tri.ravel()].astype(np.float64)
            ref = np.array([[p.x, p.y, p.z] for p in mk.points])
            if np.abs(got - ref).max() > 1e-6 * max(1.0, np.abs(ref).max()):
                fail(f"{f}: triangle corners differ from the marker's points")
            if abs(t - (mk.header.stamp.to_nsec() - t0) * 1e-9) > 1e-9:
                fail(f"{f}: timestep {t} is not the marker's stamp")
        print(f"{ns}.pvd: {len(entries)} samples of {len(tri)} triangles as in the bag")


if __name__ == "__main__":
    if len(sys.argv) >= 4 and sys.argv[1] == "csv":
        check_csv(sys.argv[2], sys.argv[3], sys.argv[4] if len(sys.argv) > 4 else None)
    elif len(sys.argv) == 4 and sys.argv[1] == "vtk":
        check_vtk(sys.argv[2], sys.argv[3])
    else:
        sys.exit(__doc__)
