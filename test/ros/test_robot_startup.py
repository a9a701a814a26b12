#!/usr/bin/env python3
"""Start-up against an already moving robot link (issue: a moving link was predicted as
standing still for the first ~velocity_window, with status OK).

The tracker publishes a static 1 m cube at x = 2 first; then tf starts broadcasting the robot
link `carriage` (body `slider`, 1 m cube) already moving at 0.5 m/s along +x from x = -3, so
the gap is 4 - 0.5 t and the analytic time to contact 8 - t (t from the first broadcast).
With ~velocity_window = 0.5 s the node has too little tf history for about 15 cycles:
- every array in that time is DEGRADED naming "velocity not known yet", and the pair's event,
  if any, is stale;
- every array with status OK (once the window has filled) carries the pair with the analytic
  time to contact; an OK array without it, or with the link standing still, fails the test.
"""
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402

from wp_node_testlib import (END, TIME_TOL, ContactEventArray, ScenePublisher,  # noqa: E402
                             TfBroadcaster, Track, check_array_basics, connected_collector,
                             degraded_about, events_for, fmt_event)

SPEED = 0.5
X0 = -3.0
WINDOW = 0.5


class RobotStartupTest(unittest.TestCase):
    def test_moving_link_at_start_is_never_read_as_still(self):
        col = connected_collector(self)
        scene = ScenePublisher("tracked_objects", [Track("obj", "default", (2.0, 0.0, 0.0),
                                                         (1, 1, 1), (0.0, 0.0, 0.0))],
                               latency=0.05)
        scene.start(rospy.Time.now())
        rospy.sleep(1.0)
        t0 = rospy.Time.now()
        carriage = TfBroadcaster(
            "world", "carriage", lambda stamp: (X0 + SPEED * (stamp - t0).to_sec(), 0.0, 0.0))
        rospy.sleep(3.0)
        carriage.stop.set()
        carriage.thread.join(1.0)
        scene.stop()

        unknown_velocity = exact = 0
        for m in col.contact_msgs(since=t0):
            check_array_basics(self, m)
            t = (m.header.stamp - t0).to_sec()
            if t > 3.0:
                break
            evs = [e for e in events_for(m, "obj", "slider") if e.state != END]
            ctx = "t=%.3f status=%d %r %s" % (t, m.status, list(m.status_details),
                                             [fmt_event(e) for e in m.events])
            if degraded_about(m, "velocity not known yet"):
                unknown_velocity += 1
                for ev in evs:
                    self.assertTrue(ev.stale, "velocity unknown but the pair is not stale: " + ctx)
                continue
            if m.status != ContactEventArray.OK:
                continue  # before the first transform: the link is unknown
            # OK: the link's motion is known, so the prediction must be the analytic one.
            self.assertGreater(t, WINDOW - 0.05, "OK before the velocity can be known: " + ctx)
            self.assertEqual(len(evs), 1, "OK but no prediction for the approaching link: " + ctx)
            self.assertAlmostEqual(evs[0].time_to_contact, 8.0 - t, delta=TIME_TOL, msg=ctx)
            self.assertFalse(evs[0].stale, ctx)
            exact += 1
        self.assertGreaterEqual(unknown_velocity, 5, "too few arrays while the velocity was unknown")
        self.assertGreaterEqual(exact, 30, "too few exact arrays after the window")


if __name__ == "__main__":
    rospy.init_node("test_robot_startup")
    rostest.rosrun("workspace_proximity", "test_robot_startup", RobotStartupTest)
