#!/usr/bin/env python3
"""~unseen: occupied through the topics (issue 23 item 4).

Scene: the camera at world (-2, 0, 1) looking along +x (view +-1 rad, 10 m); the robot body
"post" (0.4 m cube) at world (0, 0, 0.5); ssm_reach 0.5 m. The camera's cloud holds a plate
only, at x = -1.5, y in [0.1, 0.25], z in [0.9, 1.1] (1 cm apart): by similar triangles its
shadow at x = 0 spans y in [0.4, 1.0], z in [0.6, 1.4], which cuts into the post's protective
volume. Clouds at 10 Hz for 4 s.
Checks (from 1.5 s on):
1. /occupied/perceived_objects holds boxes labelled "unseen", velocity_unknown true, and the
   point (0, 0.5, 0.9) (0.36 m from the post, in the shadow) lies inside one of them, while
   (-0.4, -0.4, 0.5) (0.28 m from the post, in plain view) lies in none; /ignore's arrays
   hold no "unseen" box;
2. /occupied's monitor: protective stop (speed_scale 0) limited by an unseen box; /ignore's
   monitor (from 2.5 s, once its scale has risen from the start): speed_scale above 0.5 (the
   plate is 1.3 m away); status OK in both.
"""
import os
import sys
import threading
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402
from sensor_msgs import point_cloud2  # noqa: E402
from sensor_msgs.msg import PointCloud2  # noqa: E402
from std_msgs.msg import Header  # noqa: E402

from wp_node_testlib import SafetyStatus, TrackedBoxArray, broadcast_static  # noqa: E402

CAMERA = (-2.0, 0.0, 1.0)
SHADOWED = (0.0, 0.5, 0.9)
IN_VIEW = (-0.4, -0.4, 0.5)


def plate_points():
    pts = []
    for i in range(16):
        for k in range(21):
            pts.append((-1.5 - CAMERA[0], 0.1 + 0.01 * i - CAMERA[1], 0.9 + 0.01 * k - CAMERA[2]))
    return pts


def inside(box, p):
    c, d = box.pose.position, box.dimensions
    return (abs(p[0] - c.x) <= d.x / 2 and abs(p[1] - c.y) <= d.y / 2 and abs(p[2] - c.z) <= d.z / 2)


class CloudTrackerUnseen(unittest.TestCase):
    def test_shadow_stops_the_arm(self):
        lock = threading.Lock()
        arrays = {"ignore": [], "occupied": []}
        status = {"ignore": [], "occupied": []}

        def into(where):
            def cb(msg):
                with lock:
                    where.append(msg)
            return cb
        for ns in arrays:
            rospy.Subscriber("/%s/perceived_objects" % ns, TrackedBoxArray, into(arrays[ns]), queue_size=100)
            rospy.Subscriber("/%s/safety_status" % ns, SafetyStatus, into(status[ns]), queue_size=500)
        _static = broadcast_static([("world", "camera", CAMERA, (0.0, 0.0, 0.0)),
                                    ("world", "post_link", (0.0, 0.0, 0.5), (0.0, 0.0, 0.0))])
        pub = rospy.Publisher("/cam/points", PointCloud2, queue_size=5)
        deadline = rospy.Time.now() + rospy.Duration(20.0)
        while rospy.Time.now() < deadline and pub.get_num_connections() < 2:
            rospy.sleep(0.05)
        self.assertGreaterEqual(pub.get_num_connections(), 2)
        rospy.sleep(0.5)
        points = plate_points()
        t0 = rospy.Time.now()
        rate = rospy.Rate(10.0)
        while rospy.Time.now() < t0 + rospy.Duration(4.0):
            pub.publish(point_cloud2.create_cloud_xyz32(Header(stamp=rospy.Time.now(), frame_id="camera"), points))
            rate.sleep()
        t1 = rospy.Time.now()
        since = t0 + rospy.Duration(1.5)
        with lock:
            got = {ns: [a for a in arrays[ns] if since <= a.header.stamp <= t1] for ns in arrays}
            st = {ns: [s for s in status[ns] if since <= s.header.stamp <= t1] for ns in status}
            # The scale rises after the start (hold 0.5 s, then 0.5 / s): /ignore's from 2.5 s.
            st["ignore"] = [s for s in st["ignore"] if s.header.stamp >= t0 + rospy.Duration(2.5)]

        self.assertGreater(len(got["occupied"]), 10)
        counts = []
        for a in got["occupied"]:
            unseen = [b for b in a.boxes if b.label == "unseen"]
            self.assertTrue(unseen, "no unseen boxes")
            self.assertTrue(all(b.velocity_unknown for b in unseen))
            self.assertTrue(any(inside(b, SHADOWED) for b in unseen), "the shadow is not covered")
            self.assertFalse(any(inside(b, IN_VIEW) for b in unseen), "a seen place is covered: %s" % [
                (round(b.pose.position.x, 3), round(b.pose.position.y, 3), round(b.pose.position.z, 3),
                 round(b.dimensions.x, 3), round(b.dimensions.y, 3), round(b.dimensions.z, 3), len(unseen))
                for b in unseen if inside(b, IN_VIEW)])
            counts.append(len(unseen))
        rospy.loginfo("unseen boxes per array: %d to %d", min(counts), max(counts))
        self.assertLess(max(counts), 2000, "capped: the last box bounds the rest")
        self.assertGreater(len(got["ignore"]), 10)
        for a in got["ignore"]:
            self.assertFalse([b for b in a.boxes if b.label == "unseen"])

        self.assertGreater(len(st["occupied"]), 10)
        for s in st["occupied"]:
            self.assertEqual(s.status, SafetyStatus.OK, s.reason)
            self.assertEqual(s.speed_scale, 0.0, s.reason)
            self.assertTrue(s.id_object.split("/")[-1].startswith("unseen_"), s.id_object)
        self.assertGreater(len(st["ignore"]), 10)
        for s in st["ignore"]:
            self.assertEqual(s.status, SafetyStatus.OK, s.reason)
            self.assertGreater(s.speed_scale, 0.5, s.reason)


if __name__ == "__main__":
    rospy.init_node("test_cloud_tracker_unseen")
    rostest.rosrun("workspace_proximity", "test_cloud_tracker_unseen", CloudTrackerUnseen, sys.argv)
