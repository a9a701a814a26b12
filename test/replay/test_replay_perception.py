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
import os
import shutil
import tempfile
import unittest

import genpy
import rosbag

from replay_testlib import FIXTURES, main, read_csv, run_replay, write_world_tf

T0 = 100.0
CONFIG = os.path.join(FIXTURES, "common_params.yaml")


class ReplayPerception(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        from workspace_proximity.msg import PerceptionStatus, TrackedBoxArray
        cls.tmp = tempfile.mkdtemp()
        cls.bag = os.path.join(cls.tmp, "perception.bag")
        with rosbag.Bag(cls.bag, "w") as bag:
            write_world_tf(bag, T0)
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
        run = run_replay(self.bag, out, [CONFIG, config])
        self.assertEqual(run.returncode, 0, run.stderr.decode(errors="replace"))
        return read_csv(os.path.join(out, "cycles.csv"))

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


if __name__ == "__main__":
    main("test_replay_perception.py")  # with the devel space's messages
