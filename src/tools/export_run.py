#!/usr/bin/env python3
"""crusher export: a run's bag as spreadsheet CSV files and ParaView (VTK XML) files.

  export_run.py RUN.bag --csv DIR [--delimiter D] [--decimal C] | --vtk DIR   (or both)

t_s: seconds since the earliest header stamp of the exported topics.

CSV (plant units): test_point.csv (t_s, x_mm y_mm z_mm, vx_mm_s.., ax_m_s2..), drive.csv (t_s, speed_rpm,
torque_kNm, power_kW[, nutation_deg, mantle_spin_deg]), product.csv (t_s, throughput_tph, masses in kg,
passing_<sieve>mm_pct per sieve), concave_forces.csv (t_s, window_s, P<ring>_<sector>_kN per area).
VTK (SI units): particles.pvd + particles/particles_NNNNNN.vtp (points with radius, fragment, velocity, force,
from /crusher/particle_state), and per liner in /crusher/liners (mantle, concave, ...) NAME.pvd + NAME/NAME_NNNNNN.vtp.
Exit status: 0 done, 2 bad arguments or a bag that cannot be read."""
import argparse
import os
import sys
from xml.sax.saxutils import quoteattr

import numpy as np

TOPICS = {"test_point": "/crusher/test_point", "drive": "/crusher/drive", "product": "/crusher/product",
          "concave_forces": "/crusher/concave_forces", "particles": "/crusher/particle_state",
          "liners": "/crusher/liners"}
RAD_S_TO_RPM = 60.0 / (2.0 * np.pi)
MASSES = ("mass_discharged_kg", "mass_fed_kg", "mass_in_chamber_kg", "mass_crushed_kg", "mass_fines_bed_kg",
          "mass_lost_kg")


class ExportError(Exception):
    pass


def stamp_ns(msg):
    return msg.header.stamp.to_nsec()


# ---------------------------------------------------------------- CSV

def csv_tables(bag, origin_ns):
    """{name: (header, rows)} for each CSV topic in the bag; rows are lists of floats."""
    tables = {}
    tp = []
    for _, m, _ in bag.read_messages(topics=[TOPICS["test_point"]]):
        d, v, a = m.displacement, m.velocity, m.acceleration
        tp.append([t_s(m, origin_ns), d.x * 1e3, d.y * 1e3, d.z * 1e3, v.x * 1e3, v.y * 1e3, v.z * 1e3,
                   a.x, a.y, a.z])
    if tp:
        tables["test_point"] = (["t_s", "x_mm", "y_mm", "z_mm", "vx_mm_s", "vy_mm_s", "vz_mm_s",
                                 "ax_m_s2", "ay_m_s2", "az_m_s2"], tp)
    dr, extra = [], None
    for _, m, _ in bag.read_messages(topics=[TOPICS["drive"]]):
        if extra is None:  # older bags' DriveState lacks the nutation and spin
            extra = [f for f in ("nutation_angle", "mantle_spin") if hasattr(m, f)]
        dr.append([t_s(m, origin_ns), m.speed * RAD_S_TO_RPM, m.torque * 1e-3, m.power * 1e-3] +
                  [np.degrees(getattr(m, f)) for f in extra])
    if dr:
        names = {"nutation_angle": "nutation_deg", "mantle_spin": "mantle_spin_deg"}
        tables["drive"] = (["t_s", "speed_rpm", "torque_kNm", "power_kW"] + [names[f] for f in extra], dr)
    pr, sieves, masses = [], None, None
    for _, m, _ in bag.read_messages(topics=[TOPICS["product"]]):
        if sieves is None:
            sieves, masses = list(m.sieve_mm), [f for f in MASSES if hasattr(m, f)]
        if list(m.sieve_mm) != sieves or len(m.passing_pct) != len(sieves):
            raise ExportError(f"{TOPICS['product']} at t = {t_s(m, origin_ns)} s has sieves {list(m.sieve_mm)} "
                              f"({len(m.passing_pct)} passing values), the first message {sieves}: one column per "
                              f"sieve needs the same sieves in every message")
        pr.append([t_s(m, origin_ns), m.throughput_tph] + [getattr(m, f) for f in masses] + list(m.passing_pct))
    if pr:
        tables["product"] = (["t_s", "throughput_tph"] + masses + [f"passing_{s:g}mm_pct" for s in sieves], pr)
    fm, shape = [], None
    for _, m, _ in bag.read_messages(topics=[TOPICS["concave_forces"]]):
        if shape is None:
            shape = (m.rings, m.sectors)
        if (m.rings, m.sectors) != shape or len(m.mean_normal_force) != shape[0] * shape[1]:
            raise ExportError(f"{TOPICS['concave_forces']} at t = {t_s(m, origin_ns)} s has {m.rings} x {m.sectors} "
                              f"areas and {len(m.mean_normal_force)} forces; the first message {shape[0]} x {shape[1]}")
        fm.append([t_s(m, origin_ns), m.window_s] + [f * 1e-3 for f in m.mean_normal_force])
    if fm:  # area P_{ring,sector} numbered from 1 as in the paper (section 4.2.3)
        tables["concave_forces"] = (["t_s", "window_s"] + [f"P{r + 1}_{s + 1}_kN" for r in range(shape[0])
                                                           for s in range(shape[1])], fm)
    return tables


