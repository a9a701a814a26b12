#!/usr/bin/env python3
"""cloud_tracker's self-filter posed from joint_states, through its topics (issue 23).
Parameters: test/ros/fixtures/cloud_tracker_joints.yaml; the robot: swing_arm.urdf (root
"world" = the fixed frame; "arm", a 1 m box turned by joint "swing" about z at z = 0; "arm2"
held by joint "stopper" at z = 2). No tf for the arm's links: only joint_states (50 Hz, with
velocities) pose them.

Scene: the camera frame at world (0, 0, 1) (static tf), its points given in its frame. The
arm swings at its URDF velocity limit: q(t) = 2.5 sin(0.8 t), |dq/dt| up to 2 rad/s (its tip
at 2 m/s). Clouds at 15 Hz hold points 2 cm apart on the arm's true surface at the cloud's
stamp (the analytic angle), arm2's and a blob's (0.3 x 0.3 x 0.5 m at (1.6, -1.6, 0.75));
every other cloud is stamped 30 ms before it is sent, so its stamp lies between two joint
readings (the others lie after the newest).

Checks:
1. Over 4 s (60 frames): every frame's clusters (~clusters markers) are the blob alone: no
   cluster from the arm; and perception_status names no robot-pose problem for the camera.
2. joint_states silenced: perception_status DEGRADED with a reason naming the camera, the
   joint 'swing' and the arm's link (its tf is absent too), and the arm's points then make a
   cluster of their own (the frame goes without the self-filter: conservative).
"""
import math
import os
import sys
import threading
import time
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402
from sensor_msgs import point_cloud2  # noqa: E402
from sensor_msgs.msg import PointCloud2  # noqa: E402
from std_msgs.msg import Header  # noqa: E402
from visualization_msgs.msg import MarkerArray  # noqa: E402

from wp_joint_testlib import JointStatePublisher  # noqa: E402
from wp_node_testlib import broadcast_static  # noqa: E402  (also finds the devel messages)
from workspace_proximity.msg import PerceptionStatus  # noqa: E402

CAMERA = (0.0, 0.0, 1.0)
AMPLITUDE, RATE = 2.5, 0.8  # rad, rad/s: the swing's top speed is 2 rad/s
BLOB = (1.6, -1.6, 0.75)
NS = "clusters /cam/points"


def box_surface(centre_local, half, yaw, z0, step=0.02):
    """Points `step` apart on the faces of a box of half extents `half` whose centre is at
    `centre_local` in a frame turned by `yaw` about z at height z0 (world)."""
    pts = []
    c, s = math.cos(yaw), math.sin(yaw)

    def grid(h):
        n = max(1, int(round(2 * h / step)))
        return [-h + 2 * h * i / n for i in range(n + 1)]

    for axis in range(3):
        u, v = (axis + 1) % 3, (axis + 2) % 3
        for side in (-1.0, 1.0):
            for a in grid(half[u]):
                for b in grid(half[v]):
                    p = [0.0, 0.0, 0.0]
                    p[axis], p[u], p[v] = side * half[axis], a, b
                    x, y, z = centre_local[0] + p[0], centre_local[1] + p[1], centre_local[2] + p[2]
                    pts.append((c * x - s * y, s * x + c * y, z0 + z))
    return pts


def blob_points():
    pts = []
    for i in range(8):
        for j in range(8):
            for k in range(13):
                pts.append((BLOB[0] - 0.15 + 0.04 * i + 0.005, BLOB[1] - 0.15 + 0.04 * j + 0.005,
                            BLOB[2] - 0.25 + 0.04 * k + 0.005))
    return pts


class CloudTrackerJointsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("test_cloud_tracker_joints")
        cls.lock = threading.Lock()
        cls.frames = []    # (monotonic, stamp, [cluster centres])
        cls.statuses = []  # (monotonic, PerceptionStatus)
        cls.tf = broadcast_static([("world", "camera", CAMERA, (0.0, 0.0, 0.0))])
        cls.subs = [rospy.Subscriber("/cloud_tracker/clusters", MarkerArray, cls.on_markers, queue_size=50),
                    rospy.Subscriber("/perception_status", PerceptionStatus, cls.on_status, queue_size=50)]
        cls.t0 = rospy.Time.now().to_sec()
        cls.joints = JointStatePublisher(cls.positions, with_velocity=True, period=0.02)
        cls.joints.start()
        cls.cam = rospy.Publisher("/cam/points", PointCloud2, queue_size=5)
        cls.stop = threading.Event()
        cls.blob = blob_points()
        cls.arm2 = box_surface((0.5, 0.0, 0.0), (0.5, 0.05, 0.05), 0.0, 2.0)
        cls.thread = threading.Thread(target=cls.publish)
        cls.thread.daemon = True
        cls.thread.start()

    @classmethod
    def angle(cls, t):
        return AMPLITUDE * math.sin(RATE * (t - cls.t0)), AMPLITUDE * RATE * math.cos(RATE * (t - cls.t0))

    @classmethod
    def positions(cls, stamp):
        q, v = cls.angle(stamp.to_sec())
        return {"swing": (q, v), "stopper": (0.0, 0.0)}

    @classmethod
    def on_markers(cls, msg):
        centres = [(m.pose.position.x, m.pose.position.y, m.pose.position.z) for m in msg.markers if m.ns == NS]
        stamps = [m.header.stamp for m in msg.markers if m.ns.startswith("voxels")]
        if not stamps:
            return  # not a frame's markers (the unseen share's voxels share the topic)
        with cls.lock:
            cls.frames.append((time.monotonic(), stamps[0] if stamps else None, centres))

    @classmethod
    def on_status(cls, msg):
        with cls.lock:
            cls.statuses.append((time.monotonic(), msg))

    @classmethod
    def publish(cls):
        late = False
        while not cls.stop.is_set() and not rospy.is_shutdown():
            stamp = rospy.Time.now()
            if late:  # a camera's latency: the stamp lies between two joint readings
                stamp -= rospy.Duration(0.03)
            late = not late
            q, _ = cls.angle(stamp.to_sec())
            arm = box_surface((0.5, 0.0, 0.0), (0.5, 0.05, 0.05), q, 0.0)
            pts = [(x - CAMERA[0], y - CAMERA[1], z - CAMERA[2]) for x, y, z in arm + cls.arm2 + cls.blob]
            cls.cam.publish(point_cloud2.create_cloud_xyz32(Header(stamp=stamp, frame_id="camera"), pts))
            cls.stop.wait(1.0 / 15.0)

    @classmethod
    def tearDownClass(cls):
        cls.stop.set()
        cls.joints.halt()

    def robot_reasons(self, since):
        with self.lock:
            out = [r for t, s in self.statuses if t >= since for r in s.reasons]
        return [r for r in out if "robot poses unknown" in r]

    def test_1_the_swinging_arm_makes_no_cluster(self):
        deadline = time.monotonic() + 20.0
        while time.monotonic() < deadline:  # the first frames posed from the joints
            with self.lock:
                ready = len(self.frames) >= 5
            if ready and not self.robot_reasons(time.monotonic() - 0.5):
                break
            time.sleep(0.1)
        start = time.monotonic()
        time.sleep(4.0)
        with self.lock:
            frames = [f for f in self.frames if f[0] >= start]
        self.assertGreaterEqual(len(frames), 30, "too few frames")
        for _, stamp, centres in frames:
            self.assertEqual(len(centres), 1, "frame %s: clusters %s (the blob alone expected)" % (stamp, centres))
            c = centres[0]
            self.assertLess(math.hypot(c[0] - BLOB[0], c[1] - BLOB[1]), 0.3, "cluster %s is not the blob" % (c,))
        self.assertEqual(self.robot_reasons(start), [])
        # The unseen share poses the robot as the frames' self-filter did (no tf for the arm):
        # never "unknown" for want of the arm's pose.
        with self.lock:
            unknown = [r for t, s in self.statuses if t >= start for r in s.reasons if "unseen share unknown" in r]
        self.assertEqual(unknown, [])

    def test_2_silent_joint_states_are_degraded_naming_the_joint(self):
        self.joints.halt()
        since = time.monotonic()
        deadline = since + 10.0
        reason = None
        while time.monotonic() < deadline and reason is None:
            for r in self.robot_reasons(since):
                if "swing" in r and "more than ~tf_timeout" in r:
                    reason = r
            time.sleep(0.1)
        self.assertIsNotNone(reason, "no DEGRADED reason naming the joint: %s" % self.robot_reasons(since))
        self.assertIn("sensor /cam/points: robot poses unknown", reason)
        self.assertIn("frame 'arm'", reason)
        # Without the self-filter the arm's points stay: a cluster near the arm.
        time.sleep(0.5)
        with self.lock:
            frames = [f for f in self.frames if f[0] >= since + 1.0]
        self.assertTrue(any(len(centres) >= 2 for _, _, centres in frames),
                        "the arm's points did not stay once its poses were unknown")


if __name__ == "__main__":
    rostest.rosrun("workspace_proximity", "cloud_tracker_joints", CloudTrackerJointsTest)
