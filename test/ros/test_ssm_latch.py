#!/usr/bin/env python3
"""The stop latch through the node's topics and services, in real time.

The robot is a static 1 m cube ("post"); the node runs at 20 Hz with ~ssm/restart manual,
min_stop_time 0.5 s, stop_category 1 (halt: the test's /test_halt std_srvs/Trigger service,
standstill below 0.01 for 0.5 s), max_mute_time 5 s, hold_time 0.2 s, max_increase_rate 5 / s.
The test publishes the person every 50 ms and joint_states (one joint) every 20 ms.

   A  person 5 m away, joint moving (0.5 rad/s): the scale rises to 1 (the start is no stop)
   B  person 0.1 m from the post: protective stop. ~mute is refused (the scale is 0), ~reset is
      refused (a pair within S_p(v_max)); the joint still moves for 1 s: no halt
   C  joint speed 0: the halt is called once, no earlier than 0.5 s after the standstill began
   D  person 5 m away again for 2 s: the scale stays 0 (manual restart: no reset yet)
   E  ~reset: accepted; the scale rises above 0, to 1
   F  ~mute of label "person" for 2 s while clear: accepted, safety_status says muted
"""
import os
import sys
import threading
import time
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402
import tf2_ros  # noqa: E402
from geometry_msgs.msg import TransformStamped  # noqa: E402
from sensor_msgs.msg import JointState  # noqa: E402
from std_srvs.srv import Trigger, TriggerResponse  # noqa: E402

from workspace_proximity.srv import Mute  # noqa: E402
from wp_node_testlib import SsmCollector, Track, TrackedBoxArray  # noqa: E402

FAR = (5.0, 0.0, 0.9)
NEAR = (0.5 + 0.1 + 0.25, 0.0, 0.9)   # 0.1 m from the post's face


class Scene(object):
    """The person and the joint, published from a thread of their own."""

    def __init__(self):
        self.box_pub = rospy.Publisher("tracked_objects", TrackedBoxArray, queue_size=5)
        self.joint_pub = rospy.Publisher("joint_states", JointState, queue_size=5)
        self.static = tf2_ros.StaticTransformBroadcaster()
        self.where = FAR
        self.joint_speed = 0.5
        self.running = True
        self.thread = threading.Thread(target=self._run)

    def start(self):
        t = TransformStamped()
        t.header.frame_id = "world"
        t.child_frame_id = "base_link"
        t.transform.rotation.w = 1.0
        self.static.sendTransform(t)
        self.thread.start()

    def _run(self):
        k = 0
        while self.running and not rospy.is_shutdown():
            now = rospy.Time.now()
            if k % 5 == 0:
                stamp = now - rospy.Duration(0.02)
                msg = TrackedBoxArray()
                msg.header.stamp = stamp
                msg.header.frame_id = "world"
                msg.boxes = [Track("p1", "person", self.where, (0.5, 0.5, 1.8), t0=stamp).to_msg(stamp)]
                self.box_pub.publish(msg)
            js = JointState()
            js.header.stamp = now
            js.name = ["joint_1"]
            js.position = [0.0]
            js.velocity = [self.joint_speed]
            self.joint_pub.publish(js)
            k += 1
            time.sleep(0.01)

    def stop(self):
        self.running = False
        self.thread.join()


class SsmLatchTest(unittest.TestCase):
    def setUp(self):
        self.halts = []
        self.halt_srv = rospy.Service("/test_halt", Trigger, self._on_halt)

    def _on_halt(self, _req):
        self.halts.append(time.monotonic())
        return TriggerResponse(success=True, message="brakes on")

    def wait_for(self, what, pred, timeout):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if pred():
                return
            time.sleep(0.02)
        self.fail("timed out waiting for " + what)

    def test_restart_interlock_mute_and_halt(self):
        ssm = SsmCollector()
        scene = Scene()
        self.wait_for("connections", lambda: ssm.connected() and
                      scene.box_pub.get_num_connections() >= 1 and
                      scene.joint_pub.get_num_connections() >= 1, 15.0)
        rospy.wait_for_service("proximity_monitor/reset", 10.0)
        rospy.wait_for_service("proximity_monitor/mute", 10.0)
        reset = rospy.ServiceProxy("proximity_monitor/reset", Trigger)
        mute = rospy.ServiceProxy("proximity_monitor/mute", Mute)
        scene.start()
        try:
            last = lambda: ssm.statuses()[-1] if ssm.statuses() else None  # noqa: E731
            # A: rises to 1 without a reset: the start is no stop.
            self.wait_for("scale 1 at the start", lambda: last() is not None and last().speed_scale == 1.0, 10.0)
            self.assertFalse(last().reset_required)
            # B: the stop.
            scene.where = NEAR
            self.wait_for("the stop", lambda: last().protective_stop and last().stopped, 3.0)
            stop_wall = time.monotonic()
            self.assertTrue(last().reset_required)
            self.assertEqual(last().hold, "reset")
            r = mute(labels=["person"], ids=[], duration=2.0)
            self.assertFalse(r.success, r.message)
            self.assertIn("scale is 0", r.message)
            r = reset()
            self.assertFalse(r.success, r.message)
            self.assertIn("within", r.message)
            time.sleep(1.0)
            self.assertEqual(self.halts, [], "halt called while the joint moved")
            self.assertFalse(last().halt_requested)
            self.assertIn("standstill", last().reason)
            # C: standstill -> one halt, >= 0.5 s after it began.
            still_wall = time.monotonic()
            scene.joint_speed = 0.0
            self.wait_for("the halt", lambda: len(self.halts) >= 1, 3.0)
            self.assertGreaterEqual(self.halts[0] - still_wall, 0.5 - 0.1)
            self.assertGreater(self.halts[0] - stop_wall, 0.5)
            # D: the person leaves; no reset: the scale stays 0.
            scene.where = FAR
            time.sleep(0.5)
            since = rospy.Time.now()
            time.sleep(2.0)
            held = ssm.statuses(since)
            self.assertGreater(len(held), 20)
            self.assertTrue(all(m.speed_scale == 0.0 for m in held),
                            "the scale rose without a reset: %r" % [m.speed_scale for m in held])
            self.assertTrue(all(m.reset_required for m in held))
            self.assertEqual(len(self.halts), 1, "the halt once per stop")
            # E: the reset is accepted; the scale rises.
            r = reset()
            self.assertTrue(r.success, r.message)
            self.assertIn("accepted", r.message)
            self.wait_for("the scale above 0 after the reset", lambda: last().speed_scale > 0.0, 3.0)
            self.wait_for("the scale at 1", lambda: last().speed_scale == 1.0, 3.0)
            self.assertFalse(last().reset_required)
            self.assertFalse(last().stopped)
            # F: a mute while clear is accepted and shown.
            r = mute(labels=["person"], ids=[], duration=2.0)
            self.assertTrue(r.success, r.message)
            self.wait_for("muted in safety_status", lambda: last().muted, 1.0)
            self.assertIn("person", last().mute_scope)
            self.wait_for("the mute to end by itself", lambda: not last().muted, 3.5)
            self.assertEqual(len(self.halts), 1)
        finally:
            scene.stop()


if __name__ == "__main__":
    rospy.init_node("test_ssm_latch")
    rostest.rosrun("workspace_proximity", "ssm_latch", SsmLatchTest)
