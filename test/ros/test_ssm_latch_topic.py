#!/usr/bin/env python3
"""The stop latch in automatic restart, through the node's topics, in real time.

~ssm/min_stop_time 1.5 s, stop_category 1 with halt_topic /test_halt_topic (std_msgs/Empty),
standstill_time 0.3 s, max_mute_time 0 (muting off). The joint stands still throughout
(velocity 0 on joint_states). The person stands 5 m away, comes to 0.1 m from the post for
0.3 s, and leaves again.

Checks, on the statuses' stamps (the node's clock):
- every status stamped less than 1.5 s after the stop has scale 0 and hold "min_stop_time"
  (the person left long before), and the scale rises afterwards without any reset;
- one Empty on /test_halt_topic for the stop, none before it;
- ~mute is refused with "muting is off".
"""
import os
import sys
import threading
import time
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402
from std_msgs.msg import Empty  # noqa: E402

from test_ssm_latch import FAR, NEAR, Scene  # noqa: E402
from workspace_proximity.srv import Mute  # noqa: E402
from wp_node_testlib import SsmCollector  # noqa: E402


class SsmLatchTopicTest(unittest.TestCase):
    def test_min_stop_time_and_halt_topic(self):
        halts = []
        lock = threading.Lock()

        def on_halt(_msg):
            with lock:
                halts.append(rospy.Time.now())
        halt_sub = rospy.Subscriber("/test_halt_topic", Empty, on_halt, queue_size=10)
        ssm = SsmCollector()
        scene = Scene()
        scene.joint_speed = 0.0
        deadline = time.monotonic() + 15.0
        while time.monotonic() < deadline and not (
                ssm.connected() and halt_sub.get_num_connections() >= 1 and
                scene.box_pub.get_num_connections() >= 1 and
                scene.joint_pub.get_num_connections() >= 1):
            time.sleep(0.05)
        rospy.wait_for_service("proximity_monitor/mute", 10.0)
        mute = rospy.ServiceProxy("proximity_monitor/mute", Mute)
        scene.start()
        try:
            last = lambda: ssm.statuses()[-1] if ssm.statuses() else None  # noqa: E731
            deadline = time.monotonic() + 10.0
            while time.monotonic() < deadline and not (last() is not None and last().speed_scale == 1.0):
                time.sleep(0.02)
            self.assertEqual(last().speed_scale, 1.0, "the scale never reached 1")
            r = mute(labels=["person"], ids=[], duration=1.0)
            self.assertFalse(r.success)
            self.assertIn("muting is off", r.message)
            with lock:
                self.assertEqual(halts, [], "a halt without a stop")
            scene.where = NEAR
            time.sleep(0.3)
            scene.where = FAR
            time.sleep(3.5)
            statuses = ssm.statuses()
        finally:
            scene.stop()
        stop = None
        for prev, m in zip(statuses, statuses[1:]):
            if prev.speed_scale > 0.0 and m.speed_scale == 0.0:
                self.assertIsNone(stop, "more than one stop")
                stop = m.header.stamp
        self.assertIsNotNone(stop, "no stop")
        within = [m for m in statuses if stop <= m.header.stamp < stop + rospy.Duration(1.5)]
        self.assertGreater(len(within), 15)
        for m in within:
            self.assertEqual(m.speed_scale, 0.0, "the scale rose %.3f s after the stop" %
                             (m.header.stamp - stop).to_sec())
            self.assertEqual(m.hold, "min_stop_time")
            self.assertFalse(m.reset_required)
        after = [m for m in statuses if m.header.stamp >= stop + rospy.Duration(1.5)]
        self.assertTrue(any(m.speed_scale == 1.0 for m in after), "no rise after the minimum stop time")
        self.assertTrue(all(m.hold == "" for m in after))
        with lock:
            self.assertEqual(len(halts), 1, "halts: %r" % halts)
            self.assertGreaterEqual(halts[0], stop)
        self.assertTrue(any(m.halt_requested for m in within))


if __name__ == "__main__":
    rospy.init_node("test_ssm_latch_topic")
    rostest.rosrun("workspace_proximity", "ssm_latch_topic", SsmLatchTopicTest)
