#!/usr/bin/env python3
"""Checks a short coupled run (mbd_node + dem_node) from its two bags and summary.json.
Usage: check_coupled_run.py OUT_DIR"""
import json
import os
import sys

import rosbag


def fail(msg):
    print("FAIL:", msg)
    sys.exit(1)


def main(out):
    run = rosbag.Bag(os.path.join(out, "run.bag"))
    dem = rosbag.Bag(os.path.join(out, "dem.bag"))
    states = [m.step for _, m, _ in run.read_messages(topics=["/crusher/geometry_state"])]
    got = [(m.step, m) for _, m, _ in run.read_messages(topics=["/crusher/geometry_wrench"])]
    sent = {m.step: m for _, m, _ in dem.read_messages(topics=["/crusher/geometry_wrench"])}
    n = len(states)
    if n == 0:
        fail("no coupling step recorded")
    # No coupling step missing or duplicated, on either side.
    if states != list(range(n)):
        fail(f"geometry_state steps are not 0..{n - 1} exactly once")
    if [s for s, _ in got] != list(range(n)):
        fail(f"mbd_node applied wrench steps {[s for s, _ in got][:5]}... not 0..{n - 1} exactly once")
    if sorted(sent) != list(range(n)):
        fail("dem_node answered a different set of steps than were requested")
    # The wrench the mechanism applied is the one the DEM computed (no mix-up of steps).
    for s, m in got:
        d = sent[s]
        if (m.mantle.force.z, m.concave.force.z, m.mantle.torque.x) != (d.mantle.force.z, d.concave.force.z,
                                                                          d.mantle.torque.x):
            fail(f"step {s}: the wrench applied differs from the wrench sent")
    # Nonzero once rock touches the liners; and then the liners carry the rock's weight (force down on them).
    touching = [m for _, m in got if abs(m.mantle.force.z) + abs(m.concave.force.z) > 0]
    if not touching:
        fail("the liner wrench stayed zero: no rock reached the liners")
    products = [m for _, m, _ in dem.read_messages(topics=["/crusher/product"])]
    last = products[-1]
    weight = 9.81 * last.mass_in_chamber_kg
    fz = sum(m.mantle.force.z + m.concave.force.z for m in touching[-50:]) / len(touching[-50:])
    if not (fz < 0 and -fz < 3.0 * weight):
        fail(f"liners' vertical force {fz:.1f} N is not a plausible share of the rock weight {weight:.1f} N")
    # Mass balance: fed = in chamber + discharged within 0.5 %.
    bal = last.mass_in_chamber_kg + last.mass_discharged_kg
    if last.mass_fed_kg <= 0 or abs(last.mass_fed_kg - bal) > 0.005 * last.mass_fed_kg:
        fail(f"mass balance: fed {last.mass_fed_kg:.4f} kg vs in chamber + discharged {bal:.4f} kg")
    # Cumulative passing: monotone, ending at 100 % once something was discharged.
    p = list(last.passing_pct)
    if any(b < a for a, b in zip(p, p[1:])):
        fail(f"cumulative passing not monotone: {p}")
    if last.mass_discharged_kg > 0 and abs(p[-1] - 100.0) > 1e-6:
        fail(f"cumulative passing ends at {p[-1]} %, not 100 %")
    # Both bags complete and readable; the summary holds the product.
    tp = run.get_message_count("/crusher/test_point")
    s = json.load(open(os.path.join(out, "summary.json")))
    if tp < 0.9 * s["simulated_s"] * 500:
        fail(f"run.bag holds {tp} test-point samples for {s['simulated_s']} s")
    for topic in ("/crusher/particles", "/crusher/liners", "/crusher/concave_forces"):
        if dem.get_message_count(topic) == 0:
            fail(f"dem.bag has no {topic}")
    fm = [m for _, m, _ in dem.read_messages(topics=["/crusher/concave_forces"])][-1]
    if fm.rings != 13 or fm.sectors != 9 or len(fm.mean_normal_force) != 117:
        fail("concave force map is not 13 x 9")
    print(f"coupled run: {n} coupling steps, {len(touching)} with rock on the liners, fed {last.mass_fed_kg:.2f} kg, "
          f"in chamber {last.mass_in_chamber_kg:.2f} kg, discharged {last.mass_discharged_kg:.2f} kg; all checks passed")


if __name__ == "__main__":
    main(sys.argv[1])
