#!/usr/bin/env python3
"""Checks a short coupled run (mbd_node + dem_node) from its bags and summary.json.
Usage: check_coupled_run.py OUT_DIR
OUT_DIR holds run.bag (the run's one bag: dem.bag merged into mbd_node's by merge_bags), mbd.bag (mbd_node's own
bag, copied before the merge) and dem.bag (dem_node's own). The run is checked on run.bag, what a user gets;
the node bags check that the merge lost and duplicated nothing and that the wrench applied is the one sent."""
import json
import os
import sys

import rosbag

DEM_TOPICS = ("/crusher/geometry_wrench", "/crusher/particles", "/crusher/particle_state", "/crusher/liners",
              "/crusher/product", "/crusher/concave_forces")


def fail(msg):
    print("FAIL:", msg)
    sys.exit(1)


def counts(bag):
    info = bag.get_type_and_topic_info().topics
    return {t: info[t].message_count for t in info}


def main(out):
    run = rosbag.Bag(os.path.join(out, "run.bag"))
    mbd = rosbag.Bag(os.path.join(out, "mbd.bag"))
    dem = rosbag.Bag(os.path.join(out, "dem.bag"))
    # One bag: every topic of both nodes, each once (the DEM's topics from the DEM's record), nothing lost.
    c_run, c_mbd, c_dem = counts(run), counts(mbd), counts(dem)
    for topic in DEM_TOPICS:
        if c_dem.get(topic, 0) == 0:
            fail(f"dem.bag has no {topic}")
    expected = dict(c_mbd)
    expected.update(c_dem)
    if c_run != expected:
        diff = {t: (c_run.get(t), expected.get(t)) for t in set(c_run) | set(expected) if c_run.get(t) != expected.get(t)}
        fail(f"run.bag topic counts differ from the node bags' (topic: (run.bag, expected)): {diff}")

    states = [m.step for _, m, _ in run.read_messages(topics=["/crusher/geometry_state"])]
    sent = [(m.step, m) for _, m, _ in run.read_messages(topics=["/crusher/geometry_wrench"])]
    applied = [(m.step, m) for _, m, _ in mbd.read_messages(topics=["/crusher/geometry_wrench"])]
    n = len(states)
    if n == 0:
        fail("no coupling step recorded")
    # No coupling step missing or duplicated, on either side.
    if states != list(range(n)):
        fail(f"geometry_state steps are not 0..{n - 1} exactly once")
    if [s for s, _ in sent] != list(range(n)):
        fail(f"run.bag's wrench steps {[s for s, _ in sent][:5]}... are not 0..{n - 1} exactly once")
    if [s for s, _ in applied] != list(range(n)):
        fail(f"mbd_node applied wrench steps {[s for s, _ in applied][:5]}... not 0..{n - 1} exactly once")
    # The wrench the mechanism applied is the one the DEM computed (no mix-up of steps).
    for (s, m), (_, d) in zip(applied, sent):
        if (m.mantle.force.z, m.concave.force.z, m.mantle.torque.x) != (d.mantle.force.z, d.concave.force.z,
                                                                          d.mantle.torque.x):
            fail(f"step {s}: the wrench applied differs from the wrench sent")
    # Nonzero once rock touches the liners; and then the liners carry the rock's weight (force down on them).
    touching = [m for _, m in sent if abs(m.mantle.force.z) + abs(m.concave.force.z) > 0]
    if not touching:
        fail("the liner wrench stayed zero: no rock reached the liners")
    products = [m for _, m, _ in run.read_messages(topics=["/crusher/product"])]
    last = products[-1]
    weight = 9.81 * last.mass_in_chamber_kg
    fz = sum(m.mantle.force.z + m.concave.force.z for m in touching[-50:]) / len(touching[-50:])
    if not (fz < 0 and -fz < 3.0 * weight):
        fail(f"liners' vertical force {fz:.1f} N is not a plausible share of the rock weight {weight:.1f} N")
    # Mass balance: fed = in chamber (particles and the fines the flow model holds, dem.fines: flow) + discharged
    # (+ lost: spilled or thrown out of the machine), exact to round-off; the fines held are crushed rock.
    bal = last.mass_in_chamber_kg + last.mass_discharged_kg + last.mass_lost_kg
    if last.mass_fed_kg <= 0 or abs(last.mass_fed_kg - bal) > 1e-9 * last.mass_fed_kg:
        fail(f"mass balance: fed {last.mass_fed_kg:.12f} kg vs in chamber + discharged + lost {bal:.12f} kg")
    if not 0 <= last.mass_fines_bed_kg <= last.mass_crushed_kg + 1e-12:
        fail(f"fines held {last.mass_fines_bed_kg:.4f} kg is not within the {last.mass_crushed_kg:.4f} kg crushed")
    if last.mass_lost_kg > 0.05 * last.mass_fed_kg:
        fail(f"{last.mass_lost_kg:.3f} kg of {last.mass_fed_kg:.3f} kg left the machine outside the discharge")
    # Cumulative passing: monotone, ending at 100 % once something was discharged.
    p = list(last.passing_pct)
    if any(b < a for a, b in zip(p, p[1:])):
        fail(f"cumulative passing not monotone: {p}")
    if last.mass_discharged_kg > 0 and abs(p[-1] - 100.0) > 1e-6:
        fail(f"cumulative passing ends at {p[-1]} %, not 100 %")
    # Complete: test points at 500 Hz; DEM outputs at tf_hz of sim time (markers at each output, the product
    # and force map once more at the end).
    s = json.load(open(os.path.join(out, "summary.json")))
    tp = c_run.get("/crusher/test_point", 0)
    if tp < 0.9 * s["simulated_s"] * 500:
        fail(f"run.bag holds {tp} test-point samples for {s['simulated_s']} s")
    outputs = c_run["/crusher/particles"]
    if outputs < 0.9 * s["simulated_s"] * 20 or c_run["/crusher/liners"] != outputs:
        fail(f"run.bag holds {outputs} particle and {c_run['/crusher/liners']} liner samples for "
             f"{s['simulated_s']} s at 20 Hz")
    if c_run.get("/crusher/particle_state") != outputs:
        fail(f"run.bag holds {c_run.get('/crusher/particle_state')} particle-state samples, expected {outputs}")
    if c_run.get("/crusher/concave_force_markers") != outputs:
        fail(f"run.bag holds {c_run.get('/crusher/concave_force_markers')} force-map marker samples, expected {outputs}")
    if c_run["/crusher/product"] != outputs + 1 or c_run["/crusher/concave_forces"] != outputs + 1:
        fail(f"run.bag holds {c_run['/crusher/product']} product and {c_run['/crusher/concave_forces']} force-map "
             f"samples, expected {outputs + 1}")
    fm = [m for _, m, _ in run.read_messages(topics=["/crusher/concave_forces"])][-1]
    if fm.rings != 13 or fm.sectors != 9 or len(fm.mean_normal_force) != 117:
        fail("concave force map is not 13 x 9")
    print(f"coupled run: {n} coupling steps, {len(touching)} with rock on the liners, fed {last.mass_fed_kg:.2f} kg, "
          f"in chamber {last.mass_in_chamber_kg:.2f} kg, discharged {last.mass_discharged_kg:.2f} kg, lost {last.mass_lost_kg:.3f} kg; "
          f"run.bag: {len(c_run)} topics, {sum(c_run.values())} messages; all checks passed")


if __name__ == "__main__":
    main(sys.argv[1])
