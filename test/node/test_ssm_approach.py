#!/usr/bin/env python3
"""Speed and separation monitoring: walking at the robot, standing beside it, walking away.

The robot is one static box, "post" (1 m cube, x in [-0.5, 0.5], on base_link = world). A
person (0.5 x 0.5 x 1.8 m box, label "person", margin 0) starts 4 m from its face and
  A  walks straight at it at 1 m/s for 3.8 s (d = 4 - t),
  B  stands still 0.2 m from it for 1.5 s,
  C  walks away at 0.5 m/s (d = 0.2 + 0.5 (t - 5.3)).
The monitor runs with the issue's defaults: T_r 0.1 s, T_s 0.3 s, C 0.1 m, Z_d 0.1 m,
Z_r 0.02 m, v_max 1 m/s, so S_p(v_r) = 0.4 v_h + 0.25 v_r + 0.22 and the raw scale is
clamp((d - 0.4 v_h - 0.22) / 0.25, 0, 1), with v_h = 1 m/s in A and 0 in B and C.

Checks, on every safety_status the node publishes (stamp T = the cycle's instant, d from the
person's known position at T; cycles within 0.15 s after a change of velocity are skipped,
since the node extrapolates the last array over it):
- raw_scale equals the formula within 0.01, and the limiting pair is (post, p1) with
  separation d (1 mm), approach speed v_h and S_p(v_max) once d <= S_p(v_max);
- where S_p(v_max... 0) > d the scale is 0: protective_stop, speed_scale 0;
- standing still 0.2 m away (d < C + Z_d + Z_r = 0.22 m): scale 0 although no contact is
  predicted (no event for the pair in the contacts arrays of phase B after its END);
- walking away the scale comes from the distance alone (v_h = 0);
- hysteresis: speed_scale never exceeds raw_scale, follows it down at once, stays 0 until the
  raw scale has been above it for hold_time (0.5 s) and then rises by exactly 0.5 per second
  of cycle time (at most one cycle's worth, 0.025, off) until it meets the raw scale;
- speed_scale (Float64) carries safety_status.speed_scale and speed_override (Int64)
  round(100 x speed_scale), cycle by cycle.
"""
import math
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402

from wp_node_testlib import (END, SafetyStatus, ScenePublisher, SsmCollector, Track,  # noqa: E402
                             aligned, broadcast_static, connected_collector, events_for,
                             ssm_required, ssm_scale)

HOLD = 0.5
RATE = 0.5
PERIOD = 0.05        # the node's 20 Hz
T_STOP = 3.8         # A -> B
T_AWAY = 5.3         # B -> C
T_END = 8.5