def t_s(msg, origin_ns):
    return (stamp_ns(msg) - origin_ns) * 1e-9


def fmt(x, decimal):
    s = "%.12g" % x
    return s.replace(".", ",") if decimal == "," else s


def write_csv(path, header, rows, delimiter, decimal):
    with open(path, "w") as f:
        f.write(delimiter.join(header) + "\n")
        for r in rows:
            f.write(delimiter.join(fmt(x, decimal) for x in r) + "\n")


# ---------------------------------------------------------------- VTK

PC2_TYPES = {1: "i1", 2: "u1", 3: "i2", 4: "u2", 5: "i4", 6: "u4", 7: "f4", 8: "f8"}
CLOUD_FIELDS = ("x", "y", "z", "radius", "fragment", "vx", "vy", "vz", "fx", "fy", "fz")


def cloud_arrays(m):
    """PointCloud2 -> {field: 1-D array}."""
    fields = {f.name: f for f in m.fields}
    missing = [n for n in CLOUD_FIELDS if n not in fields]
    if missing:
        raise ExportError(f"{TOPICS['particles']} lacks the fields {missing} (has {sorted(fields)})")
    order = ">" if m.is_bigendian else "<"
    dt = np.dtype({"names": list(CLOUD_FIELDS),
                   "formats": [order + PC2_TYPES[fields[n].datatype] for n in CLOUD_FIELDS],
                   "offsets": [fields[n].offset for n in CLOUD_FIELDS], "itemsize": m.point_step})
    n = m.width * m.height
    if len(m.data) < n * m.point_step:
        raise ExportError(f"{TOPICS['particles']} at stamp {m.header.stamp.to_sec()} holds {len(m.data)} bytes "
                          f"for {n} points of {m.point_step} bytes")
    rec = np.frombuffer(bytes(m.data[:n * m.point_step]), dtype=dt, count=n)
    return {k: rec[k] for k in CLOUD_FIELDS}


def data_array(name, values, vtype, components=1):
    fmt_ = "%d" if vtype.startswith("Int") else "%.9g"  # 9 digits: a float32 read back exactly
    flat = np.asarray(values).reshape(-1)
    text = " ".join(fmt_ % v for v in flat.tolist())
    comp = f' NumberOfComponents="{components}"' if components > 1 else ""
    nm = f" Name={quoteattr(name)}" if name else ""
    return f'<DataArray type="{vtype}"{nm}{comp} format="ascii">{text}</DataArray>\n'


