#!/usr/bin/env python3
"""Checks that a run stopped and resumed from its checkpoint (B) is the uninterrupted run (A).
Usage: check_resume.py A_DIR B_DIR          coupled run: each holds run.bag, summary.json, breaks.csv, trajectories.csv
       check_resume.py --fast A_DIR B_DIR   fast (flow) run: run.bag and summary.json"""
import json
import os
import sys

import rosbag


def fail(msg):
    print("FAIL:", msg)
    sys.exit(1)


def messages(path):
    out = {}
    with rosbag.Bag(path) as bag:
        for topic, msg, t in bag.read_messages(raw=True):
            out.setdefault(topic, []).append((t.to_nsec(), msg[1]))  # raw: (type, serialized bytes, md5, ...)
    return out


def same_bags_and_summary(a_dir, b_dir):
    """Every topic of B's run.bag equals A's message for message (stamp and serialized bytes); summary.json the
    same but for wall_s."""
    a, b = messages(os.path.join(a_dir, "run.bag")), messages(os.path.join(b_dir, "run.bag"))
    if sorted(a) != sorted(b):
        fail(f"topics differ: {sorted(a)} vs {sorted(b)}")
    for topic in sorted(a):
        if len(a[topic]) != len(b[topic]):
            fail(f"{topic}: {len(a[topic])} messages in one go, {len(b[topic])} resumed")
        for k, (ma, mb) in enumerate(zip(a[topic], b[topic])):
            if ma != mb:
                fail(f"{topic}: message {k} (t = {ma[0] * 1e-9:.4f} s) differs after the resume")
        print(f"topic {topic}: {len(a[topic])} messages identical")
    sa, sb = (json.load(open(os.path.join(d, "summary.json"))) for d in (a_dir, b_dir))
    for s in (sa, sb):
        s.pop("wall_s", None)
    if sa != sb:
        fail(f"summary.json differs: {sa} vs {sb}")
    return a


def main(a_dir, b_dir):
    same_bags_and_summary(a_dir, b_dir)
    steps = [m.step for _, m, _ in rosbag.Bag(os.path.join(b_dir, "run.bag")).read_messages(["/crusher/geometry_state"])]
    if steps != list(range(len(steps))) or len(steps) != 120:
        fail(f"coupling steps are not 0..119 exactly once: {len(steps)} states")
    for name in ("breaks.csv", "trajectories.csv"):
        fa, fb = (open(os.path.join(d, name)).read() for d in (a_dir, b_dir))
        if fa != fb:
            fail(f"{name} differs after the resume")
    t_resume = 0.08
    breaks = [float(l.split(",")[0]) for l in open(os.path.join(a_dir, "breaks.csv")).read().splitlines()[1:]]
    n_breaks = len(breaks)
    if not any(t > t_resume for t in breaks):
        fail("no bond broke after the resume point: the case does not exercise the restored bonds")
    wrench = [m for _, m, _ in rosbag.Bag(os.path.join(a_dir, "run.bag")).read_messages(["/crusher/geometry_wrench"])]
    if not any(abs(m.mantle.force.z) > 0 and m.time > t_resume for m in wrench):
        fail("no rock on the mantle after the resume point: the case does not exercise the restored contacts")
    print(f"resumed run identical to the uninterrupted one: {len(steps)} coupling steps, {n_breaks} broken bonds")


def main_fast(a_dir, b_dir):
    a = same_bags_and_summary(a_dir, b_dir)
    for topic in ("/crusher/test_point", "/crusher/drive", "/crusher/product", "/crusher/chamber"):
        if not a.get(topic):
            fail(f"{topic} is missing from the fast run's bag")
    print(f"resumed fast run identical to the uninterrupted one: {len(a['/crusher/test_point'])} test-point samples")


if __name__ == "__main__":
    if sys.argv[1] == "--fast":
        main_fast(sys.argv[2], sys.argv[3])
    else:
        main(sys.argv[1], sys.argv[2])
