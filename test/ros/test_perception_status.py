#!/usr/bin/env python3
"""Perception health through the monitor (issue 23 item 3).

cloud_tracker sees /cam/points (no view given: the whole protective volume is outside every
view, unseen share exactly 1; unseen_limit 1.0 keeps that from being DEGRADED). The test
publishes a cloud of a small box far from the robot's post at 10 Hz for 3 s, then stops.
Monitors (speed and separation on, degraded_scale 0):
  /a: ~perception_status_topics [/perception_status];
  /b: the same and /nobody/perception_status, which nobody publishes.
Checks:
1. while the camera publishes (from 1.5 s on): /a is OK with safety_status.unseen_share 1.0
   and /diagnostics "unseen share" 1.000; /b is DEGRADED, a status line naming
   /nobody/perception_status ("no status yet"), its speed_scale 0 and unseen_share NaN;
2. 1.6 s after the camera stopped (its front end's source_timeout 1.0 s): /a is DEGRADED with
   a line "perception /perception_status: ... /cam/points ..." (the silent sensor, named) and
   speed_scale 0.
"""
import math
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402
from sensor_msgs import point_cloud2  # noqa: E402
from sensor_msgs.msg import PointCloud2  # noqa: E402
from std_msgs.msg import Header  # noqa: E402

from wp_node_testlib import (ContactEventArray, ContactStatusRecorder, SafetyStatus,  # noqa: E402
                             broadcast_static, diag_values)


Recorder = ContactStatusRecorder  # wp_node_testlib


def box_points():
    pts = []
    for i in range(11):
        for j in range(11):
            for k in range(11):
                pts.append((1.5 + 0.02 * i, 1.5 + 0.02 * j, -0.5 + 0.02 * k))  # camera at z 1
    return pts


class PerceptionStatusTest(unittest.TestCase):
    def test_status_reaches_the_monitor(self):
        rec = {ns: Recorder("/" + ns) for ns in ("a", "b")}
        from diagnostic_msgs.msg import DiagnosticArray
        shown = []  # the monitors' "unseen share" on /diagnostics (names carry their namespace)

        def on_diag(msg):
            for st in msg.status:
                if st.name.endswith("proximity monitor"):
                    shown.append(diag_values(st).get("unseen share"))
        rospy.Subscriber("/diagnostics", DiagnosticArray, on_diag, queue_size=100)
        _static = broadcast_static([("world", "camera", (0.0, 0.0, 1.0), (0.0, 0.0, 0.0)),
                                    ("world", "post_link", (-1.0, -1.0, 0.5), (0.0, 0.0, 0.0))])
        pub = rospy.Publisher("/cam/points", PointCloud2, queue_size=5)
        deadline = rospy.Time.now() + rospy.Duration(20.0)
        while rospy.Time.now() < deadline and not (
                pub.get_num_connections() >= 1 and all(r.status for r in rec.values())):
            rospy.sleep(0.05)
        self.assertGreaterEqual(pub.get_num_connections(), 1)
        points = box_points()
        t0 = rospy.Time.now()
        rate = rospy.Rate(10.0)
        while rospy.Time.now() < t0 + rospy.Duration(3.0):
            pub.publish(point_cloud2.create_cloud_xyz32(Header(stamp=rospy.Time.now(), frame_id="camera"),
                                                        points))
            rate.sleep()
        t_stop = rospy.Time.now()
        rospy.sleep(2.5)

        # 1. While the camera publishes.
        contacts, status = rec["a"].between(t0 + rospy.Duration(1.5), t_stop)
        self.assertGreater(len(status), 10)
        for c in contacts:
            self.assertEqual(c.status, ContactEventArray.OK, list(c.status_details))
        for s in status:
            self.assertEqual(s.status, SafetyStatus.OK, s.reason)
            self.assertAlmostEqual(s.unseen_share, 1.0, delta=1e-9)
        contacts, status = rec["b"].between(t0 + rospy.Duration(1.5), t_stop)
        self.assertGreater(len(contacts), 10)
        for c in contacts:
            self.assertEqual(c.status, ContactEventArray.DEGRADED)
            self.assertIn("perception /nobody/perception_status: no status yet", list(c.status_details))
            self.assertFalse([d for d in c.status_details if "/cam/points" in d], list(c.status_details))
        for s in status:
            self.assertEqual(s.status, SafetyStatus.DEGRADED)
            self.assertEqual(s.speed_scale, 0.0)
            self.assertTrue(math.isnan(s.unseen_share), s.unseen_share)
        self.assertIn("1.000", shown, "the unseen share is not on /diagnostics: %s" % shown[-5:])

        # 2. The camera silent.
        contacts, status = rec["a"].between(t_stop + rospy.Duration(1.6), t_stop + rospy.Duration(2.4))
        self.assertGreater(len(contacts), 5)
        for c in contacts:
            self.assertEqual(c.status, ContactEventArray.DEGRADED)
            named = [d for d in c.status_details
                     if d.startswith("perception /perception_status: ") and "/cam/points" in d]
            self.assertTrue(named, list(c.status_details))
        for s in status:
            self.assertEqual(s.status, SafetyStatus.DEGRADED)
            self.assertEqual(s.speed_scale, 0.0)


if __name__ == "__main__":
    rospy.init_node("test_perception_status")
    rostest.rosrun("workspace_proximity", "test_perception_status", PerceptionStatusTest, sys.argv)