class SsmApproachTest(unittest.TestCase):
    def test_approach_stand_leave(self):
        tf_pub = broadcast_static([("world", "base_link", (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))])
        ssm = SsmCollector()
        col = connected_collector(self)
        person = Track("p1", "person", (0.5 + 0.25 + 4.0, 0.0, 0.9), (0.5, 0.5, 1.8),
                       (-1.0, 0.0, 0.0))
        scene = ScenePublisher("tracked_objects", [person], latency=0.05)
        t0 = scene.start()
        rospy.sleep((t0 + rospy.Duration(T_STOP) - rospy.Time.now()).to_sec())
        scene.set_velocity(person, t0 + rospy.Duration(T_STOP), (0.0, 0.0, 0.0))
        rospy.sleep((t0 + rospy.Duration(T_AWAY) - rospy.Time.now()).to_sec())
        scene.set_velocity(person, t0 + rospy.Duration(T_AWAY), (0.5, 0.0, 0.0))
        rospy.sleep((t0 + rospy.Duration(T_END) - rospy.Time.now()).to_sec())
        scene.stop()
        rospy.sleep(0.3)

        def gap(stamp):
            (x, _, _), _ = person.state(stamp)
            return max(0.0, x - 0.25 - 0.5)

        def phase(t):
            return "A" if t < T_STOP else ("B" if t < T_AWAY else "C")

        statuses = [m for m in ssm.statuses(since=t0 + rospy.Duration(0.3))
                    if m.header.stamp <= t0 + rospy.Duration(T_END - 0.1)]
        self.assertGreater(len(statuses), 120, "too few safety_status messages: %d" % len(statuses))
        checked = {"A": 0, "B": 0, "C": 0}
        stopped = 0
        prev = None
        first_above = None   # cycle instant from which the raw scale stays above the output
        held_zero = rising = 0
        for m in statuses:
            t = (m.header.stamp - t0).to_sec()
            ctx = "t=%.3f %s: raw %.4f scale %.4f %s-%s d %.4f S_p %.4f v_h %.3f status %d %r" % (
                t, phase(t), m.raw_scale, m.speed_scale, m.id_robot, m.id_object, m.separation,
                m.required_separation, m.approach_speed, m.status, m.reason)
            self.assertEqual(m.header.frame_id, "world")
            self.assertEqual(m.status, SafetyStatus.OK, ctx)
            self.assertTrue(0.0 <= m.speed_scale <= 1.0 and 0.0 <= m.raw_scale <= 1.0, ctx)
            self.assertEqual(m.protective_stop, m.speed_scale == 0.0, ctx)
            # The hysteresis, on every cycle: never above the raw scale, down at once, up only
            # after the hold and at the rate.
            self.assertLessEqual(m.speed_scale, m.raw_scale + 1e-12, ctx)
            if prev is not None:
                dt = (m.header.stamp - prev.header.stamp).to_sec()
                self.assertLessEqual(m.speed_scale - prev.speed_scale, RATE * dt + 1e-9, ctx)
                if m.raw_scale <= prev.speed_scale:
                    self.assertEqual(m.speed_scale, m.raw_scale, "did not drop at once: " + ctx)
            if m.raw_scale > m.speed_scale or (prev is not None and m.speed_scale > prev.speed_scale):
                if first_above is None:
                    first_above = m.header.stamp
            else:
                first_above = None
            if phase(t) == "C" and first_above is not None:
                since = (m.header.stamp - first_above).to_sec()
                if since < HOLD - 1e-6:
                    self.assertEqual(m.speed_scale, 0.0, "rose before the hold: " + ctx)
                    held_zero += 1
                else:
                    want = min(m.raw_scale, RATE * (since - HOLD))
                    self.assertAlmostEqual(m.speed_scale, want, delta=RATE * PERIOD + 1e-6,
                                           msg="rise after the hold (%.3f s): " % since + ctx)
                    rising += m.speed_scale < m.raw_scale
            prev = m

            # The formula from the known geometry, away from the changes of velocity.
            if T_STOP <= t < T_STOP + 0.15 or T_AWAY <= t < T_AWAY + 0.15:
                continue
            d = gap(m.header.stamp)
            v_h = 1.0 if phase(t) == "A" else 0.0
            expected = ssm_scale(d, v_h)
            self.assertAlmostEqual(m.raw_scale, expected, delta=0.01, msg="formula: " + ctx)
            full_speed_needs = ssm_required(v_h, 1.0)
            if d <= full_speed_needs - 0.01:
                self.assertEqual((m.id_robot, m.id_object), ("post", "p1"), ctx)
                self.assertAlmostEqual(m.separation, d, delta=1e-3, msg=ctx)
                self.assertAlmostEqual(m.approach_speed, v_h, delta=1e-6, msg=ctx)
                self.assertAlmostEqual(m.required_separation, full_speed_needs, delta=1e-6, msg=ctx)
            if ssm_required(v_h, 0.0) > d + 0.01:  # even a standing robot is too close
                self.assertEqual(m.raw_scale, 0.0, ctx)
                self.assertEqual(m.speed_scale, 0.0, ctx)
                self.assertTrue(m.protective_stop, ctx)
                stopped += 1
            checked[phase(t)] += 1
        self.assertGreater(checked["A"], 50, checked)
        self.assertGreater(checked["B"], 20, checked)
        self.assertGreater(checked["C"], 40, checked)
        self.assertGreater(stopped, 30, "too few protective stops checked")
        self.assertGreaterEqual(held_zero, 8, "too few cycles checked in the hold")
        self.assertGreaterEqual(rising, 20, "too few cycles checked while rising")
        self.assertEqual(statuses[-1].speed_scale, 1.0, "back to full speed at the end")

        # Standing still: no contact is predicted (after the pair's END), yet the robot stops.
        standing = [m for m in col.contact_msgs(since=t0 + rospy.Duration(T_STOP + 0.3))
                    if m.header.stamp < t0 + rospy.Duration(T_AWAY)]
        self.assertGreater(len(standing), 15)
        for m in standing:
            live = [e for e in events_for(m, "p1", "post") if e.state != END]
            self.assertEqual(live, [], "contact predicted while standing still")

        # The Float64 and Int64 outputs, cycle by cycle.
        status, scale, override = ssm.sequences()
        self.assertIsNotNone(aligned([m.speed_scale for m in status], scale, lambda a, b: a == b),
                             "speed_scale does not carry safety_status.speed_scale")
        # round() half away from zero (the scale is never negative)
        self.assertIsNotNone(aligned(scale, override, lambda s, o: o == math.floor(100.0 * s + 0.5)),
                             "speed_override is not round(100 x speed_scale)")
        self.assertIn(0, override)
        self.assertIn(100, override)
        self.assertTrue(any(0 < o < 100 for o in override))
        del tf_pub


if __name__ == "__main__":
    rospy.init_node("test_ssm_approach")
    rostest.rosrun("workspace_proximity", "test_ssm_approach", SsmApproachTest)
