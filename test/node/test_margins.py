#!/usr/bin/env python3
"""Margins: label margins (default 0.1, person 0.2, forklift 0.3 m; unknown labels use
default) and robot_margin (0.05 m) inflate the shapes, and the inflated shapes are what touch.
Every pair approaches face-on, so the exact numbers are those of boxes whose half extents
are grown by the margins: distance = face gap - both margins, time_to_contact = that / the
closing speed, time_to_separation likewise.
  walker (person, 0.5 m cube) -> robot body "pillar" (0.4 x 0.4 x 2 m): face gap 2.0 m at
      0.5 m/s -> 1.75 m, 3.5 s
  box (default) -> cart (forklift), 1 m cubes: face gap 2.0 m at 1 m/s -> 1.6 m, 1.6 s
  alien_b -> alien_a (label "alien", not configured: default), 1 m cubes: face gap 1.5 m at
      1 m/s -> 1.3 m, 1.3 s
Levels follow the stricter label's thresholds (robot_thresholds for the pillar).
"""
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402

from wp_node_testlib import (StaticBody, Track, broadcast_static, checked_arrays,  # noqa: E402
                             check_scene_events, connected_collector, node_labels, run_scene)

HORIZON = 5.0


class Inflated(object):
    """A body as the node should see it: half extents grown by its label's margin."""

    def __init__(self, body, labels):
        self.body, self.id, self.label = body, body.id, body.label
        self.half = tuple(h + labels[body.label]["margin"] for h in body.half)

    def state(self, stamp):
        return self.body.state(stamp)


class MarginsTest(unittest.TestCase):
    def test_margins(self):
        tf_pub = broadcast_static([("world", "base_link", (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))])
        col = connected_collector(self)
        pillar = StaticBody("pillar", "robot", (0.0, 0.0, 1.0), (0.2, 0.2, 1.0))
        tracks = [
            Track("walker", "person", (-2.45, 0.0, 1.0), (0.5, 0.5, 0.5), (0.5, 0.0, 0.0)),
            Track("cart", "forklift", (10.0, 0.0, 0.5), (1, 1, 1)),
            Track("box", "default", (13.0, 0.0, 0.5), (1, 1, 1), (-1.0, 0.0, 0.0)),
            Track("alien_a", "alien", (20.0, 0.0, 0.5), (1, 1, 1)),
            Track("alien_b", "alien", (22.5, 0.0, 0.5), (1, 1, 1), (-1.0, 0.0, 0.0)),
        ]
        labels = node_labels()
        t0, msgs = run_scene(col, tracks, 1.4, 0.3)
        bodies = [Inflated(b, labels) for b in [pillar] + tracks]
        checked = 0
        seen = set()
        for m in checked_arrays(self, msgs, t0, 1.25):
            checked += check_scene_events(self, m, bodies, HORIZON, thresholds=labels,
                                          check_points=False)
            seen.update((e.id_a, e.id_b) for e in m.events)
        self.assertEqual(seen, {("pillar", "walker"), ("box", "cart"), ("alien_a", "alien_b")})
        self.assertGreaterEqual(checked, 40, "too few events checked")
        del tf_pub


if __name__ == "__main__":
    rospy.init_node("test_margins")
    rostest.rosrun("workspace_proximity", "test_margins", MarginsTest)
