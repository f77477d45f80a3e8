#!/usr/bin/python3
"""Table-5 figures of a coupled run window by window in time, from its bag: does the run reach a steady state?

Usage: scripts/run_windows.py RUN.bag [--cycles 2]

Windows are whole drive cycles (the power swings within a cycle). Per window: test-point amplitude x (half the
peak-to-peak per drive cycle, averaged over the window's cycles, as summary.json), mean drive power, throughput
(discharged mass over the window / its length), specific energy (power / throughput), and the mass in the chamber
at the window's end (and the part of it held as fines in the flow model, dem.fines: flow). summary.json gives one mean over all the run after run.settle_s, which hides a chamber
still filling up from a pre-filled start (that takes seconds of simulated time). In a coupled run also: the power
the liners put into the rock (minus the work of the DEM's wrenches on the mantle and the concave, each step's
wrench with the mean of the liner's twists at the step's start and end; the drive's power less this is what the
mechanism itself dissipates, mostly in the absorbers), the mean force of the rock on the mantle, and the mantle's
mean nutation (the angle between the mantle's and the concave's axes): how far the rock lets the vibrator swing the
mantle towards the concave (the idle machine, mantle resting on the concave, ~1.67 deg; the calibrated equivalent
bed holds it at ~0.73 deg).
"""
import argparse
import bisect
import math
import sys

from bag_tools import open_bag


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("bag")
    ap.add_argument("--cycles", type=int, default=2, help="drive cycles per window")
    a = ap.parse_args()
    if a.cycles < 1:
        sys.exit(f"run_windows: --cycles must be a whole number >= 1 (got {a.cycles})")
    tx, x, tp, p, speeds, prod = [], [], [], [], [], []
    nutation = []  # (t, deg) per coupling step
    states, wrenches = {}, {}  # coupling step -> (start time, [mantle, concave twist]) / [mantle, concave wrench]
    with open_bag(a.bag, "run_windows") as b:
        topics = ["/crusher/test_point", "/crusher/drive", "/crusher/product", "/crusher/geometry_state",
                  "/crusher/geometry_wrench"]
        for topic, m, _ in b.read_messages(topics=topics):
            t = m.header.stamp.to_sec()
            if topic == "/crusher/geometry_state":
                states[m.step] = (m.time, [twist(m.mantle_twist), twist(m.concave_twist)])
                nutation.append((m.time, angle_deg(axis(m.mantle_pose.orientation), axis(m.concave_pose.orientation))))
            elif topic == "/crusher/geometry_wrench":
                if not m.stopped:
                    wrenches[m.step] = [wrench(m.mantle), wrench(m.concave)]
            elif topic == "/crusher/test_point":
                tx.append(t)
                x.append(m.displacement.x * 1e3)
            elif topic == "/crusher/drive":
                tp.append(t)
                p.append(m.power * 1e-3)
                speeds.append(m.speed)
            else:
                prod.append((t, m.mass_discharged_kg, m.mass_in_chamber_kg, getattr(m, "mass_fines_bed_kg", 0.0)))
    if not tp:
        sys.exit(f"run_windows: {a.bag} has no /crusher/drive message")
    speed = sum(speeds) / len(speeds)  # rad/s
    if not speed > 0:
        sys.exit(f"run_windows: {a.bag}: the drive does not turn (mean speed {speed} rad/s)")
    period = 2 * math.pi / speed
    window = a.cycles * period
    t_end = max(tp[-1], tx[-1] if tx else 0)
    print(f"{a.bag}: {t_end:.2f} s, drive {speed * 60 / (2 * math.pi):.0f} rpm, "
          f"windows of {a.cycles} cycles ({window:.3f} s)")
    rock = rock_power(states, wrenches)  # [(t, power into the rock W, |mantle force| N)]
    trock = [r[0] for r in rock]
    fines = any(q[3] > 0 for q in prod)
    print(f"{'from':>6} {'to':>6} {'amp x mm':>9} {'power kW':>9} {'t/h':>7} {'kWh/t':>7} {'chamber kg':>11}"
          + (f" {'fines kg':>8}" if fines else "") + (f" {'rock kW':>8} {'mantle kN':>9} {'nut deg':>7}" if rock else ""))
    w0 = 0.0
    while w0 < t_end - 1e-9:
        w1 = w0 + window
        if w1 > t_end + 1e-6:
            break  # a part cycle at the end would bias the power
        amps = []
        for c in range(a.cycles):
            seg = x[bisect.bisect_left(tx, w0 + c * period):bisect.bisect_left(tx, w0 + (c + 1) * period)]
            if seg:
                amps.append(0.5 * (max(seg) - min(seg)))
        pw = p[bisect.bisect_left(tp, w0):bisect.bisect_left(tp, w1)]
        amp = f"{sum(amps) / len(amps):9.2f}" if amps else f"{'n/a':>9}"
        pm = sum(pw) / len(pw) if pw else float("nan")
        inside = [q for q in prod if w0 <= q[0] <= w1]
        tph = se = chamber = held = float("nan")
        if inside:
            before = [q for q in prod if q[0] < w0]
            m0 = before[-1][1] if before else 0.0
            t0 = before[-1][0] if before else 0.0
            t1, m1, chamber, held = inside[-1]
            if t1 > t0:
                tph = (m1 - m0) / (t1 - t0) * 3.6
                se = pm / tph if tph > 0 else float("nan")
        extra = f" {held:8.1f}" if fines else ""
        if rock:
            rw = rock[bisect.bisect_left(trock, w0 - 1e-9):bisect.bisect_left(trock, w1 - 1e-9)]
            if rw:
                extra += (f" {sum(r[1] for r in rw) / len(rw) * 1e-3:8.1f}"
                         f" {sum(r[2] for r in rw) / len(rw) * 1e-3:9.2f}")
            else:
                extra += f" {'n/a':>8} {'n/a':>9}"
            nw = [n[1] for n in nutation if w0 - 1e-9 <= n[0] < w1 - 1e-9]
            extra += f" {sum(nw) / len(nw):7.3f}" if nw else f" {'n/a':>7}"
        print(f"{w0:6.2f} {w1:6.2f} {amp} {pm:9.1f} {tph:7.1f} {se:7.2f} {chamber:11.1f}{extra}")
        w0 = w1


