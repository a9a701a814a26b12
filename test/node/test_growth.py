#!/usr/bin/env python3
"""Growing margins through the node's topics. A static robot "pillar" (1 x 1 x 2 m, faces at
x, y = +-0.5) and 1 m cubes standing still around it, all margins 0. A label's growth is
R(s) = min(e s + a s^2 / 2, (v_max + |v|) s), s counted from the box's measurement stamp S,
so the grown cube first touches the pillar at the instant S + T with R(T) = face gap:
  p (person: e = 1.6 m/s), gap 1.6 m              -> T = 1.6 / 1.6 = 1.0 s
  r (runner: a = 2 m/s^2), gap 1.0 m              -> T = sqrt(2 * 1.0 / 2) = 1.0 s
  c (capped: a = 4 m/s^2, v_max = 1 m/s), gap 1.5 -> R = min(2 s^2, s): T = 1.5 s
                                                     (0.87 s without the cap)
  s (default: no growth), gap 0.3 m               -> never
  w (default), gap 2.5 m approaching at 1 m/s     -> t0 + 2.5 s, constant velocity as before
Each published array re-measures the standing cubes, so a cycle's prediction counts from the
stamp of the array the node used: the predicted instant (header.stamp + time_to_contact)
must be S + T for one of the published stamps S (within 2 ms; the array's period is 50 ms),
never later, and the distance then is gap - R(header.stamp - S) for that same S.
"""
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402

from wp_node_testlib import (END, ScenePublisher, Track, broadcast_static,  # noqa: E402
                             checked_arrays, connected_collector, fmt_event)

MATCH_TOL = 2e-3   # s: which published stamp the node used
LATE_TOL = 1e-6    # s: never late (the narrow phase stops within 1e-5 m, i.e. early)
DIST_TOL = 1e-4    # m


def growth(e, a, cap, s):
    r = e * s + 0.5 * a * s * s
    return min(r, cap * s) if cap is not None else r


class RecordingPublisher(ScenePublisher):
    """A ScenePublisher that remembers every stamp it sent."""

    def __init__(self, *args, **kwargs):
        ScenePublisher.__init__(self, *args, **kwargs)
        self.stamps = []

    def publish_once(self):
        ScenePublisher.publish_once(self)
        with self.lock:
            self.stamps.append(self.last_stamp["p"])


class GrowthTest(unittest.TestCase):
    def test_growth(self):
        tf_pub = broadcast_static([("world", "base_link", (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))])
        col = connected_collector(self)
        cube = (1.0, 1.0, 1.0)
        tracks = [
            Track("p", "person", (0.5 + 1.6 + 0.5, 0.0, 1.0), cube),
            Track("r", "runner", (-(0.5 + 1.0 + 0.5), 0.0, 1.0), cube),
            Track("c", "capped", (0.0, 0.5 + 1.5 + 0.5, 1.0), cube),
            Track("s", "default", (0.0, -(0.5 + 0.3 + 0.5), 1.0), cube),
            Track("w", "default", (0.0, -(0.5 + 2.5 + 0.5), 1.0), cube, (0.0, 1.0, 0.0)),
        ]
        # (first contact T after the stamp, face gap, e, a, speed cap)
        standing = {"p": (1.0, 1.6, 1.6, 0.0, None),
                    "r": (1.0, 1.0, 0.0, 2.0, None),
                    "c": (1.5, 1.5, 0.0, 4.0, 1.0)}
        scene = RecordingPublisher("tracked_objects", tracks, latency=0.05)
        t0 = scene.start()
        rospy.sleep(1.2)
        scene.stop()
        stamps = list(scene.stamps)
        msgs = col.contact_msgs(since=t0 + rospy.Duration(0.3))
        self.assertGreaterEqual(len(msgs), 10)
        checked = {"p": 0, "r": 0, "c": 0, "w": 0}
        for m in checked_arrays(self, msgs, t0, 1.1):
            ids = set()
            for ev in m.events:
                self.assertIn("pillar", (ev.id_a, ev.id_b), fmt_event(ev))
                other = ev.id_b if ev.id_a == "pillar" else ev.id_a
                self.assertNotEqual(ev.state, END, fmt_event(ev))
                ids.add(other)
                predicted = m.header.stamp + rospy.Duration(ev.time_to_contact)
                if other == "w":
                    # Default settings: today's constant-velocity contact at t0 + 2.5 s.
                    self.assertAlmostEqual((predicted - t0).to_sec(), 2.5, delta=1e-3,
                                           msg=fmt_event(ev))
                    checked["w"] += 1
                    continue
                self.assertIn(other, standing, fmt_event(ev))
                t, gap, e, a, cap = standing[other]
                used = min(stamps, key=lambda s: abs((predicted - s).to_sec() - t))
                off = (predicted - used).to_sec() - t
                self.assertLessEqual(abs(off), MATCH_TOL,
                                     "%s: predicted %.4f s after the nearest stamp, not %.1f"
                                     % (fmt_event(ev), (predicted - used).to_sec(), t))
                self.assertLessEqual(off, LATE_TOL, "late: " + fmt_event(ev))
                self.assertLessEqual(used, m.header.stamp)
                age = (m.header.stamp - used).to_sec()
                self.assertAlmostEqual(ev.distance, max(0.0, gap - growth(e, a, cap, age)),
                                       delta=DIST_TOL, msg=fmt_event(ev))
                # The constant-velocity contact never comes (standing): separation = contact.
                self.assertEqual(ev.time_to_separation, ev.time_to_contact, fmt_event(ev))
                checked[other] += 1
            self.assertNotIn("s", ids, "a standing box without growth must never be reached")
        for k, n in checked.items():
            self.assertGreaterEqual(n, 8, "too few events of %s checked: %d" % (k, n))
        del tf_pub


if __name__ == "__main__":
    rospy.init_node("test_growth")
    rostest.rosrun("workspace_proximity", "test_growth", GrowthTest)
