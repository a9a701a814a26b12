#!/usr/bin/env python3
"""dynamic_reconfigure: a person (1 m cube, label person) walks face-on at 0.1 m/s towards
the robot body `pillar` (1 m cube at the origin) from a face gap of 2 m, so the analytic time
to contact is 20 s minus the time walked, far beyond every threshold: NOTICE.
1. person_warning_time := 30 s -> WARNING from the next cycles (and the config reads back 30).
2. person_critical_time := 40 s (> warning_time): refused; the config reads back 0.4 and the
   level stays WARNING, never CRITICAL.
3. horizon := 5 s -> the pair ENDs (its contact is ~18 s away) and stays absent.
4. robot_thresholds' warning time 30 s with the person's back at 1 s: WARNING again (the
   stricter label counts), and a horizon of 30 s brings the pair back.
"""
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402
from dynamic_reconfigure.client import Client  # noqa: E402

from wp_node_testlib import (END, TIME_TOL, Collector, ContactEvent, ScenePublisher,  # noqa: E402
                             Track, broadcast_static, check_array_basics, events_for)

SPEED = 0.1


class ReconfigureTest(unittest.TestCase):
    def setUp(self):
        self.tf_pub = broadcast_static([("world", "base_link", (0, 0, 0), (0, 0, 0))])
        self.col = Collector()
        self.assertTrue(self.col.wait_for_node(), "proximity_monitor published no contacts")
        self.client = Client("proximity_monitor", timeout=20)
        self.t0 = rospy.Time.now()
        self.scene = ScenePublisher("tracked_objects", [Track(
            "person_1", "person", (3.0, 0.0, 0.0), (1, 1, 1), (-SPEED, 0.0, 0.0))], latency=0.05)
        self.scene.start(self.t0)

    def tearDown(self):
        self.scene.stop()

    def pair_events(self, since):
        """(array, event or None) for every array stamped at or after `since`."""
        out = []
        for m in self.col.contact_msgs(since=since):
            check_array_basics(self, m)
            evs = [e for e in events_for(m, "person_1", "pillar")]
            out.append((m, evs[0] if evs else None))
        return out

    def settle(self, seconds=1.0):
        """Waits, then returns the events of the last half second (changes have taken effect)."""
        rospy.sleep(seconds)
        return self.pair_events(rospy.Time.now() - rospy.Duration(0.5))

    def check_analytic(self, ev, m):
        t = (m.header.stamp - self.t0).to_sec()
        self.assertAlmostEqual(ev.time_to_contact, (2.0 - SPEED * t) / SPEED, delta=20 * TIME_TOL,
                               msg="t=%.3f ttc %.4f" % (t, ev.time_to_contact))

    def test_live_thresholds_and_horizon(self):
        before = self.settle(1.5)
        self.assertTrue(before)
        for m, ev in before:
            self.assertIsNotNone(ev, "no event for the approaching person")
            self.assertEqual(ev.level, ContactEvent.NOTICE)
            self.check_analytic(ev, m)

        cfg = self.client.update_configuration({"person_warning_time": 30.0})
        self.assertEqual(cfg["person_warning_time"], 30.0)
        for m, ev in self.settle():
            self.assertIsNotNone(ev)
            self.assertEqual(ev.level, ContactEvent.WARNING, "warning time 30 s not applied")
            self.check_analytic(ev, m)

        changed = rospy.Time.now()
        cfg = self.client.update_configuration({"person_critical_time": 40.0})
        self.assertEqual(cfg["person_critical_time"], 0.4, "invalid change not refused")
        self.assertEqual(cfg["person_warning_time"], 30.0)
        for m, ev in self.pair_events(changed) + self.settle():
            if ev is not None and ev.state != END:
                self.assertEqual(ev.level, ContactEvent.WARNING, "refused change applied")

        cfg = self.client.update_configuration({"horizon": 5.0})
        self.assertEqual(cfg["horizon"], 5.0)
        for m, ev in self.settle():
            self.assertIsNone(ev, "pair still predicted beyond the 5 s horizon")

        cfg = self.client.update_configuration({"horizon": 30.0, "person_warning_time": 1.0,
                                                "robot_warning_time": 30.0})
        self.assertEqual(cfg["robot_warning_time"], 30.0)
        for m, ev in self.settle():
            self.assertIsNotNone(ev, "pair not back with a 30 s horizon")
            self.assertEqual(ev.level, ContactEvent.WARNING, "robot thresholds not applied")
            self.check_analytic(ev, m)


if __name__ == "__main__":
    rospy.init_node("test_reconfigure")
    rostest.rosrun("workspace_proximity", "test_reconfigure", ReconfigureTest)