def twist(t):
    return [t.linear.x, t.linear.y, t.linear.z, t.angular.x, t.angular.y, t.angular.z]


def axis(q):
    """The body's z axis in the world: the third column of the rotation of the unit quaternion q."""
    return [2 * (q.x * q.z + q.w * q.y), 2 * (q.y * q.z - q.w * q.x), 1 - 2 * (q.x * q.x + q.y * q.y)]


def angle_deg(a, b):
    c = sum(ai * bi for ai, bi in zip(a, b)) / math.sqrt(sum(ai * ai for ai in a) * sum(bi * bi for bi in b))
    return math.degrees(math.acos(max(-1.0, min(1.0, c))))


def wrench(w):
    return [w.force.x, w.force.y, w.force.z, w.torque.x, w.torque.y, w.torque.z]


def rock_power(states, wrenches):
    """Per coupling step with a wrench and the states at its start and end: (start time, power the liners put into
    the rock in W, |force on the mantle| in N). The wrench (of the rock on each body, about its centre of mass) is
    the step's mean; the twist is taken as the mean of the step's two ends."""
    out = []
    for k in sorted(wrenches):
        if k not in states or k + 1 not in states:
            continue
        t, v0 = states[k]
        _, v1 = states[k + 1]
        work_rate = sum(wi * 0.5 * (a + b) for body in range(2)
                        for wi, a, b in zip(wrenches[k][body], v0[body], v1[body]))
        out.append((t, -work_rate, math.sqrt(sum(f * f for f in wrenches[k][0][:3]))))
    return out


if __name__ == "__main__":
    main()
