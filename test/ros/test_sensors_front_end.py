#!/usr/bin/env python3
"""The simulated sensors into cloud_tracker, through the topics (sensors_front_end.test).

Scene: the demo arm (config/demo_arm.urdf) swinging at full speed (scene_simulator, joints on
tf); sensor_simulator's default depth camera (320 x 240 at (3.6, 2.4, 2.4) looking at the arm)
and floor scanner (1 000 beams at (3.6, -1.0, 0.2)); the true boxes are what this test
publishes on /true_objects; cloud_tracker with config/cloud_tracker/demo.yaml. Clusters are
read from /cloud_tracker/clusters (a MarkerArray per sensor frame, stamped with the frame).

1. The arm's own points never make a cluster: 4 s of the empty cell, every camera and scanner
   frame without a cluster, while the camera does see the arm (robot points counted).
2. A person (a 0.5 x 0.5 x 1.8 m box) is a camera cluster overlapping their footprint; after they leave at T,
   every camera frame stamped from T + 0.05 s on is free of them. The sensor simulator stamps a
   frame with the robot's newest tf stamp, which is never later than when it rendered the frame,
   and it heard of the departure within 0.05 s: so "free within one frame" is exact here: only
   the frame being rendered as the person left may still show them.
3. The camera silenced: DEGRADED naming it within source_timeout (1 s) and a diagnostic period;
   meanwhile the scanner alone sees a person standing in its plane (in every scan frame a
   cluster overlapping their footprint); the camera back: its name leaves the status.
"""
import os
import sys
import threading
import time
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402
from std_msgs.msg import Bool  # noqa: E402
from visualization_msgs.msg import MarkerArray  # noqa: E402

from wp_node_testlib import (DiagnosticsCollector, TrackedBox, TrackedBoxArray,  # noqa: E402
                             diag_values)

STATUS = "cloud_tracker: cloud_tracker"
CAMERA = "sim_camera_points"  # cloud_tracker names a sensor by its topic as configured
SCAN = "/sim_scan"
PERSON = (0.5, 0.5, 1.8)


class Frames(object):
    """Every sensor frame's clusters: (receipt wall time, stamp s, [(centre, size)]) per sensor."""

    def __init__(self):
        self.lock = threading.Lock()
        self.frames = {CAMERA: [], SCAN: []}
        self.unseen = []  # (stamp s, set of voxel indices)
        self.sub = rospy.Subscriber("/cloud_tracker/clusters", MarkerArray, self.on_markers, queue_size=50)

    def on_markers(self, msg):
        now = time.monotonic()
        per = {}
        for m in msg.markers:
            if m.ns == "unseen":
                cells = {voxel_index((p.x, p.y, p.z)) for p in m.points}
                with self.lock:
                    self.unseen.append((m.header.stamp.to_sec(), cells))
                continue
            for name in (CAMERA, SCAN):
                if m.ns == "voxels " + name:
                    per.setdefault(name, (m.header.stamp.to_sec(), []))
                elif m.ns == "clusters " + name:
                    per.setdefault(name, (m.header.stamp.to_sec(), []))[1].append(
                        ((m.pose.position.x, m.pose.position.y, m.pose.position.z),
                         (m.scale.x, m.scale.y, m.scale.z)))
        with self.lock:
            for name, (stamp, clusters) in per.items():
                self.frames[name].append((now, stamp, clusters))

    def since(self, name, wall):
        with self.lock:
            return [f for f in self.frames[name] if f[0] >= wall]

    def stamped(self, name, t):
        """The frames stamped at or after the ROS time t (s): what the sensors saw from t on,
        however late this process got to them."""
        with self.lock:
            return [f for f in self.frames[name] if f[1] >= t]

    def wait_stamped(self, name, t, count, timeout=20.0):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline and len(self.stamped(name, t)) < count:
            time.sleep(0.05)
        return self.stamped(name, t)

    def wait(self, name, wall, count, timeout=20.0):
        """The frames received since `wall`, once there are `count` (a loaded machine slows the
        sensors down: the test waits for frames, not for seconds)."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline and len(self.since(name, wall)) < count:
            time.sleep(0.05)
        return self.since(name, wall)


VOXEL = 0.05  # config/cloud_tracker/demo.yaml; the grid's corners are whole multiples of it
CAMERA_AT = (3.6, 2.4, 2.4)  # sensor_simulator's default camera position
BASE_RADIUS, BASE_TOP = 0.2, 0.4  # the demo arm's base cylinder (config/demo_arm.urdf)


def voxel_index(p):
    return tuple(int(round((c - 0.5 * VOXEL) / VOXEL)) for c in p)


def hidden_by_base(centre, core=0.1, top=0.35):
    """True when the straight line from the camera to `centre` passes through the core of the
    arm's base (within `core` of its axis, below `top`): an analytic oracle, independent of
    cloud_tracker's voxel walk."""
    for k in range(1, 400):
        u = k / 400.0
        x = CAMERA_AT[0] + u * (centre[0] - CAMERA_AT[0])
        y = CAMERA_AT[1] + u * (centre[1] - CAMERA_AT[1])
        z = CAMERA_AT[2] + u * (centre[2] - CAMERA_AT[2])
        if x * x + y * y <= core * core and 0.05 <= z <= top:
            return True
    return False


