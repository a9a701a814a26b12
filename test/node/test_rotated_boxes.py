#!/usr/bin/env python3
"""Rotated boxes: overlapping axis-aligned bounds, no contact.

Scene 1 (z = 0): two parallel sticks 3 x 0.2 x 0.2 m, both yawed 45 degrees, 0.3 m apart
across their axis; one slides along its own axis at 0.5 m/s. Their bounding boxes overlap
(also per axis over the whole horizon) but the sticks never touch.
Scene 2 (z = 50): a 1 m cube and a stick yawed -45 degrees lying 0.15 m off the cube's
vertical edge, sliding along its axis at 0.5 m/s: bounds overlap, never touch.
Controls (z = 100 and z = 150): the same two pairs, the stick moving towards the other body
across its axis (0.1 and 0.05 m/s, both touching 3.0 s after t0): events with analytic
time_to_contact (1 ms), distance, normal, closing_speed and nearest points.
"""
import math
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402

from wp_node_testlib import (END, TIME_TOL, Track, check_array_basics,  # noqa: E402
                             connected_collector, events_for, fmt_event, pt, quat_from_rpy,
                             run_scene, vadd, vdot, vscale)

HORIZON = 5.0
S = 1.0 / math.sqrt(2.0)
U = (S, S, 0.0)     # axis of the +45 degree sticks
N = (S, -S, 0.0)    # across them
CUBE_GAP = 0.15
C = S + 0.1 + CUBE_GAP   # distance of the -45 degree stick's centre from the cube centre


class RotatedBoxesTest(unittest.TestCase):
    def check_closing(self, ev, dt, initial_gap, speed, normal):
        """A control pair closing at `speed` along `normal` from `initial_gap` at t0, seen dt
        later: never END, time, separation, distance, normal and speed analytic. Returns the
        gap now and a context string for further checks."""
        self.assertNotEqual(ev.state, END, fmt_event(ev))
        gap = initial_gap - speed * dt
        ctx = "T-t0=%.4f %s" % (dt, fmt_event(ev))
        self.assertAlmostEqual(ev.time_to_contact, gap / speed, delta=TIME_TOL, msg=ctx)
        self.assertAlmostEqual(ev.time_to_separation, HORIZON, delta=TIME_TOL, msg=ctx)
        self.assertAlmostEqual(ev.distance, gap, delta=1e-4, msg=ctx)
        for k in range(3):
            self.assertAlmostEqual(pt(ev.normal)[k], normal[k], delta=1e-3, msg=ctx)
        self.assertAlmostEqual(ev.closing_speed, speed, delta=1e-3, msg=ctx)
        return gap, ctx

    def test_rotated_boxes(self):
        col = connected_collector(self)
        q45 = quat_from_rpy(0, 0, math.pi / 4)
        qm45 = quat_from_rpy(0, 0, -math.pi / 4)
        stick = (3.0, 0.2, 0.2)

        def z(h):
            return (0.0, 0.0, h)

        tracks = [
            Track("stick_a", "default", z(0), stick, quat=q45),
            Track("stick_b", "default", vscale(N, 0.5), stick, vscale(U, 0.5), quat=q45),
            Track("cube_c", "default", z(50), (1, 1, 1)),
            Track("stick_d", "default", vadd(vscale(U, C), z(50)), stick, vscale(N, 0.5),
                  quat=qm45),
            Track("ctl_a1", "default", z(100), stick, quat=q45),
            Track("ctl_b1", "default", vadd(vscale(N, 0.5), z(100)), stick, vscale(N, -0.1),
                  quat=q45),
            Track("ctl_cube", "default", z(150), (1, 1, 1)),
            Track("ctl_stick", "default", vadd(vscale(U, C), z(150)), stick, vscale(U, -0.05),
                  quat=qm45),
        ]
        t0, msgs = run_scene(col, tracks, 2.2, 0.3)
        self.assertGreater(len(msgs), 25)
        checked = {"sticks": 0, "cube": 0}
        for m in msgs:
            check_array_basics(self, m)
            dt = (m.header.stamp - t0).to_sec()
            for ev in m.events:
                self.assertIn((ev.id_a, ev.id_b), [("ctl_a1", "ctl_b1"), ("ctl_cube", "ctl_stick")],
                              "unexpected event at T-t0=%.3f: %s" % (dt, fmt_event(ev)))
            if dt > 2.0:
                continue
            for ev in events_for(m, "ctl_a1", "ctl_b1"):
                gap, ctx = self.check_closing(ev, dt, 0.3, 0.1, N)
                self.assertAlmostEqual(vdot(pt(ev.point_a), N), 0.1, delta=1e-4, msg=ctx)
                self.assertAlmostEqual(vdot(pt(ev.point_b), N), 0.1 + gap, delta=1e-4, msg=ctx)
                checked["sticks"] += 1
            for ev in events_for(m, "ctl_cube", "ctl_stick"):
                gap, ctx = self.check_closing(ev, dt, CUBE_GAP, 0.05, U)
                # The cube's nearest point lies on its vertical edge x = y = 0.5.
                self.assertAlmostEqual(ev.point_a.x, 0.5, delta=1e-4, msg=ctx)
                self.assertAlmostEqual(ev.point_a.y, 0.5, delta=1e-4, msg=ctx)
                self.assertAlmostEqual(vdot(pt(ev.point_b), U), S + gap, delta=1e-4, msg=ctx)
                checked["cube"] += 1
        self.assertGreaterEqual(checked["sticks"], 20, "control pair of sticks: %r" % checked)
        self.assertGreaterEqual(checked["cube"], 20, "control pair cube-stick: %r" % checked)


if __name__ == "__main__":
    rospy.init_node("test_rotated_boxes")
    rostest.rosrun("workspace_proximity", "test_rotated_boxes", RotatedBoxesTest)
