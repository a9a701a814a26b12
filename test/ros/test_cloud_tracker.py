#!/usr/bin/env python3
"""cloud_tracker through its topics (status "cloud_tracker: cloud_tracker" on /diagnostics, or
~status; clusters as markers on /cloud_tracker/clusters). Parameters:
test/ros/fixtures/cloud_tracker_params.yaml.

Scene (static tf): the camera at world (0, 0, 1) not turned, its points given in its frame;
the robot body "post" (0.3 m cube) on frame post_link at world (1.5, 0.5, 0.5); a floor
scanner at world (0, -1.5, 0.11) turned +90 deg about z. Clouds and scans at 10 Hz.

Checks:
1. The camera's cloud: a blob filling [0.9, 1.2) x [-0.6, -0.3) x [0.3, 0.9) (world) gives one
   cluster whose box is that block of voxels, exactly; the points on the post's faces are the
   robot's (counted as robot points, no cluster there).
2. The scan's two legs (1.02 m ahead, 0.1 to 0.2 m either side) give two clusters at world
   x in (0.1, 0.2) and (-0.2, -0.1), y in [-0.5, -0.45).
3. Clouds without a z field on the camera's topic, between the good ones: rejected by name
   ("missing_xyz", counted), and the good frames keep giving the cluster.
4. /diagnostics: WARN naming /silent_scan (no usable frame) and /cam2/points (its frame
   'nowhere' not placed by tf), and not naming /cam/points or /scan.
6. The robot body "arm" on a tf frame broadcast at 50 Hz (far from everything): while its tf
   stops for 0.6 s the cameras' frames come with poses older than self_max_gap (0.1 s):
   DEGRADED naming it; once tf is back that reason goes.
5. The unseen share: the only view (the camera's, azimuth -0.6 to -0.4 rad) misses every
   voxel within ssm_reach 0.5 m of the post (their azimuths from the camera are above -0.1
   rad; the scanners have no view): share exactly 1, above unseen_limit 0.5: DEGRADED.
"""
import math
import os
import struct
import sys
import threading
import time
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402
from sensor_msgs import point_cloud2  # noqa: E402
from sensor_msgs.msg import LaserScan, PointCloud2, PointField  # noqa: E402
from std_msgs.msg import Header  # noqa: E402
from visualization_msgs.msg import MarkerArray  # noqa: E402

from wp_node_testlib import (DiagnosticsCollector, TfBroadcaster, broadcast_static,  # noqa: E402
                             diag_values)

STATUS = "cloud_tracker: cloud_tracker"
CAMERA = (0.0, 0.0, 1.0)


def blob_points():
    """Points 2 cm apart filling [0.9, 1.2) x [-0.6, -0.3) x [0.3, 0.9), offset by 0.5 cm so
    none lies on a 5 cm voxel face, given in the camera frame."""
    pts = []
    for i in range(15):
        for j in range(15):
            for k in range(30):
                x, y, z = 0.905 + 0.02 * i, -0.595 + 0.02 * j, 0.305 + 0.02 * k
                pts.append((x - CAMERA[0], y - CAMERA[1], z - CAMERA[2]))
    return pts


def post_points():
    """Points on the faces of the post (0.3 m cube at (1.5, 0.5, 0.5)), camera frame."""
    pts = []
    for a in range(-7, 8):
        for b in range(-7, 8):
            u, v = 0.02 * a, 0.02 * b
            for p in ((1.35, 0.5 + u, 0.5 + v), (1.5 + u, 0.35, 0.5 + v), (1.5 + u, 0.5 + v, 0.65)):
                pts.append((p[0] - CAMERA[0], p[1] - CAMERA[1], p[2] - CAMERA[2]))
    return pts


def leg_ranges():
    ranges = []
    for i in range(501):
        a = -0.5 + 0.002 * i
        y = math.tan(a)
        leg = (-0.2 < y < -0.1) or (0.1 < y < 0.2)
        ranges.append(1.02 / math.cos(a) if leg else float("inf"))
    return ranges


class CloudTrackerTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("test_cloud_tracker")
        # As a nodelet, diagnostic_updater names the status after the manager.
        cls.diag = DiagnosticsCollector(rospy.get_param("~status", STATUS))
        cls.lock = threading.Lock()
        cls.markers = []  # (monotonic, MarkerArray)
        cls.sub = rospy.Subscriber("/cloud_tracker/clusters", MarkerArray, cls.on_markers, queue_size=50)
        cls.tf = broadcast_static([
            ("world", "camera", CAMERA, (0.0, 0.0, 0.0)),
            ("world", "post_link", (1.5, 0.5, 0.5), (0.0, 0.0, 0.0)),
            ("world", "scan_link", (0.0, -1.5, 0.11), (0.0, 0.0, math.pi / 2)),
        ])
        cls.arm_tf = TfBroadcaster("world", "arm_link", lambda stamp: (2.5, 2.5, 2.0))
        cls.cam = rospy.Publisher("/cam/points", PointCloud2, queue_size=5)
        cls.cam2 = rospy.Publisher("/cam2/points", PointCloud2, queue_size=5)
        cls.scan = rospy.Publisher("/scan", LaserScan, queue_size=5)
        cls.spoil = threading.Event()
        cls.stop = threading.Event()
        cls.points = blob_points() + post_points()
        cls.thread = threading.Thread(target=cls.publish)
        cls.thread.daemon = True
        cls.thread.start()

    @classmethod
    def on_markers(cls, msg):
        with cls.lock:
            cls.markers.append((time.monotonic(), msg))

    @classmethod
    def publish(cls):
        ranges = leg_ranges()
        while not cls.stop.is_set() and not rospy.is_shutdown():
            stamp = rospy.Time.now()
            cloud = point_cloud2.create_cloud_xyz32(Header(stamp=stamp, frame_id="camera"), cls.points)
            cls.cam.publish(cloud)
            cls.cam2.publish(point_cloud2.create_cloud_xyz32(Header(stamp=stamp, frame_id="nowhere"),
                                                             [(1.0, 0.0, 0.0)]))
            if cls.spoil.is_set():
                fields = [PointField("x", 0, PointField.FLOAT32, 1), PointField("y", 4, PointField.FLOAT32, 1)]
                cls.cam.publish(point_cloud2.create_cloud(Header(stamp=stamp, frame_id="camera"), fields,
                                                          [(1.0, 0.0), (1.1, 0.0)]))
            scan = LaserScan()
            scan.header = Header(stamp=stamp, frame_id="scan_link")
            scan.angle_min, scan.angle_increment = -0.5, 0.002
            scan.angle_max = -0.5 + 0.002 * 500
            scan.range_min, scan.range_max = 0.05, 10.0
            scan.ranges = ranges
            cls.scan.publish(scan)
            cls.stop.wait(0.1)

    @classmethod
    def tearDownClass(cls):
        cls.stop.set()

    def clusters(self, ns, since, count, timeout=10.0):
        """The cluster cubes in namespace `ns` of the first marker array after `since` that has
        `count` of them. (Under load a frame can come without the robot posed within
        self_max_gap: it keeps the robot's points, conservative, and has one cluster more.)"""
        deadline = time.monotonic() + timeout
        seen = set()
        while time.monotonic() < deadline:
            with self.lock:
                found = [[x for x in m.markers if x.ns == ns] for t, m in self.markers if t >= since]
            found = [f for f in found if f]
            seen.update(len(f) for f in found)
            for f in found:
                if len(f) == count:
                    return f
            time.sleep(0.05)
        self.fail("no markers in namespace %s with %d clusters (seen: %s)" % (ns, count, sorted(seen)))

    def test_1_blob_is_one_cluster_and_the_post_is_the_robot(self):
        cubes = self.clusters("clusters /cam/points", time.monotonic(), 1)
        c = cubes[0]
        # The voxels [0.90, 1.20) x [-0.60, -0.30) x [0.30, 0.90).
        for got, want in ((c.pose.position.x, 1.05), (c.pose.position.y, -0.45), (c.pose.position.z, 0.6),
                          (c.scale.x, 0.3), (c.scale.y, 0.3), (c.scale.z, 0.6)):
            self.assertAlmostEqual(got, want, delta=1e-4)
        st = self.diag.wait_for(lambda s, v: int(v.get("/cam/points: robot points", "0")) > 0, 10.0)
        self.assertIsNotNone(st, "no robot points counted")
        self.assertEqual(int(diag_values(st)["/cam/points: robot points"]), len(post_points()))

    def test_2_scan_legs_are_two_clusters(self):
        cubes = self.clusters("clusters /scan", time.monotonic(), 2)
        xs = sorted(c.pose.position.x for c in cubes)
        self.assertTrue(-0.2 < xs[0] < -0.1 and 0.1 < xs[1] < 0.2, xs)
        for c in cubes:
            self.assertAlmostEqual(c.pose.position.y, -0.475, delta=1e-4)

    def test_3_malformed_clouds_are_rejected_by_name(self):
        self.spoil.set()
        try:
            st = self.diag.wait_for(lambda s, v: int(v.get("/cam/points: frames rejected", "0")) >= 3, 10.0)
            self.assertIsNotNone(st, "malformed clouds not counted")
            self.assertEqual(diag_values(st)["/cam/points: last rejection"], "missing_xyz")
            self.clusters("clusters /cam/points", time.monotonic(), 1)
            self.assertNotIn("/cam/points", st.message)
        finally:
            self.spoil.clear()

    def test_4_silent_and_unreachable_sensors_are_degraded_by_name(self):
        st = self.diag.wait_for(lambda s, v: "/silent_scan" in s.message and "'nowhere'" in s.message, 10.0,
                                since=time.monotonic())
        self.assertIsNotNone(st, "no DEGRADED status naming both sensors")
        self.assertEqual(st.level, 1)
        self.assertIn("no usable frame", st.message)
        self.assertIn("'nowhere'", st.message)
        self.assertNotIn("sensor /cam/points", st.message)
        self.assertNotIn("sensor /scan:", st.message)

    def test_5_unseen_share_outside_every_view(self):
        st = self.diag.wait_for(lambda s, v: "unseen share" in v, 10.0, since=time.monotonic())
        self.assertIsNotNone(st, "no unseen share")
        v = diag_values(st)
        self.assertEqual(float(v["unseen share"]), 1.0)
        self.assertGreater(int(v["protective voxels"]), 1000)
        self.assertEqual(v["unseen: outside every view"], v["protective voxels"])
        self.assertIn("unseen share 1.000 of the protective volume above unseen_limit 0.500", st.message)

    def test_6_robot_poses_too_old_are_degraded(self):
        def gap(s, v):
            return "self_max_gap" in s.message
        self.assertIsNone(self.diag.wait_for(gap, 1.0, since=time.monotonic()), "gap before the outage")
        self.arm_tf.paused.set()
        try:
            st = self.diag.wait_for(gap, 5.0, since=time.monotonic())
            self.assertIsNotNone(st, "no DEGRADED reason for robot poses older than self_max_gap")
            self.assertIn("sensor /cam/points: robot poses unknown", st.message)
        finally:
            self.arm_tf.paused.clear()
        time.sleep(0.5)
        st = self.diag.wait_for(lambda s, v: not gap(s, v), 5.0, since=time.monotonic())
        self.assertIsNotNone(st, "the gap reason stayed after tf came back")


if __name__ == "__main__":
    rostest.rosrun("workspace_proximity", "cloud_tracker", CloudTrackerTest)