def covers(cluster, xy):
    """The cluster's box overlaps the footprint of the person standing at xy (a sensor sees the
    faces turned to it: a floor scanner's cluster is the front of the legs' column)."""
    (cx, cy, _), (sx, sy, _) = cluster
    return (abs(cx - xy[0]) <= 0.5 * (sx + PERSON[0]) + 1e-3 and
            abs(cy - xy[1]) <= 0.5 * (sy + PERSON[1]) + 1e-3)


class Scene(object):
    """Publishes the true boxes on /true_objects at 30 Hz: the people standing at self.people."""

    def __init__(self):
        self.people = []
        self.pub = rospy.Publisher("/true_objects", TrackedBoxArray, queue_size=5)
        self.timer = rospy.Timer(rospy.Duration(1.0 / 30.0), self.tick)

    def tick(self, _):
        msg = TrackedBoxArray()
        msg.header.stamp = rospy.Time.now()
        msg.header.frame_id = "world"
        for i, (x, y) in enumerate(list(self.people)):
            b = TrackedBox()
            b.id, b.label = "person_%d" % i, "person"
            b.pose.position.x, b.pose.position.y, b.pose.position.z = x, y, 0.5 * PERSON[2]
            b.pose.orientation.w = 1.0
            b.dimensions.x, b.dimensions.y, b.dimensions.z = PERSON
            msg.boxes.append(b)
        try:
            self.pub.publish(msg)
        except rospy.ROSException:
            pass  # shutting down

    def set(self, people):
        self.people = list(people)
        self.tick(None)


