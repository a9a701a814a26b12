#!/usr/bin/env python3
"""BEGIN -> ONGOING -> END -> BEGIN -> ONGOING -> END over one scene, horizon 2 s.

Boxes are published in frame "tracker": static tf world -> tracker = translation (10, 0, 0),
yaw 90 degrees, so tracker x is world y. Box "box_a" (1 m cube) rests at the tracker origin;
"box_b" (1 m cube) starts 3 m away (tracker x = -4) and moves:
  t0 .. t0+1.8  towards a at 1 m/s   (time to contact 3 - t: enters the horizon at t0 + 1.0)
  t0+1.8 .. 2.5 away at 1 m/s        (END on the first cycle that sees it)
  t0+2.5 .. 3.0 towards a at 2 m/s   (gap 1.9 m: BEGIN again at once)
then stops being published (track timeout -> END). Every cycle away from the velocity
switches is compared with the exact prediction in world coordinates.
"""
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402

from wp_node_testlib import (BEGIN, PlanarTransformed, ScenePublisher, Track,  # noqa: E402
                             broadcast_static, check_array_basics, check_scene_events,
                             connected_collector, events_for, state_sequence)

HORIZON = 2.0
LATENCY = 0.05


class EventLifecycleTest(unittest.TestCase):
    def test_begin_ongoing_end(self):
        tf_pub = broadcast_static([("world", "tracker", (10.0, 0.0, 0.0),
                                    (0.0, 0.0, 1.5707963267948966))])
        col = connected_collector(self)
        a = Track("box_a", "default", (0.0, 0.0, 0.0), (1, 1, 1))
        b = Track("box_b", "default", (-4.0, 0.0, 0.0), (1, 1, 1), (1.0, 0.0, 0.0))
        scene = ScenePublisher("tracked_objects", [a, b], frame_id="tracker", latency=LATENCY)
        t0 = scene.start()

        def at(dt):
            return t0 + rospy.Duration(dt)

        def sleep_until(dt):
            rospy.sleep(max(0.0, (at(dt) - rospy.Time.now()).to_sec()))

        sleep_until(1.8 + 0.01)
        scene.set_velocity(b, at(1.8), (-1.0, 0.0, 0.0))
        sleep_until(2.5 + 0.01)
        scene.set_velocity(b, at(2.5), (2.0, 0.0, 0.0))
        sleep_until(3.0)
        scene.stop()
        rospy.sleep(1.2)
        msgs = col.contact_msgs(since=at(0.2))

        world = [PlanarTransformed(t, (10.0, 0.0, 0.0), 1) for t in (a, b)]
        checked = 0
        for m in msgs:
            check_array_basics(self, m)
            dt = (m.header.stamp - t0).to_sec()
            near_switch = any(s - 0.02 <= dt <= s + 0.25 for s in (1.8, 2.5))
            if dt <= 3.0 and not near_switch:
                checked += check_scene_events(self, m, world, HORIZON)
        self.assertGreaterEqual(checked, 15, "too few events checked")

        seq = state_sequence(msgs, "box_a", "box_b")
        self.assertRegex(seq, r"^\.+BO+E\.+BO+E\.*$", "state sequence: " + seq)
        first = next(m for m in msgs if events_for(m, "box_a", "box_b"))
        begin_dt = (first.header.stamp - t0).to_sec()
        self.assertEqual(events_for(first, "box_a", "box_b")[0].state, BEGIN)
        self.assertTrue(0.94 <= begin_dt <= 1.12,
                        "first BEGIN at t0 + %.3f s, expected when the time to contact "
                        "reaches the 2 s horizon at t0 + 1.0 s" % begin_dt)
        del tf_pub


if __name__ == "__main__":
    rospy.init_node("test_event_lifecycle")
    rostest.rosrun("workspace_proximity", "test_event_lifecycle", EventLifecycleTest)
