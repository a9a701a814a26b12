#!/usr/bin/env python3
"""A person in the arm's shadow with ~unseen: occupied, from the simulated camera
(sensors_unseen.test).

Scene: the demo arm swinging (scene_simulator, joint_states through robot_state_publisher);
sensor_simulator's default depth camera (320 x 240 at (3.6, 2.4, 2.4) looking at the arm), no
scanner; cloud_tracker with config/cloud_tracker/demo.yaml and ~unseen: occupied; the monitor
on /perceived_objects.

A person stands right behind the arm's base as the camera sees it (the spot of
sensors_front_end's shadow check). Every voxel of their legs whose line of sight from the
camera crosses the base's core (test_sensors_front_end.hidden_by_base, analytic) lies inside
one of the 'unseen' boxes of each perceived_objects array stamped 1 s after they stepped in, and
the monitor stops the arm (speed_scale 0). What no sensor sees near the robot counts as
occupied, so the hidden person cannot be clear; with the arm's own shadow next to it, the stop
does not single out the person (cloud_tracker_unseen, the perceived branch's test, compares
occupied with ignore on a scene of its own).
"""
import os
import sys
import threading
import time
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402
from std_msgs.msg import Float64  # noqa: E402

from wp_node_testlib import TrackedBox, TrackedBoxArray  # noqa: E402
from test_sensors_front_end import PERSON, VOXEL, hidden_by_base  # noqa: E402

SHADOW = (-0.5, -0.333)


class SensorsUnseen(unittest.TestCase):
    def test_shadow(self):
        lock = threading.Lock()
        arrays, scales = [], []

        def on_array(msg):
            boxes = [(b.pose.position, b.dimensions) for b in msg.boxes if b.label == "unseen"]
            with lock:
                arrays.append((msg.header.stamp.to_sec(), boxes))

        def on_scale(msg):
            with lock:
                scales.append((rospy.Time.now().to_sec(), msg.data))

        rospy.Subscriber("/perceived_objects", TrackedBoxArray, on_array, queue_size=100)
        rospy.Subscriber("/speed_scale", Float64, on_scale, queue_size=100)
        pub = rospy.Publisher("/true_objects", TrackedBoxArray, queue_size=5)

        def person():
            msg = TrackedBoxArray()
            msg.header.stamp, msg.header.frame_id = rospy.Time.now(), "world"
            b = TrackedBox()
            b.id, b.label = "hidden", "person"
            b.pose.position.x, b.pose.position.y, b.pose.position.z = SHADOW[0], SHADOW[1], 0.5 * PERSON[2]
            b.pose.orientation.w = 1.0
            b.dimensions.x, b.dimensions.y, b.dimensions.z = PERSON
            msg.boxes.append(b)
            try:
                pub.publish(msg)
            except rospy.ROSException:
                pass  # shutting down

        timer = rospy.Timer(rospy.Duration(1.0 / 30.0), lambda _: person())
        t0 = rospy.Time.now().to_sec()
        hidden = []
        for ix in range(-8, 8):
            for iy in range(-8, 8):
                for iz in range(0, 8):
                    c = (VOXEL * (ix + 0.5) + round(SHADOW[0] / VOXEL) * VOXEL,
                         VOXEL * (iy + 0.5) + round(SHADOW[1] / VOXEL) * VOXEL, VOXEL * (iz + 0.5))
                    if (abs(c[0] - SHADOW[0]) < 0.5 * PERSON[0] and abs(c[1] - SHADOW[1]) < 0.5 * PERSON[1]
                            and c[2] > 0.05 and hidden_by_base(c)):
                        hidden.append(c)
        self.assertGreater(len(hidden), 3)

        deadline = time.monotonic() + 30.0
        later = []
        while time.monotonic() < deadline and len(later) < 10:
            time.sleep(0.1)
            with lock:
                later = [a for a in arrays if a[0] >= t0 + 1.0]
        self.assertGreaterEqual(len(later), 10, "perceived_objects too slow")

        def inside(c, box):
            p, d = box
            return (abs(c[0] - p.x) <= 0.5 * d.x + 1e-3 and abs(c[1] - p.y) <= 0.5 * d.y + 1e-3 and
                    abs(c[2] - p.z) <= 0.5 * d.z + 1e-3)

        for stamp, boxes in later:
            self.assertTrue(boxes, "no 'unseen' boxes at %.3f with ~unseen: occupied" % stamp)
            bare = [c for c in hidden if not any(inside(c, b) for b in boxes)]
            self.assertFalse(bare, "%d of %d hidden voxels of the person outside every 'unseen' box at %.3f, "
                             "e.g. %s" % (len(bare), len(hidden), stamp, bare[:2]))
        deadline = time.monotonic() + 10.0
        stopped = None
        while stopped is None and time.monotonic() < deadline:
            with lock:
                stopped = next((s for s in scales if s[0] >= t0 and s[1] == 0.0), None)
            time.sleep(0.05)
        self.assertIsNotNone(stopped, "the arm was not stopped: %s" % scales[-3:])
        rospy.loginfo("sensors_unseen: %d hidden voxels of the person inside 'unseen' boxes in %d arrays "
                      "(%d boxes in the last); the arm stopped", len(hidden), len(later), len(later[-1][1]))
        timer.shutdown()


if __name__ == "__main__":
    rospy.init_node("test_sensors_unseen")
    rostest.rosrun("workspace_proximity", "sensors_unseen", SensorsUnseen)
