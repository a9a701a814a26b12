#!/usr/bin/env python3
"""Near miss: a 1 m cube moving along (1, -1, 0) at 1.41 m/s passes the vertical edge of a
resting 1 m cube with a 0.025 m gap on x and on y (0.035 m at closest, at t0 + 3.025 s).
Over the 5 s horizon its swept bounds overlap the resting cube and each axis overlaps for a
while (x over [1, 3] s, y from 3.05 s), but never all at once: no event may be reported.

Positive control, 50 m higher: the same motion with label "padded" (0.1 m margin on each box)
must be reported, since the inflated shapes overlap by 0.165 m.
"""
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402

from wp_node_testlib import (END, Track, check_array_basics, connected_collector,  # noqa: E402
                             events_for, fmt_event, run_scene)


class NearMissTest(unittest.TestCase):
    def test_near_miss_gives_no_event(self):
        col = connected_collector(self)
        tracks = [
            Track("miss_a", "default", (0.0, 0.0, 0.0), (1, 1, 1)),
            Track("miss_b", "default", (-2.0, 4.05, 0.0), (1, 1, 1), (1.0, -1.0, 0.0)),
            Track("ctl_a", "padded", (0.0, 0.0, 50.0), (1, 1, 1)),
            Track("ctl_b", "padded", (-2.0, 4.05, 50.0), (1, 1, 1), (1.0, -1.0, 0.0)),
        ]
        t0, msgs = run_scene(col, tracks, 3.6, 0.3)  # past the closest approach at t0 + 3.025 s
        self.assertGreater(len(msgs), 40)
        control_cycles = window = 0
        for m in msgs:
            check_array_basics(self, m)
            for ev in m.events:
                self.assertEqual((ev.id_a, ev.id_b), ("ctl_a", "ctl_b"),
                                 "unexpected event at T-t0=%.3f: %s" % (
                                     (m.header.stamp - t0).to_sec(), fmt_event(ev)))
            if (m.header.stamp - t0).to_sec() <= 3.0:
                window += 1
                if any(e.state != END for e in events_for(m, "ctl_a", "ctl_b")):
                    control_cycles += 1
        # Until t0 + 3.2 s the padded pair touches within the horizon: it must be reported in
        # nearly every cycle up to t0 + 3 s.
        self.assertGreaterEqual(control_cycles, int(0.9 * window),
                                "positive control (margins 0.1) reported in only %d of %d "
                                "cycles" % (control_cycles, window))


if __name__ == "__main__":
    rospy.init_node("test_near_miss")
    rostest.rosrun("workspace_proximity", "test_near_miss", NearMissTest)
