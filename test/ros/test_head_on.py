#!/usr/bin/env python3
"""Head-on approach: two 1 m cubes 4 m apart closing at 2 m/s touch 2.0 s after t0.

The boxes are published with a 0.1 s sensor latency (stamp = now - 0.1 s) and positions that
match their stamps, so every event must agree with the analytic answer computed for the
event array's own header.stamp: time_to_contact within 1 ms, and distance, normal, nearest
points, closing_speed and time_to_separation likewise. The scene runs on past the contact into
overlap (time_to_contact = 0, distance = 0), then stops being published: the pair is marked
stale once the tracks' stamps are older than ~stale_after (0.25 s), then ENDs when they time
out. While every input is fresh the array's status is OK and no event is stale.
"""
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402

from wp_node_testlib import (BEGIN, END, TIME_TOL, ContactEventArray, ScenePublisher,  # noqa: E402
                             Track, aabb_prediction, check_array_basics, check_face_contact,
                             connected_collector, events_for, expected_level, fmt_event,
                             node_labels, state_sequence)

HORIZON = 10.0


class HeadOnTest(unittest.TestCase):
    def test_head_on_analytic(self):
        col = connected_collector(self)
        half = (0.5, 0.5, 0.5)
        thresholds = node_labels()["default"]
        a = Track("a", "default", (-2.5, 0.3, 1.0), (1, 1, 1), (1.0, 0.0, 0.0))
        b = Track("b", "default", (2.5, 0.3, 1.0), (1, 1, 1), (-1.0, 0.0, 0.0))
        scene = ScenePublisher("tracked_objects", [a, b], latency=0.1)
        t0 = scene.start()
        rospy.sleep(2.6)           # contact at t0 + 2.0, then 0.6 s of overlap
        scene.stop()
        last_stamp = scene.last_stamp["a"]
        rospy.sleep(1.2)           # tracks time out -> END
        msgs = col.contact_msgs(since=t0)
        self.assertGreater(len(msgs), 40, "too few contact arrays: %d" % len(msgs))

        approach = overlap = stale = 0
        for m in msgs:
            check_array_basics(self, m)
            T = m.header.stamp
            age = (T - last_stamp).to_sec()   # > 0: after the last message's stamp
            if (T - t0).to_sec() > 0.5 and age < 0.0:
                self.assertEqual(m.status, ContactEventArray.OK,
                                 "status while all inputs are fresh: %r" % m.status_details)
            others = [e for e in m.events if (e.id_a, e.id_b) != ("a", "b")]
            self.assertEqual(others, [], "unexpected events: %s" % [fmt_event(e) for e in others])
            for ev in events_for(m, "a", "b"):
                self.assertEqual((ev.label_a, ev.label_b), ("default", "default"))
                if ev.state == END:
                    continue
                # stale: the tracks' stamps are older than ~stale_after (0.25 s)
                if age < -0.05:
                    self.assertFalse(ev.stale, "stale while published: " + fmt_event(ev))
                elif age > 0.26:
                    self.assertTrue(ev.stale, "not stale %.3f s after the last stamp: %s" % (
                        age, fmt_event(ev)))
                    stale += 1
                ca, va = a.state(T)
                cb, vb = b.state(T)
                exp = aabb_prediction(ca, half, va, cb, half, vb, HORIZON)
                self.assertIsNotNone(exp, "event although no contact is possible at "
                                     "T-t0=%.3f: %s" % ((T - t0).to_sec(), fmt_event(ev)))
                # The analytic contact: gap 4 m closing at 2 m/s from t0, separation at t0+3.
                dt = (T - t0).to_sec()
                self.assertAlmostEqual(exp["ttc"], max(0.0, 2.0 - dt), delta=1e-9)
                self.assertAlmostEqual(exp["tts"], min(3.0 - dt, HORIZON), delta=1e-9)
                check_face_contact(self, ev, exp, ca, half, cb, half,
                                   "T-t0=%.4f" % dt)
                if exp["distance"] > 0:
                    approach += 1
                    self.assertAlmostEqual(ev.normal.x, 1.0, delta=1e-3)
                    self.assertAlmostEqual(ev.closing_speed, 2.0, delta=1e-3)
                else:
                    overlap += 1
                    self.assertLessEqual(ev.time_to_contact, TIME_TOL, fmt_event(ev))
                    self.assertLessEqual(ev.distance, 1e-4, fmt_event(ev))
                lvl = expected_level(exp["ttc"], exp["distance"], thresholds)
                if lvl is not None:
                    self.assertEqual(ev.level, lvl, "level of " + fmt_event(ev))
        self.assertGreaterEqual(approach, 20, "too few approach-phase events checked")
        self.assertGreaterEqual(overlap, 5, "too few overlap-phase events checked")
        self.assertGreaterEqual(stale, 2, "too few stale events checked")

        seq = state_sequence(msgs, "a", "b")
        self.assertRegex(seq, r"^\.*BO+E\.*$", "state sequence of pair (a, b): " + seq)
        first = next(m for m in msgs if events_for(m, "a", "b"))
        self.assertEqual(events_for(first, "a", "b")[0].state, BEGIN)


if __name__ == "__main__":
    rospy.init_node("test_head_on")
    rostest.rosrun("workspace_proximity", "test_head_on", HeadOnTest)
