#!/usr/bin/env python3
"""Speed and separation monitoring while the prediction is DEGRADED.

The robot body "post" (0.4 m cube) sits on frame "carriage", broadcast by the test on /tf at
50 Hz (not static, so it can go stale); a person stands 5 m away (raw scale 1). Parameters:
~ssm/degraded_scale 0.3, hold_time 0.2 s, max_increase_rate 5 / s; tf_timeout 0.5 s,
track_timeout 0.5 s.
  1. all fresh: OK, the scale reaches 1;
  2. the tf broadcasts pause for 1.2 s: once the link's newest transform is older than
     tf_timeout, DEGRADED ("robot body post stale"): the scale drops at once to 0.3;
  3. tf resumes: OK, the scale rises back to 1 (after the hold, at the rate);
  4. the tracker goes silent: after min(source_timeout, track_timeout) DEGRADED ("source
     /tracked_objects: no data"), the scale 0.3.
Checks on every safety_status: the status is the contacts array's of the same cycle; while
DEGRADED speed_scale <= degraded_scale, and exactly 0.3 here (the raw scale is 1), the raw
scale stays 1, and the reason reads "DEGRADED, scale at most 0.30: <the cause>"; each outage
is seen (enough cycles of each cause) and the scale is 1 again between them.
"""
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402

from wp_node_testlib import (ContactEventArray, SafetyStatus, ScenePublisher,  # noqa: E402
                             SsmCollector, TfBroadcaster, Track, connected_collector)

CAP = 0.3


class SsmDegradedTest(unittest.TestCase):
    def test_degraded_caps_the_scale(self):
        ssm = SsmCollector()
        col = connected_collector(self)
        carriage = TfBroadcaster("world", "carriage", lambda stamp: (0.0, 0.0, 0.0))
        person = Track("p1", "person", (5.0, 0.0, 0.9), (0.5, 0.5, 1.8))
        scene = ScenePublisher("tracked_objects", [person], latency=0.05)
        t0 = scene.start()
        rospy.sleep(2.0)                      # 1. fresh; the scale rises to 1
        carriage.paused.set()                 # 2. tf outage
        rospy.sleep(1.2)
        carriage.paused.clear()               # 3. tf back
        rospy.sleep(1.5)
        scene.stop()                          # 4. the tracker goes silent
        silent = rospy.Time.now()
        rospy.sleep(1.5)
        end = rospy.Time.now()
        carriage.stop.set()

        statuses = [m for m in ssm.statuses(since=t0) if m.header.stamp <= end]
        contacts = dict((m.header.stamp, m) for m in col.contact_msgs(since=t0))
        self.assertGreater(len(statuses), 100)
        causes = {"robot body post stale": 0, "source /tracked_objects: no data": 0}
        full_between = False
        saw_tf_outage = False
        prev = None
        for m in statuses:
            ctx = "t=%.3f status %d raw %.3f scale %.3f %r" % (
                (m.header.stamp - t0).to_sec(), m.status, m.raw_scale, m.speed_scale, m.reason)
            arr = contacts.get(m.header.stamp)
            if arr is not None:
                self.assertEqual(m.status == SafetyStatus.DEGRADED,
                                 arr.status == ContactEventArray.DEGRADED, ctx)
            if m.status == SafetyStatus.DEGRADED:
                self.assertLessEqual(m.speed_scale, CAP + 1e-12, ctx)
                self.assertTrue(m.reason.startswith("DEGRADED, scale at most 0.30: "), ctx)
                for cause in causes:
                    if cause in m.reason:
                        causes[cause] += 1
                        saw_tf_outage = saw_tf_outage or cause.startswith("robot")
                if m.header.stamp >= t0 + rospy.Duration(1.0):
                    self.assertEqual(m.raw_scale, 1.0, ctx)
                    # Drops at once to the cap; from below it, rises to it after the hold.
                    if prev is not None and prev.speed_scale >= CAP:
                        self.assertEqual(m.speed_scale, CAP, ctx)
            elif m.header.stamp >= t0 + rospy.Duration(1.0):
                self.assertEqual(m.raw_scale, 1.0, ctx)
                self.assertNotIn("DEGRADED", m.reason, ctx)
                if saw_tf_outage and m.header.stamp < silent and m.speed_scale == 1.0:
                    full_between = True
            prev = m
        self.assertGreater(causes["robot body post stale"], 8, causes)
        self.assertGreater(causes["source /tracked_objects: no data"], 8, causes)
        self.assertTrue(full_between, "the scale did not return to 1 after the tf outage")
        self.assertEqual(statuses[-1].status, SafetyStatus.DEGRADED)
        self.assertEqual(statuses[-1].speed_scale, CAP)


if __name__ == "__main__":
    rospy.init_node("test_ssm_degraded")
    rostest.rosrun("workspace_proximity", "test_ssm_degraded", SsmDegradedTest)
