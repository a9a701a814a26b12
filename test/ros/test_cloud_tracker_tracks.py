#!/usr/bin/env python3
"""cloud_tracker's tracks on perceived_objects (workspace_proximity/TrackedBoxArray).

Scene: the camera frame "camera" at world (0, 0, 1), not turned; the robot body "post" far
away (world (2.5, 2.5, 2.0)). A box 0.4 x 0.4 x 1.0 m, its centre at z 0.6, moves along y at
V = 0.5 m/s from y = -1.0 (x = 1.0): every 0.1 s a cloud of points on its six faces (2 cm
apart, edges included) at its position at the cloud's stamp.

Checks, on every array (header: the cloud's stamp, frame world):
- at most one box, label "unknown", id stable;
- the first array's box has velocity_unknown true (a new track) and a zero twist;
- from 1.5 s on, velocity_unknown is false, the twist is V along y within the track's own
  velocity_error and within 0.1 m/s, and the box grown by its position_error on every side
  contains the true box at the stamp (its voxel hull rounded out: exact containment, 1e-4 m
  for float rounding).
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

from wp_node_testlib import TrackedBoxArray, broadcast_static  # noqa: E402

CAMERA = (0.0, 0.0, 1.0)
SIZE = (0.4, 0.4, 1.0)
V = 0.5
X0, Y0, Z0 = 1.0, -1.0, 0.6
SCENE_S = 4.0


def box_points(cx, cy, cz):
    """Points on the six faces of the box centred at (cx, cy, cz), camera frame."""
    pts = []
    hx, hy, hz = SIZE[0] / 2, SIZE[1] / 2, SIZE[2] / 2

    def grid(lo, hi):
        n = int(round((hi - lo) / 0.02))
        return [lo + (hi - lo) * i / n for i in range(n + 1)]
    for u in grid(-hx, hx):
        for v in grid(-hy, hy):
            pts.append((cx + u, cy + v, cz - hz))
            pts.append((cx + u, cy + v, cz + hz))
    for u in grid(-hx, hx):
        for w in grid(-hz, hz):
            pts.append((cx + u, cy - hy, cz + w))
            pts.append((cx + u, cy + hy, cz + w))
    for v in grid(-hy, hy):
        for w in grid(-hz, hz):
            pts.append((cx - hx, cy + v, cz + w))
            pts.append((cx + hx, cy + v, cz + w))
    return [(x - CAMERA[0], y - CAMERA[1], z - CAMERA[2]) for x, y, z in pts]


class CloudTrackerTracks(unittest.TestCase):
    def test_moving_box(self):
        lock = threading.Lock()
        arrays = []

        def on_array(msg):
            with lock:
                arrays.append(msg)
        rospy.Subscriber("/perceived_objects", TrackedBoxArray, on_array, queue_size=100)
        _static = broadcast_static([("world", "camera", CAMERA, (0.0, 0.0, 0.0)),
                                    ("world", "post_link", (2.5, 2.5, 2.0), (0.0, 0.0, 0.0))])
        pub = rospy.Publisher("/cam/points", PointCloud2, queue_size=5)
        deadline = rospy.Time.now() + rospy.Duration(20.0)
        while pub.get_num_connections() < 1 and rospy.Time.now() < deadline:
            rospy.sleep(0.05)
        self.assertGreaterEqual(pub.get_num_connections(), 1, "cloud_tracker did not subscribe")
        rospy.sleep(0.5)  # the static transforms reach the node's tf buffer
        t0 = rospy.Time.now()
        rate = rospy.Rate(10.0)
        while rospy.Time.now() < t0 + rospy.Duration(SCENE_S):
            stamp = rospy.Time.now()
            y = Y0 + V * (stamp - t0).to_sec()
            pub.publish(point_cloud2.create_cloud_xyz32(Header(stamp=stamp, frame_id="camera"),
                                                        box_points(X0, y, Z0)))
            rate.sleep()
        rospy.sleep(0.3)

        with lock:
            got = [a for a in arrays if a.header.stamp >= t0]
        self.assertGreater(len(got), 25, "%d arrays" % len(got))
        first = [a for a in got if a.boxes][0]
        self.assertTrue(first.boxes[0].velocity_unknown, "a new track's velocity must be unknown")
        self.assertEqual((first.boxes[0].twist.linear.x, first.boxes[0].twist.linear.y), (0.0, 0.0))
        ids = set()
        settled = 0
        for a in got:
            self.assertEqual(a.header.frame_id, "world")
            self.assertLessEqual(len(a.boxes), 1, "one box, one track")
            if not a.boxes:
                continue
            b = a.boxes[0]
            ids.add(b.id)
            self.assertEqual(b.label, "unknown")
            age = (a.header.stamp - t0).to_sec()
            if age < 1.5:
                continue
            settled += 1
            self.assertFalse(b.velocity_unknown, "velocity still unknown at %.2f s" % age)
            err = b.velocity_error
            self.assertGreater(err, 0.0)
            self.assertLessEqual(abs(b.twist.linear.y - V), min(err, 0.1) + 1e-9,
                                 "vy %.3f at %.2f s (error %.3f)" % (b.twist.linear.y, age, err))
            self.assertLessEqual(abs(b.twist.linear.x), min(err, 0.1) + 1e-9)
            true_c = (X0, Y0 + V * age, Z0)
            track_c = (b.pose.position.x, b.pose.position.y, b.pose.position.z)
            track_h = (b.dimensions.x / 2, b.dimensions.y / 2, b.dimensions.z / 2)
            for axis in range(3):
                # The true box's faces inside the track's box grown by position_error.
                reach = abs(track_c[axis] - true_c[axis]) + SIZE[axis] / 2
                self.assertLessEqual(reach, track_h[axis] + b.position_error + 1e-4,
                                     "axis %d at %.2f s: true face %.4f beyond %.4f + %.4f" % (
                                         axis, age, reach, track_h[axis], b.position_error))
        self.assertGreater(settled, 15)
        self.assertEqual(len(ids), 1, "the track changed ids: %s" % sorted(ids))


if __name__ == "__main__":
    rospy.init_node("test_cloud_tracker_tracks")
    rostest.rosrun("workspace_proximity", "test_cloud_tracker_tracks", CloudTrackerTracks, sys.argv)
