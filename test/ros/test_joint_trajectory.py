#!/usr/bin/env python3
"""A planned trajectory with a stop in the middle, through ~trajectory_topic.

The plan for joint "swing" (header stamp t0, 0.5 s after it is sent): 0 rad at 0 s, 0.5 rad at
1 s, held until 2 s (the stop), 1.2 rad at 3 s; the joint states follow it exactly. The box on
the arc at 1 rad is first touched at contact_angle(1.0) = 0.771 rad, on the last leg:
t_c = 2 + (0.771 - 0.5) / 0.7 = 2.388 s. Every OK array from 0.4 s before t0 (t_c within the
3 s horizon) must carry the pair with time_to_contact within EARLY_TOL of t_c - t and never
later, in particular during the stop, when the arm stands still and its own velocity would
predict nothing. Then a trajectory with times not increasing is ignored, and one for joint
"stopper" that the joint states (holding it at 0) contradict by more than
~trajectory_tolerance is dropped: both counted in /diagnostics with the reason.
"""
import os
import sys
import time
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint  # noqa: E402

from wp_joint_testlib import OBJ_HALF, OBJ_R, JointStatePublisher, contact_angle  # noqa: E402
from wp_node_testlib import (END, Collector, ContactEventArray, DiagnosticsCollector,  # noqa: E402
                             ScenePublisher, Track, check_array_basics, diag_values, events_for,
                             fmt_event)

import math  # noqa: E402

PHI = 1.0
TIMES = [0.0, 1.0, 2.0, 3.0]
POSITIONS = [0.0, 0.5, 0.5, 1.2]
# s: the keyframes' bound makes predictions early, never late; the 16-segment budget over a
# 3 s horizon spreads them wider than joint_swing's, hence the looser early tolerance.
EARLY_TOL = 0.02
LATE_TOL = 0.001


def plan_at(t):
    """(position, velocity) of the plan t s after its start, linear between points."""
    if t <= TIMES[0]:
        return POSITIONS[0], 0.0
    for k in range(1, len(TIMES)):
        if t <= TIMES[k]:
            v = (POSITIONS[k] - POSITIONS[k - 1]) / (TIMES[k] - TIMES[k - 1])
            return POSITIONS[k - 1] + v * (t - TIMES[k - 1]), v
    return POSITIONS[-1], 0.0


def trajectory(names, times, positions, stamp):
    msg = JointTrajectory()
    msg.header.stamp = stamp
    msg.joint_names = names
    for t, q in zip(times, positions):
        msg.points.append(JointTrajectoryPoint(positions=q, time_from_start=rospy.Duration(t)))
    return msg


class JointTrajectoryTest(unittest.TestCase):
    def test_plan_with_a_stop(self):
        angle = contact_angle(PHI)
        self.assertTrue(0.5 < angle < 1.2)
        t_contact = 2.0 + (angle - 0.5) / 0.7

        col = Collector()
        diag = DiagnosticsCollector()
        self.assertTrue(col.wait_for_node(), "proximity_monitor published no contacts")
        box = Track("obj", "default", (OBJ_R * math.cos(PHI), OBJ_R * math.sin(PHI), 0.0),
                    (2 * OBJ_HALF, 2 * OBJ_HALF, 0.1), yaw=PHI)
        scene = ScenePublisher("tracked_objects", [box], latency=0.05)
        scene.start(rospy.Time.now())
        pub = rospy.Publisher("arm_controller/command", JointTrajectory, queue_size=5, latch=True)
        t0 = rospy.Time.now() + rospy.Duration(1.0)
        joints = JointStatePublisher(lambda stamp: {"swing": plan_at((stamp - t0).to_sec()),
                                                    "stopper": (0.0, 0.0)})
        self.assertTrue(joints.wait_connected(), "the node does not subscribe joint_states")
        joints.start()
        deadline = time.monotonic() + 10.0
        while pub.get_num_connections() == 0 and time.monotonic() < deadline:
            time.sleep(0.05)
        self.assertGreater(pub.get_num_connections(), 0, "the node does not subscribe the plan")
        pub.publish(trajectory(["swing"], TIMES, [[q] for q in POSITIONS], t0))
        while rospy.Time.now() < t0 + rospy.Duration(TIMES[-1] + 0.3):
            rospy.sleep(0.05)

        wall = time.monotonic()
        # Times not increasing: ignored.
        pub.publish(trajectory(["swing"], [0.0, 1.0, 1.0], [[0.0], [0.1], [0.2]], rospy.Time(0)))
        rospy.sleep(0.3)
        # "stopper" to 0.5 rad in 1 s from now, while its joint states hold it at 0: dropped
        # once it should be more than 0.1 rad away (after 0.2 s).
        pub.publish(trajectory(["stopper"], [0.0, 1.0], [[0.0], [0.5]], rospy.Time(0)))
        st = diag.wait_for(lambda s, v: v.get("trajectories dropped (not followed)") == "1" and
                           v.get("trajectories ignored") == "1", 5.0, since=wall)
        joints.halt()
        scene.stop()
        latest = diag.latest()
        self.assertIsNotNone(st, "diagnostics never counted the ignored and the dropped "
                             "trajectory: %r" % (diag_values(latest) if latest else None))
        self.assertIn("stopper", diag_values(st).get("last trajectory problem", ""))
        self.assertEqual(diag_values(st).get("trajectories accepted"), "2")

        during_stop = checked = 0
        for m in col.contact_msgs(since=t0 - rospy.Duration(0.4)):
            t = (m.header.stamp - t0).to_sec()
            if t >= t_contact - 0.05:
                break
            check_array_basics(self, m)
            ctx = "t=%.3f status=%d %r %s" % (t, m.status, list(m.status_details),
                                             [fmt_event(e) for e in m.events])
            self.assertEqual(m.status, ContactEventArray.OK, ctx)
            evs = [e for e in events_for(m, "arm", "obj") + events_for(m, "obj", "arm")
                   if e.state != END]
            self.assertEqual(len(evs), 1, "the planned contact is not predicted: " + ctx)
            expected = t_contact - t
            ttc = evs[0].time_to_contact
            self.assertLessEqual(ttc, expected + LATE_TOL, "late: expected %.4f: %s" % (expected, ctx))
            self.assertGreaterEqual(ttc, expected - EARLY_TOL, "expected %.4f: %s" % (expected, ctx))
            checked += 1
            if 1.05 < t < 1.95:
                during_stop += 1
        self.assertGreaterEqual(checked, 40)
        self.assertGreaterEqual(during_stop, 12, "too few arrays during the stop")


if __name__ == "__main__":
    rospy.init_node("test_joint_trajectory")
    rostest.rosrun("workspace_proximity", "test_joint_trajectory", JointTrajectoryTest)