def write_vtp(path, points, point_data=(), verts=False, triangles=None):
    """points: (n, 3); point_data: [(name, array, vtype, components)]; verts: one vertex cell per point;
    triangles: (m, 3) point indices."""
    n = len(points)
    nv = n if verts else 0
    nt = 0 if triangles is None else len(triangles)
    with open(path, "w") as f:
        f.write('<?xml version="1.0"?>\n<VTKFile type="PolyData" version="0.1" byte_order="LittleEndian">\n'
                f'<PolyData>\n<Piece NumberOfPoints="{n}" NumberOfVerts="{nv}" NumberOfLines="0" '
                f'NumberOfStrips="0" NumberOfPolys="{nt}">\n<Points>\n')
        f.write(data_array("", points, "Float32", 3))
        f.write("</Points>\n")
        if point_data:
            f.write('<PointData Scalars="radius" Vectors="velocity">\n')
            for name, arr, vtype, comp in point_data:
                f.write(data_array(name, arr, vtype, comp))
            f.write("</PointData>\n")
        if verts:
            f.write("<Verts>\n" + data_array("connectivity", np.arange(n), "Int32") +
                    data_array("offsets", np.arange(1, n + 1), "Int32") + "</Verts>\n")
        if nt:
            f.write("<Polys>\n" + data_array("connectivity", triangles, "Int32") +
                    data_array("offsets", 3 * np.arange(1, nt + 1), "Int32") + "</Polys>\n")
        f.write("</Piece>\n</PolyData>\n</VTKFile>\n")


def write_pvd(path, entries):
    """entries: [(time_s, file relative to the .pvd)]."""
    with open(path, "w") as f:
        f.write('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">\n'
                "<Collection>\n")
        for t, rel in entries:
            f.write(f'<DataSet timestep="{t:.12g}" group="" part="0" file={quoteattr(rel)}/>\n')
        f.write("</Collection>\n</VTKFile>\n")


def export_vtk(bag, origin_ns, out, say):
    counts = {}
    series = {}
    topics = bag.get_type_and_topic_info().topics
    if TOPICS["particles"] in topics:
        os.makedirs(os.path.join(out, "particles"), exist_ok=True)
        entries = []
        for k, (_, m, _) in enumerate(bag.read_messages(topics=[TOPICS["particles"]])):
            a = cloud_arrays(m)
            rel = f"particles/particles_{k:06d}.vtp"
            write_vtp(os.path.join(out, rel), np.column_stack([a["x"], a["y"], a["z"]]), [
                ("radius", a["radius"], "Float32", 1),
                ("fragment", a["fragment"].astype(np.int64), "Int32", 1),
                ("velocity", np.column_stack([a["vx"], a["vy"], a["vz"]]), "Float32", 3),
                ("force", np.column_stack([a["fx"], a["fy"], a["fz"]]), "Float32", 3)], verts=True)
            entries.append((t_s(m, origin_ns), rel))
        write_pvd(os.path.join(out, "particles.pvd"), entries)
        counts["particles"] = len(entries)
    else:
        say(f"{TOPICS['particles']} not in the bag: no particle files (a coupled run's dem_node records it)")
    if TOPICS["liners"] in topics:
        for k, (_, m, _) in enumerate(bag.read_messages(topics=[TOPICS["liners"]])):
            for mk in m.markers:
                if mk.type != 11 or not mk.points:  # TRIANGLE_LIST
                    continue
                name = "".join(c if c.isalnum() or c in "_-" else "_" for c in (mk.ns or f"liner{mk.id}"))
                p = np.array([[q.x, q.y, q.z] for q in mk.points], dtype=np.float64)
                pts, inv = np.unique(p, axis=0, return_inverse=True)  # shared vertices once
                os.makedirs(os.path.join(out, name), exist_ok=True)
                rel = f"{name}/{name}_{k:06d}.vtp"
                write_vtp(os.path.join(out, rel), pts, triangles=inv.reshape(-1, 3))
                series.setdefault(name, []).append(((mk.header.stamp.to_nsec() - origin_ns) * 1e-9, rel))
        for name, entries in series.items():
            write_pvd(os.path.join(out, name + ".pvd"), entries)
            counts[name] = len(entries)
        if not series:
            say(f"{TOPICS['liners']} holds no triangles: no liner files")
    else:
        say(f"{TOPICS['liners']} not in the bag: no liner files")
    return counts


# ---------------------------------------------------------------- main

