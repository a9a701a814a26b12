#!/usr/bin/env python3
"""Rotation: a stick (2 x 0.1 x 0.1 m) centred at the origin turns about z at 0.5 rad/s from
yaw -1 rad; a wall (1 x 3 x 1 m) has its face at x = 0.95. The stick's farthest corner reaches
x = cos(yaw) + 0.05 |sin(yaw)|, which equals 0.95 at yaw = -0.371 (contact, ~1.26 s after t0)
and again at +0.371 (separation). Boxes are published with a 0.1 s latency and the
orientation of their stamp, so the node must extrapolate the orientation with the angular
twist. Checked per event against the exact values at the array's stamp: time_to_contact and
time_to_separation (1 ms), distance, normal, closing_speed (the corner's velocity along the
normal, from the angular velocity) and the nearest points.
"""
import math
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402

from wp_node_testlib import (END, TIME_TOL, Track, check_array_basics,  # noqa: E402
                             connected_collector, events_for, fmt_event, run_scene)

HORIZON = 5.0
HALF_L, HALF_W = 1.0, 0.05
FACE = 0.95
YAW0, RATE = -1.0, 0.5


def reach(yaw):
    """Largest x of the stick at this yaw."""
    return HALF_L * abs(math.cos(yaw)) + HALF_W * abs(math.sin(yaw))


def bisect(f, lo, hi):
    flo = f(lo)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if (f(mid) > 0) == (flo > 0):
            lo, flo = mid, f(mid)
        else:
            hi = mid
    return 0.5 * (lo + hi)


YAW_CONTACT = bisect(lambda y: reach(y) - FACE, -1.2, -0.06)
YAW_SEPARATE = bisect(lambda y: reach(y) - FACE, 0.06, 1.2)


class RotatingBoxTest(unittest.TestCase):
    def test_rotating_stick(self):
        self.assertAlmostEqual(YAW_CONTACT, -0.371, delta=2e-3)
        col = connected_collector(self)
        stick = Track("stick", "default", (0.0, 0.0, 0.0), (2 * HALF_L, 2 * HALF_W, 0.1),
                      yaw=YAW0, yaw_rate=RATE)
        wall = Track("wall", "default", (FACE + 0.5, 0.0, 0.0), (1.0, 3.0, 1.0))
        t0, msgs = run_scene(col, [stick, wall], 2.0, 0.3, latency=0.1)
        approach = overlap = 0
        for m in msgs:
            check_array_basics(self, m)
            dt = (m.header.stamp - t0).to_sec()
            if dt > 1.95:
                break
            yaw = YAW0 + RATE * dt
            ttc = max(0.0, (YAW_CONTACT - yaw) / RATE)
            tts = min((YAW_SEPARATE - yaw) / RATE, HORIZON)
            evs = [e for e in events_for(m, "stick", "wall") if e.state != END]
            self.assertEqual(len(evs), 1, "T-t0=%.3f: %s" % (dt, [fmt_event(e) for e in m.events]))
            ev = evs[0]
            ctx = "T-t0=%.4f yaw=%.4f %s" % (dt, yaw, fmt_event(ev))
            self.assertAlmostEqual(ev.time_to_contact, ttc, delta=TIME_TOL, msg="ttc " + ctx)
            self.assertAlmostEqual(ev.time_to_separation, tts, delta=TIME_TOL, msg="tts " + ctx)
            if ttc > 0:
                approach += 1
                # farthest corner: local (HALF_L, HALF_W) for yaw < 0
                cx = HALF_L * math.cos(yaw) - HALF_W * math.sin(yaw)
                cy = HALF_L * math.sin(yaw) + HALF_W * math.cos(yaw)
                self.assertAlmostEqual(ev.distance, FACE - cx, delta=1e-4, msg="distance " + ctx)
                self.assertAlmostEqual(ev.normal.x, 1.0, delta=1e-3, msg="normal " + ctx)
                self.assertAlmostEqual(ev.closing_speed, -RATE * cy, delta=1e-3,
                                       msg="closing_speed " + ctx)
                self.assertAlmostEqual(ev.point_a.x, cx, delta=1e-4, msg="point_a " + ctx)
                self.assertAlmostEqual(ev.point_a.y, cy, delta=1e-4, msg="point_a " + ctx)
                self.assertAlmostEqual(ev.point_b.x, FACE, delta=1e-4, msg="point_b " + ctx)
                self.assertAlmostEqual(ev.point_b.y, cy, delta=1e-4, msg="point_b " + ctx)
            else:
                overlap += 1
                self.assertLessEqual(ev.distance, 1e-6, ctx)
        self.assertGreaterEqual(approach, 12)
        self.assertGreaterEqual(overlap, 5)


if __name__ == "__main__":
    rospy.init_node("test_rotating_box")
    rostest.rosrun("workspace_proximity", "test_rotating_box", RotatingBoxTest)
