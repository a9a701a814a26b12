#!/usr/bin/env python3
"""Robot body on a moving tf frame, with a tf outage.

The test broadcasts world -> carriage at 50 Hz (stamp = now); the carriage moves along +x at
0.5 m/s and passes x = -2 at t0, 1 s after the broadcasts start (time for the connections
and for the node's tf history). Robot body "slider" (0.2 m cube on carriage) and object
"obj" (1 m cube from x = 1, moving -x at 0.2 m/s) close in: face gap 2.4 - 0.7 (T - t0),
time_to_contact = gap / 0.7 at the array's stamp T. The node has no velocity for robot
links except its tf history (~velocity_window = 0.1 s), so the numbers (1 ms, closing speed
0.7 m/s) check the estimate and the extrapolation from the latest transform to the cycle.

At t0 + 1.0 the broadcasts stop for 1.2 s. Until ~tf_timeout (0.5 s) after the last transform
the link is still extrapolated (same numbers). After it, the link is unknown: its pair stays
reported (no END: the object still approaches) and is marked stale, and the status is
DEGRADED naming "slider". When the broadcasts resume, stale and DEGRADED clear and the numbers
are exact again.
"""
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402

from wp_node_testlib import (END, TIME_TOL, ContactEventArray, ScenePublisher,  # noqa: E402
                             TfBroadcaster, Track, check_array_basics, connected_collector,
                             degraded_about, events_for, fmt_event, state_sequence)

SLIDER_SPEED = 0.5
OBJ_SPEED = 0.2
CLOSING = SLIDER_SPEED + OBJ_SPEED
X0 = -2.0
TF_TIMEOUT = 0.5


class RobotMovingTfTest(unittest.TestCase):
    def test_moving_robot_link(self):
        col = connected_collector(self)
        # t0 lies 1 s ahead: the publishers connect and the node gathers tf history first.
        t0 = rospy.Time.now() + rospy.Duration(1.0)
        carriage = TfBroadcaster(
            "world", "carriage", lambda stamp: (X0 + SLIDER_SPEED * (stamp - t0).to_sec(), 0.0, 0.0))
        obj = Track("obj", "default", (1.0, 0.0, 0.0), (1, 1, 1), (-OBJ_SPEED, 0.0, 0.0))
        scene = ScenePublisher("tracked_objects", [obj], latency=0.05)
        scene.start(t0)
        rospy.sleep((t0 - rospy.Time.now()).to_sec() + 1.0)
        carriage.paused.set()
        rospy.sleep(0.05)
        last_tf = carriage.last_stamp
        rospy.sleep(1.15)
        resumed = rospy.Time.now()
        carriage.paused.clear()
        rospy.sleep(0.8)
        end = rospy.Time.now()
        carriage.stop.set()
        carriage.thread.join(1.0)
        scene.stop()

        msgs = [m for m in col.contact_msgs(since=t0) if m.header.stamp <= end]
        exact = stale = fresh_again = 0
        for m in msgs:
            check_array_basics(self, m)
            dt = (m.header.stamp - t0).to_sec()
            for ev in m.events:
                self.assertEqual((ev.id_a, ev.id_b, ev.label_a, ev.label_b),
                                 ("obj", "slider", "default", "robot"), fmt_event(ev))
            evs = [e for e in events_for(m, "obj", "slider") if e.state != END]
            self.assertEqual(len(evs), 1, "T-t0=%.3f: no event for (obj, slider): %s" % (
                dt, [fmt_event(e) for e in m.events]))
            ev = evs[0]
            ctx = "T-t0=%.4f %s status=%d %r" % (dt, fmt_event(ev), m.status, m.status_details)
            since_tf = (m.header.stamp - last_tf).to_sec()
            since_resume = (m.header.stamp - resumed).to_sec()
            if since_tf < TF_TIMEOUT - 0.05 or since_resume > 0.3:
                # posed from tf (extrapolated from the latest transform)
                gap = 2.4 - CLOSING * dt
                self.assertAlmostEqual(ev.time_to_contact, gap / CLOSING, delta=TIME_TOL,
                                       msg=ctx)
                self.assertAlmostEqual(ev.time_to_separation, (gap + 1.2) / CLOSING,
                                       delta=TIME_TOL, msg=ctx)
                self.assertAlmostEqual(ev.distance, gap, delta=1e-3, msg=ctx)
                self.assertAlmostEqual(ev.normal.x, -1.0, delta=1e-3, msg=ctx)
                self.assertAlmostEqual(ev.closing_speed, CLOSING, delta=1e-2, msg=ctx)
                self.assertFalse(ev.stale, ctx)
                self.assertEqual(m.status, ContactEventArray.OK, ctx)
                exact += 1
                if since_resume > 0.3:
                    fresh_again += 1
            elif since_tf > TF_TIMEOUT + 0.1 and since_resume < 0.0:
                self.assertTrue(ev.stale, "link unknown but pair not stale: " + ctx)
                self.assertTrue(degraded_about(m, "slider"), "status: " + ctx)
                stale += 1
        self.assertGreaterEqual(exact, 20, "too few exact events checked")
        self.assertGreaterEqual(stale, 6, "too few stale events checked")
        self.assertGreaterEqual(fresh_again, 4, "too few events checked after the outage")
        seq = state_sequence(col.contact_msgs(), "obj", "slider")
        self.assertRegex(seq, r"^\.*BO+E?\.*$", "state sequence of (obj, slider): " + seq)


if __name__ == "__main__":
    rospy.init_node("test_robot_moving_tf")
    rostest.rosrun("workspace_proximity", "test_robot_moving_tf", RobotMovingTfTest)
