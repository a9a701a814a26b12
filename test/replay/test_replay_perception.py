#!/usr/bin/env python3
"""PerceptionStatus in the offline replay (issue 23): a bag with a perception front end's
status topic, replayed with ~perception_status_topics listing it, gives the cycles the status
says, as the node would.

The bag (written at test time): /tf_static (world -> base_link), empty TrackedBoxArray arrays on
/tracked_objects at 20 Hz for 3 s from T0 = 100 s, and PerceptionStatus on /perception_status at
10 Hz: healthy (unseen share 0.2) until T0 + 1.5 s, then degraded ("/cam/points: no usable frame
for 1.20 s").
Checks (cycles.csv):
- listing /perception_status: OK from T0 + 0.3 s to T0 + 1.4 s; DEGRADED from T0 + 1.7 s to
  T0 + 2.9 s with the detail "perception /perception_status: /cam/points: no usable frame ...";
- listing also /nobody/perception_status (not in the bag): every cycle DEGRADED naming it
  ("no status yet").
"""
import csv
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))

import genpy  # noqa: E402
import rosbag  # noqa: E402
import geometry_msgs.msg as g  # noqa: E402
from tf2_msgs.msg import TFMessage  # noqa: E402

REPLAY_BAG = None
T0 = 100.0
CONFIG = os.path.join(ROOT, "test", "ros", "fixtures", "common_params.yaml")


class ReplayPerception(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        from workspace_proximity.msg import PerceptionStatus, TrackedBoxArray
        cls.tmp = tempfile.mkdtemp()
        cls.bag = os.path.join(cls.tmp, "perception.bag")
        with rosbag.Bag(cls.bag, "w") as bag:
            tf = g.TransformStamped()
            tf.header.stamp = genpy.Time.from_sec(T0 - 0.5)
            tf.header.frame_id, tf.child_frame_id = "world", "base_link"
            tf.transform.rotation.w = 1.0
            bag.write("/tf_static", TFMessage(transforms=[tf]), tf.header.stamp)
            for k in range(61):
                stamp = genpy.Time.from_sec(T0 + 0.05 * k)
                a = TrackedBoxArray()
                a.header.stamp, a.header.frame_id = stamp, "world"
                bag.write("/tracked_objects", a, stamp)
                if k % 2 == 0:
                    s = PerceptionStatus()
                    s.header.stamp, s.header.frame_id = stamp, "world"
                    s.unseen_share = 0.2
                    if 0.05 * k >= 1.5:
                        s.degraded = True
                        s.reasons = ["/cam/points: no usable frame for 1.20 s"]
                    bag.write("/perception_status", s, stamp)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp)

    def replay(self, name, topics):
        config = os.path.join(self.tmp, name + ".yaml")
        with open(config, "w") as f:
            f.write("perception_status_topics: [%s]\n" % ", ".join(topics))
        out = os.path.join(self.tmp, "out-" + name)
        run = subprocess.run([REPLAY_BAG, self.bag, "--out", out, "--no-report", "--config", CONFIG,
                              "--config", config], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             timeout=120)
        self.assertEqual(run.returncode, 0, run.stderr.decode(errors="replace"))
        with open(os.path.join(out, "cycles.csv")) as f:
            return list(csv.DictReader(f))

    def test_recorded_status_drives_the_cycles(self):
        cycles = self.replay("one", ["/perception_status"])
        healthy = [c for c in cycles if T0 + 0.3 <= float(c["stamp"]) <= T0 + 1.4]
        degraded = [c for c in cycles if T0 + 1.7 <= float(c["stamp"]) <= T0 + 2.9]
        self.assertGreater(len(healthy), 15)
        self.assertGreater(len(degraded), 15)
        for c in healthy:
            self.assertEqual(c["status"], "OK", c["details"])
        for c in degraded:
            self.assertEqual(c["status"], "DEGRADED")
            self.assertIn("perception /perception_status: /cam/points: no usable frame", c["details"])

    def test_a_status_topic_missing_from_the_bag_is_degraded(self):
        cycles = self.replay("two", ["/perception_status", "/nobody/perception_status"])
        steady = [c for c in cycles if T0 + 0.3 <= float(c["stamp"]) <= T0 + 2.9]
        self.assertGreater(len(steady), 30)
        for c in steady:
            self.assertEqual(c["status"], "DEGRADED")
            self.assertIn("perception /nobody/perception_status: no status yet", c["details"])


def main():
    global REPLAY_BAG
    REPLAY_BAG = sys.argv.pop(1)
    # This package's Python messages from the devel space beside replay_bag.
    devel = os.path.normpath(os.path.join(os.path.dirname(REPLAY_BAG), "..", ".."))
    sys.path.insert(0, os.path.join(devel, "lib", "python3", "dist-packages"))
    unittest.main()


if __name__ == "__main__":
    main()
