#!/usr/bin/env python3
"""rostest checker for mbd_node: topics arrive at the configured rates in sim time, the bag is complete."""
import json
import os
import sys
import time
import unittest

import rosbag
import rospy
import rostest
import yaml
from inertia_crusher.msg import DriveState, TestPoint
from rosgraph_msgs.msg import Clock
from tf2_msgs.msg import TFMessage


def tf_point(T, p):
    """World coordinates of point p given in the frame of transform T (rotation by the unit quaternion, then shift)."""
    q, t = T.rotation, T.translation
    u = (q.x, q.y, q.z)
    v = (p.x, p.y, p.z)
    c1 = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
    c2 = (u[1] * c1[2] - u[2] * c1[1], u[2] * c1[0] - u[0] * c1[2], u[0] * c1[1] - u[1] * c1[0])
    r = [v[i] + 2 * (q.w * c1[i] + c2[i]) for i in range(3)]
    return {"x": r[0] + t.x, "y": r[1] + t.y, "z": r[2] + t.z}


class MbdNodeTest(unittest.TestCase):
    def setUp(self):
        rospy.init_node("check_mbd_node")
        self.out = rospy.get_param("~out")
        cfg = yaml.safe_load(open(rospy.get_param("~config")))
        self.publish_hz = float(cfg["run"]["publish_hz"])
        self.tf_hz = float(cfg["run"]["tf_hz"])
        self.duration = float(rospy.get_param("~duration"))
        self.got = {"tp": [], "drive": [], "tf": [], "clock": []}
        rospy.Subscriber("/crusher/test_point", TestPoint, lambda m: self.got["tp"].append(m.header.stamp.to_sec()),
                         queue_size=100000)
        rospy.Subscriber("/crusher/drive", DriveState, lambda m: self.got["drive"].append(m.header.stamp.to_sec()),
                         queue_size=100000)
        rospy.Subscriber("/tf", TFMessage, lambda m: self.got["tf"].append(
            (m.transforms[0].header.stamp.to_sec(), sorted(t.child_frame_id for t in m.transforms))), queue_size=10000)
        rospy.Subscriber("/clock", Clock, lambda m: self.got["clock"].append(m.clock.to_sec()), queue_size=100000)

    def test_topics_and_bag(self):
        summary = os.path.join(self.out, "summary.json")
        deadline = time.time() + 200
        while not os.path.exists(summary) and time.time() < deadline:
            time.sleep(0.2)
        self.assertTrue(os.path.exists(summary), "mbd_node wrote no summary.json")
        time.sleep(0.5)
        # Live topics: stamped in sim time (the /clock the node publishes), at publish_hz of sim time.
        tp = self.got["tp"]
        self.assertGreater(len(tp), 0.5 * self.duration * self.publish_hz, "too few /crusher/test_point messages")
        span = tp[-1] - tp[0]
        self.assertGreater(span, 0.5 * self.duration)
        rate = (len(tp) - 1) / span
        self.assertAlmostEqual(rate, self.publish_hz, delta=0.02 * self.publish_hz)
        self.assertLessEqual(tp[-1], self.duration + 1e-6, "stamps are not sim time")
        self.assertTrue(all(b > a for a, b in zip(tp, tp[1:])), "test_point stamps not increasing")
        # /clock ticks with /tf (run.tf_hz): sim time for the tools, without waking every node at publish_hz.
        clock = self.got["clock"]
        self.assertTrue(len(clock) > 2 and abs(clock[-1] - tp[-1]) < 2.0 / self.tf_hz, clock[-3:])
        clock_rate = (len(clock) - 1) / (clock[-1] - clock[0])
        self.assertAlmostEqual(clock_rate, self.tf_hz, delta=0.05 * self.tf_hz)
        tf_rate = (len(self.got["tf"]) - 1) / (self.got["tf"][-1][0] - self.got["tf"][0][0])
        self.assertAlmostEqual(tf_rate, self.tf_hz, delta=0.05 * self.tf_hz)
        frames = self.got["tf"][0][1]
        self.assertEqual(frames, sorted(["fixed_cone", "floating_cone", "vibrator", "globe_bearing",
                                         "connecting_shaft", "drive_shaft", "test_point"]))
        # Bag: every sample the node produced, from t = 0 to the end, evenly spaced.
        expected = int(round(self.duration * self.publish_hz))  # t = k / publish_hz, k = 1..N
        with rosbag.Bag(os.path.join(self.out, "run.bag")) as bag:
            counts = {t: i.message_count for t, i in bag.get_type_and_topic_info().topics.items()}
            self.assertEqual(counts.get("/crusher/test_point"), expected, counts)
            self.assertEqual(counts.get("/crusher/drive"), expected, counts)
            self.assertEqual(counts.get("/tf"), int(round(self.duration * self.tf_hz)), counts)
            stamps = [m.header.stamp.to_sec() for _, m, _ in bag.read_messages(topics=["/crusher/test_point"])]
            gaps = [b - a for a, b in zip(stamps, stamps[1:])]
            self.assertAlmostEqual(max(gaps), 1.0 / self.publish_hz, delta=0.51 / self.publish_hz * 0.5)
            self.assertAlmostEqual(min(gaps), 1.0 / self.publish_hz, delta=0.51 / self.publish_hz * 0.5)
            self.assertAlmostEqual(stamps[-1], self.duration, delta=1.0 / self.publish_hz)
            # The test_point frame (fixed_cone -> test_point) moves in world as TestPoint's displacement does.
            disp = {round(m.header.stamp.to_sec(), 6): m.displacement
                    for _, m, _ in bag.read_messages(topics=["/crusher/test_point"])}
            world = {}
            for _, m, _ in bag.read_messages(topics=["/tf"]):
                T = {t.child_frame_id: t for t in m.transforms}
                self.assertEqual(T["test_point"].header.frame_id, "fixed_cone")
                world[round(m.transforms[0].header.stamp.to_sec(), 6)] = tf_point(T["fixed_cone"].transform,
                                                                                  T["test_point"].transform.translation)
            common = sorted(set(disp) & set(world))
            self.assertGreater(len(common), 10)
            t0 = common[0]
            for t in common[1:]:
                for axis in "xyz":
                    moved = world[t][axis] - world[t0][axis]
                    self.assertAlmostEqual(moved, getattr(disp[t], axis) - getattr(disp[t0], axis), delta=1e-7)
        s = json.load(open(summary))
        self.assertAlmostEqual(s["simulated_s"], self.duration, delta=1.0 / self.publish_hz)
        self.assertGreater(s["amplitude_x_mm"]["mean"], 0.5)
        self.assertIsNone(s["throughput_tph"])


if __name__ == "__main__":
    rostest.rosrun("inertia_crusher", "mbd_node_topics_and_bag", MbdNodeTest, sys.argv)
