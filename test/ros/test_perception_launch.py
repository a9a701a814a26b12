#!/usr/bin/env python3
"""proximity_monitor.launch with clouds:='[/cam/points]': the perception front end beside the
monitor in one nodelet manager (issue 23 item 5).

Scene: the robot body "post" (0.4 m cube) on post_link at world (0, 0, 0.5); the camera frame at
world (0, 0, 1). A box 0.4 x 0.4 x 1.0 m (centre z 0.6) walks from x = 2.0 m towards the post
at 0.5 m/s (y = 0), seen as a cloud of its faces at 10 Hz for 3 s; then the camera stops.
Checks:
1. the launch started the manager /proximity_manager, and the monitor and cloud_tracker are
   nodelets in it (their loader nodes exist; the manager publishes both perceived_objects and
   contacts);
2. while the camera publishes (from 1.0 s on), every contacts array is OK; some array has an
   event between the post and a track of label "unknown" from perceived_objects; some
   safety_status has a raw scale below 1 (the box within the speed and separation reach);
3. 1.6 s after the camera stopped: DEGRADED, a status line naming the front end's
   perception_status and /cam/points, speed_scale 0.
"""
import os
import sys
import threading
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rosgraph  # noqa: E402
import rosnode  # noqa: E402
import rospy  # noqa: E402
import rostest  # noqa: E402
from sensor_msgs import point_cloud2  # noqa: E402
from sensor_msgs.msg import PointCloud2  # noqa: E402
from std_msgs.msg import Header  # noqa: E402

from wp_node_testlib import ContactEventArray, SafetyStatus, broadcast_static  # noqa: E402

CAMERA = (0.0, 0.0, 1.0)


def box_points(cx, cy, cz, size=(0.4, 0.4, 1.0)):
    hx, hy, hz = size[0] / 2, size[1] / 2, size[2] / 2
    pts = []

    def grid(h):
        n = int(round(2 * h / 0.02))
        return [-h + 2 * h * i / n for i in range(n + 1)]
    for u in grid(hx):
        for v in grid(hy):
            pts += [(cx + u, cy + v, cz - hz), (cx + u, cy + v, cz + hz)]
        for w in grid(hz):
            pts += [(cx + u, cy - hy, cz + w), (cx + u, cy + hy, cz + w)]
    for v in grid(hy):
        for w in grid(hz):
            pts += [(cx - hx, cy + v, cz + w), (cx + hx, cy + v, cz + w)]
    return [(x - CAMERA[0], y - CAMERA[1], z - CAMERA[2]) for x, y, z in pts]


class PerceptionLaunchTest(unittest.TestCase):
    def test_front_end_beside_the_monitor(self):
        lock = threading.Lock()
        contacts, status = [], []

        def into(where):
            def cb(msg):
                with lock:
                    where.append(msg)
            return cb
        rospy.Subscriber("/contacts", ContactEventArray, into(contacts), queue_size=500)
        rospy.Subscriber("/safety_status", SafetyStatus, into(status), queue_size=500)
        _static = broadcast_static([("world", "camera", CAMERA, (0.0, 0.0, 0.0)),
                                    ("world", "post_link", (0.0, 0.0, 0.5), (0.0, 0.0, 0.0))])
        pub = rospy.Publisher("/cam/points", PointCloud2, queue_size=5)
        deadline = rospy.Time.now() + rospy.Duration(30.0)
        while rospy.Time.now() < deadline and not (pub.get_num_connections() >= 1 and status):
            rospy.sleep(0.05)
        self.assertGreaterEqual(pub.get_num_connections(), 1, "cloud_tracker did not subscribe")

        # 1. One manager.
        nodes = rosnode.get_node_names()
        self.assertIn("/proximity_manager", nodes)
        self.assertIn("/proximity_monitor", nodes)
        self.assertIn("/cloud_tracker", nodes)
        # In a manager the nodelets' topics are the manager's: it publishes them both.
        publishers = dict(rosgraph.Master("/test_perception_launch").getSystemState()[0])
        self.assertEqual(publishers.get("/perceived_objects"), ["/proximity_manager"], publishers)
        self.assertEqual(publishers.get("/contacts"), ["/proximity_manager"], publishers)

        t0 = rospy.Time.now()
        rate = rospy.Rate(10.0)
        while rospy.Time.now() < t0 + rospy.Duration(3.0):
            stamp = rospy.Time.now()
            x = 2.0 - 0.5 * (stamp - t0).to_sec()
            pub.publish(point_cloud2.create_cloud_xyz32(Header(stamp=stamp, frame_id="camera"),
                                                        box_points(x, 0.0, 0.6)))
            rate.sleep()
        t_stop = rospy.Time.now()
        rospy.sleep(2.4)

        with lock:
            during_c = [c for c in contacts if t0 + rospy.Duration(1.0) <= c.header.stamp <= t_stop]
            during_s = [s for s in status if t0 + rospy.Duration(1.0) <= s.header.stamp <= t_stop]
            after_c = [c for c in contacts
                       if t_stop + rospy.Duration(1.6) <= c.header.stamp <= t_stop + rospy.Duration(2.3)]
            after_s = [s for s in status
                       if t_stop + rospy.Duration(1.6) <= s.header.stamp <= t_stop + rospy.Duration(2.3)]
        # 2. Seeing.
        self.assertGreater(len(during_c), 20)
        for c in during_c:
            self.assertEqual(c.status, ContactEventArray.OK, list(c.status_details))
        paired = [e for c in during_c for e in c.events if "unknown" in (e.label_a, e.label_b)]
        self.assertTrue(paired, "no event between the post and a perceived track")
        self.assertTrue(any("perceived_objects" in (e.id_a + e.id_b) for e in paired),
                        [(e.id_a, e.id_b) for e in paired[:3]])
        self.assertTrue(any(s.raw_scale < 1.0 for s in during_s), "the scale never dropped")
        # 3. The camera silent.
        self.assertGreater(len(after_c), 5)
        for c in after_c:
            self.assertEqual(c.status, ContactEventArray.DEGRADED)
            named = [d for d in c.status_details if "perception_status" in d and "/cam/points" in d]
            self.assertTrue(named, list(c.status_details))
        for s in after_s:
            self.assertEqual(s.speed_scale, 0.0)


if __name__ == "__main__":
    rospy.init_node("test_perception_launch")
    rostest.rosrun("workspace_proximity", "test_perception_launch", PerceptionLaunchTest, sys.argv)
