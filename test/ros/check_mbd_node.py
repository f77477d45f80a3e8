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
        clock = self.got["clock"]
        self.assertTrue(clock and abs(clock[-1] - tp[-1]) < 2.0 / self.publish_hz)
        tf_rate = (len(self.got["tf"]) - 1) / (self.got["tf"][-1][0] - self.got["tf"][0][0])
        self.assertAlmostEqual(tf_rate, self.tf_hz, delta=0.05 * self.tf_hz)
        frames = self.got["tf"][0][1]
        self.assertEqual(frames, sorted(["fixed_cone", "floating_cone", "vibrator", "globe_bearing",
                                         "connecting_shaft", "drive_shaft"]))
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
        s = json.load(open(summary))
        self.assertAlmostEqual(s["simulated_s"], self.duration, delta=1.0 / self.publish_hz)
        self.assertGreater(s["amplitude_x_mm"]["mean"], 0.5)
        self.assertIsNone(s["throughput_tph"])


if __name__ == "__main__":
    rostest.rosrun("inertia_crusher", "mbd_node_topics_and_bag", MbdNodeTest, sys.argv)