class SensorsFrontEnd(unittest.TestCase):
    def test_scene(self):
        frames = Frames()
        diag = DiagnosticsCollector(STATUS)
        scene = Scene()
        pause = rospy.Publisher("/sensor_simulator/pause_camera", Bool, queue_size=1, latch=True)
        # Wait for both sensors' frames to come through.
        deadline = time.monotonic() + 30.0
        while time.monotonic() < deadline and not (frames.since(CAMERA, 0) and frames.since(SCAN, 0)):
            time.sleep(0.1)
        self.assertTrue(frames.since(CAMERA, 0) and frames.since(SCAN, 0), "no frames from cloud_tracker")

        # 1. The empty cell with the arm swinging at full speed: no cluster, ever.
        t0 = rospy.Time.now().to_sec()
        for name in (CAMERA, SCAN):
            got = frames.wait_stamped(name, t0, 30)
            self.assertGreaterEqual(len(got), 30, "%s: %d frames" % (name, len(got)))
            bad = [f for f in got if f[2]]
            self.assertFalse(bad, "%s: the arm made clusters in %d of %d frames, e.g. %s"
                             % (name, len(bad), len(got), bad[:1]))
        robot_points = [int(diag_values(st).get(CAMERA + ": robot points", "0")) for _, st in diag.since(0.0)]
        self.assertTrue(robot_points and max(robot_points) > 100,
                        "the camera should see the arm (robot points %s)" % robot_points[-5:])

        # 2. A person in front of the arm, then gone.
        spot = (1.2, 1.0)
        t1 = time.monotonic()
        scene.set([spot])
        found = None
        while time.monotonic() < t1 + 3.0 and found is None:
            for _, stamp, clusters in frames.since(CAMERA, t1):
                if any(covers(c, spot) for c in clusters):
                    found = stamp
            time.sleep(0.05)
        self.assertIsNotNone(found, "the camera's clusters never covered the person at %s" % (spot,))
        time.sleep(0.5)
        gone = rospy.Time.now().to_sec()
        scene.set([])
        t2 = time.monotonic()
        after = []
        deadline = time.monotonic() + 20.0
        while len(after) < 10 and time.monotonic() < deadline:
            time.sleep(0.1)
            after = [f for f in frames.since(CAMERA, t2 - 0.5) if f[1] >= gone + 0.05]
        self.assertGreaterEqual(len(after), 10)
        late = [f[1] - gone for f in after if any(covers(c, spot) for c in f[2])]
        self.assertFalse(late, "frames stamped %s s after the person left still show them" % late)

        # 4. A person in the arm's shadow: right behind its base as the camera sees it. Every
        #    voxel of their legs whose line of sight crosses the base's core is reported unseen.
        shadow = (-0.5, -0.333)   # 0.6 m behind the base's axis, on the camera's line through it
        scene.set([shadow])
        hidden = []
        for ix in range(-8, 8):
            for iy in range(-8, 8):
                for iz in range(0, 8):
                    c = (VOXEL * (ix + 0.5) + round(shadow[0] / VOXEL) * VOXEL,
                         VOXEL * (iy + 0.5) + round(shadow[1] / VOXEL) * VOXEL, VOXEL * (iz + 0.5))
                    inside = (abs(c[0] - shadow[0]) < 0.5 * PERSON[0] and abs(c[1] - shadow[1]) < 0.5 * PERSON[1]
                              and c[2] > 0.05)
                    if inside and hidden_by_base(c):
                        hidden.append(voxel_index(c))
        self.assertGreater(len(hidden), 3, "the scene should hide some of the person's legs behind the base")
        t_shadow = rospy.Time.now().to_sec()
        deadline = time.monotonic() + 20.0
        unseen = []
        while time.monotonic() < deadline and len(unseen) < 5:
            time.sleep(0.1)
            with frames.lock:
                unseen = [u for t, u in frames.unseen if t >= t_shadow + 0.5]
        self.assertGreaterEqual(len(unseen), 5, "no unseen markers from cloud_tracker")
        for cells in unseen:
            missing = [h for h in hidden if h not in cells]
            self.assertFalse(missing, "%d of the %d voxels of the person hidden behind the base are not "
                             "reported unseen, e.g. %s" % (len(missing), len(hidden), missing[:3]))
        st = diag.latest()
        self.assertGreater(int(diag_values(st).get("unseen: shadowed", "0")), 0)
        rospy.loginfo("sensors_front_end: %d voxels of the person hidden behind the base, unseen in all %d "
                      "unseen reports; unseen share %s", len(hidden), len(unseen),
                      diag_values(st).get("unseen share"))
        scene.set([])

        # 3. The camera silenced: DEGRADED by name; the scanner alone still sees a person.
        legs = (2.0, -1.3)
        scene.set([legs])
        t3 = time.monotonic()
        pause.publish(Bool(data=True))
        st = diag.wait_for(lambda s, v: CAMERA in s.message and "DEGRADED" in s.message, 3.0, since=t3)
        self.assertIsNotNone(st, "a silent camera is not DEGRADED by name: %s"
                             % (diag.latest().message if diag.latest() else None))
        t4 = rospy.Time.now().to_sec()
        scans = frames.wait_stamped(SCAN, t4, 10)
        self.assertGreaterEqual(len(scans), 10)
        self.assertFalse(frames.stamped(CAMERA, t4 + 0.2), "the camera was to be silent")
        missing = [f[1:] for f in scans if not any(covers(c, legs) for c in f[2])]
        self.assertFalse(missing, "scan frames without a cluster covering the person at %s: %d of %d"
                         % (legs, len(missing), len(scans)))
        t5 = time.monotonic()
        pause.publish(Bool(data=False))
        st = diag.wait_for(lambda s, v: CAMERA not in s.message, 3.0, since=t5 + 0.3)
        self.assertIsNotNone(st, "the camera is back but still named: %s"
                             % (diag.latest().message if diag.latest() else None))


if __name__ == "__main__":
    rospy.init_node("test_sensors_front_end")
    rostest.rosrun("workspace_proximity", "sensors_front_end", SensorsFrontEnd)
