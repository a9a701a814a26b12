#!/usr/bin/env python3
"""A revolute joint swings a link onto a box on its arc, the link posed from joint_states.

Joint "swing" turns at 0.5 rad/s from 0 (t0); the box stands on the arc at 1 rad, so the
analytic first contact is at contact_angle(1.0) / 0.5 = 1.5425 s. The joint states carry no
velocity (finite differences) and the second comes 0.2 s after the first: until then the
link is stale (DEGRADED, "velocity ... not known"), never read as standing still. Then every OK array must carry the pair with time_to_contact within 5 ms of
the analytic value and never later. Straight-line extrapolation of the link's box from t0
(checked here by dense sampling) would say 2.00 s: more than 0.3 s late.
Joint "stopper" turns the same way at z = 2 but stops at its limit 0.6 rad (the publisher
holds it there, as the robot would), short of its box at 1 rad (contact at 0.771 rad): no
prediction may ever put it in contact.
After 1.2 s the joint states stop: once they are older than ~tf_timeout (0.5 s) the arrays
are DEGRADED naming the joint state and the arm's pair is stale.
"""
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402

from wp_joint_testlib import (OBJ_HALF, OBJ_R, OMEGA, JointStatePublisher,  # noqa: E402
                              contact_angle, straight_line_contact)
from wp_node_testlib import (END, ContactEventArray, ScenePublisher, Track,  # noqa: E402
                             check_array_basics, connected_collector, degraded_about, events_for,
                             fmt_event)

import math  # noqa: E402

PHI = 1.0
EARLY_TOL = 0.005  # s: the keyframes' bound (joint_path_tolerance 1 mm) makes it early, never late
LATE_TOL = 0.001   # s: stamps and float rounding
LIMIT = 0.6


def box_on_arc(box_id, z):
    return Track(box_id, "default", (OBJ_R * math.cos(PHI), OBJ_R * math.sin(PHI), z),
                 (2 * OBJ_HALF, 2 * OBJ_HALF, 0.1), yaw=PHI)


class JointSwingTest(unittest.TestCase):
    def test_swing_onto_a_box(self):
        t_contact = contact_angle(PHI) / OMEGA
        line = straight_line_contact(0.0, PHI)
        self.assertGreater(line - t_contact, 0.3, "the scene must tell the arc from the line")
        self.assertLess(contact_angle(PHI), PHI)
        self.assertGreater(contact_angle(PHI), LIMIT, "the stopped arm must stay clear")

        col = connected_collector(self)
        scene = ScenePublisher("tracked_objects", [box_on_arc("obj", 0.0), box_on_arc("obj2", 2.0)],
                               latency=0.05)
        scene.start(rospy.Time.now())
        rospy.sleep(1.0)
        # No joint state yet: the arm is unknown, the status DEGRADED.
        before = col.contact_msgs(since=rospy.Time.now() - rospy.Duration(0.5))
        self.assertTrue(before)
        for m in before:
            self.assertTrue(degraded_about(m, "no joint state"), "%r" % list(m.status_details))

        t0 = [None]

        def positions(stamp):
            if t0[0] is None:
                t0[0] = stamp
            t = (stamp - t0[0]).to_sec()
            return {"swing": (OMEGA * t, OMEGA),
                    "stopper": (min(LIMIT, OMEGA * t), OMEGA if OMEGA * t < LIMIT else 0.0)}

        joints = JointStatePublisher(positions, with_velocity=False, first_pause=0.2)
        self.assertTrue(joints.wait_connected(), "the node does not subscribe joint_states")
        joints.start()
        rospy.sleep(1.2)
        joints.halt()
        last = joints.last_stamp
        rospy.sleep(1.2)
        scene.stop()

        stale_velocity = exact = lost = 0
        for m in col.contact_msgs(since=t0[0]):
            check_array_basics(self, m)
            t = (m.header.stamp - t0[0]).to_sec()
            ctx = "t=%.3f status=%d %r %s" % (t, m.status, list(m.status_details),
                                             [fmt_event(e) for e in m.events])
            for ev in events_for(m, "arm2", "obj2") + events_for(m, "obj2", "arm2"):
                self.assertTrue(ev.state == END or ev.stale,
                                "the arm stopped at its limit is predicted in contact: " + ctx)
            evs = [e for e in events_for(m, "arm", "obj") + events_for(m, "obj", "arm") if e.state != END]
            if (m.header.stamp - last).to_sec() > 0.5 + 0.06:
                self.assertTrue(degraded_about(m, "joint state of 'swing'"), ctx)
                for ev in evs:
                    self.assertTrue(ev.stale, "joint states stopped but the pair is not stale: " + ctx)
                lost += 1
                continue
            if m.header.stamp > last:
                continue  # the joint states may or may not be stale yet
            if degraded_about(m, "not known"):
                stale_velocity += 1
                for ev in evs:
                    self.assertTrue(ev.stale, "velocity unknown but the pair is not stale: " + ctx)
                continue
            self.assertEqual(m.status, ContactEventArray.OK, ctx)
            self.assertEqual(len(evs), 1, "no prediction for the swinging link: " + ctx)
            expected = t_contact - t
            ttc = evs[0].time_to_contact
            self.assertFalse(evs[0].stale, ctx)
            self.assertLessEqual(ttc, expected + LATE_TOL, "late: expected %.4f: %s" % (expected, ctx))
            self.assertGreaterEqual(ttc, expected - EARLY_TOL, "expected %.4f: %s" % (expected, ctx))
            exact += 1
        self.assertGreaterEqual(stale_velocity, 1, "the first reading must leave the link stale")
        self.assertGreaterEqual(exact, 15, "too few predictions while the arm swung")
        self.assertGreaterEqual(lost, 5, "too few arrays after the joint states stopped")


if __name__ == "__main__":
    rospy.init_node("test_joint_swing")
    rostest.rosrun("workspace_proximity", "test_joint_swing", JointSwingTest)