def origin_of(bag):
    """Earliest header stamp over the first message of each exported topic (ns); None when there is none."""
    firsts = []
    have = bag.get_type_and_topic_info().topics
    for topic in TOPICS.values():
        if topic not in have:
            continue
        for _, m, _ in bag.read_messages(topics=[topic]):
            stamps = [mk.header.stamp.to_nsec() for mk in m.markers] if hasattr(m, "markers") else [stamp_ns(m)]
            firsts += stamps
            break
    return min(firsts) if firsts else None


def parse_args(argv):
    ap = argparse.ArgumentParser(prog="crusher export", description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog=__doc__.split("\n\n", 2)[2])
    ap.add_argument("bag", metavar="RUN.bag")
    ap.add_argument("--csv", metavar="DIR", help="write spreadsheet CSV files into DIR")
    ap.add_argument("--vtk", metavar="DIR", help="write ParaView .vtp/.pvd files into DIR")
    ap.add_argument("--delimiter", default=",", help="CSV field separator: ',' (default), ';', 'tab' or '|'")
    ap.add_argument("--decimal", default=".", help="decimal mark: '.' (default) or ','")
    a = ap.parse_args(argv)
    if not a.csv and not a.vtk:
        ap.error("give --csv DIR or --vtk DIR (or both)")
    if a.delimiter in ("tab", "\\t"):
        a.delimiter = "\t"
    if a.delimiter not in (",", ";", "\t", "|"):
        ap.error(f"--delimiter {a.delimiter!r} not accepted (accepted: ',', ';', 'tab', '|')")
    if a.decimal not in (".", ","):
        ap.error(f"--decimal {a.decimal!r} not accepted (accepted: '.', ',')")
    if a.decimal == a.delimiter:
        ap.error(f"--decimal {a.decimal!r} is also the delimiter: with a decimal comma use --delimiter ';'")
    if (a.delimiter != "," or a.decimal != ".") and not a.csv:
        ap.error("--delimiter and --decimal apply to --csv DIR only")
    return a


def main(argv):
    a = parse_args(argv)

    def say(line):
        print(f"export: {line}")

    import rosbag  # after the arguments: --help works without ROS on the path
    if not os.path.isfile(a.bag):
        print(f"export: {a.bag}: no such file", file=sys.stderr)
        return 2
    try:
        bag = rosbag.Bag(a.bag)
    except Exception as e:  # rosbag raises ROSBagException, ROSBagFormatException, ValueError, ...
        hint = "; not closed (a node killed?): `rosbag reindex` may repair it" if "Unindexed" in type(e).__name__ else ""
        print(f"export: {a.bag} cannot be read as a bag ({type(e).__name__}: {e}{hint})", file=sys.stderr)
        return 2
    try:
        with bag:
            origin = origin_of(bag)
            if origin is None:
                say(f"{a.bag} holds none of {sorted(TOPICS.values())}: nothing to export")
            if a.csv:
                os.makedirs(a.csv, exist_ok=True)
                tables = csv_tables(bag, origin or 0)
                for name in ("test_point", "drive", "product", "concave_forces"):
                    if name not in tables:
                        say(f"{TOPICS[name]} not in the bag: {name}.csv skipped")
                        continue
                    header, rows = tables[name]
                    path = os.path.join(a.csv, name + ".csv")
                    write_csv(path, header, rows, a.delimiter, a.decimal)
                    say(f"{path}: {len(rows)} rows, {len(header)} columns")
            if a.vtk:
                os.makedirs(a.vtk, exist_ok=True)
                for name, n in export_vtk(bag, origin or 0, a.vtk, say).items():
                    say(f"{os.path.join(a.vtk, name + '.pvd')}: {n} time steps")
    except ExportError as e:
        print(f"export: {a.bag}: {e}", file=sys.stderr)
        return 2
    except Exception as e:  # a bag cut short (node killed) fails while reading its messages
        if type(e).__module__.startswith("rosbag") or isinstance(e, (EOFError, ValueError)):
            print(f"export: {a.bag} cannot be read as a bag ({type(e).__name__}: {e})", file=sys.stderr)
            return 2
        raise
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
