#!/usr/bin/env python3
"""~max_tracks = 2 ("beyond it the nearest to the robot win").

Robot body "post" (0.4 x 0.4 x 2 m at the origin). Topic src_a keeps publishing two boxes
30 m from the robot ("f1", "f2", at rest) and fills the cap first. After 0.6 s topic src_b
starts publishing "near": a 0.5 m cube 1.8 m from the post, approaching it at 0.5 m/s
(time to contact 3.6 s, horizon 5 s). "near" is the nearest object to the robot, so it must
be monitored: the pair ("/src_b/near", "post") must be reported (with its analytic time to
contact) within 1 s of src_b's first message, while one of the far boxes gives way.
"""
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402

from wp_node_testlib import (END, TIME_TOL, ScenePublisher, Track, broadcast_static,  # noqa: E402
                             check_array_basics, connected_collector, events_for, fmt_event)

NEAR = "/src_b/near"


class MaxTracksTest(unittest.TestCase):
    def test_nearest_tracks_win(self):
        tf_pub = broadcast_static([("world", "base_link", (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))])
        col = connected_collector(self)
        far = ScenePublisher("src_a", [Track("f1", "default", (30.0, 0.0, 1.0), (1, 1, 1)),
                                       Track("f2", "default", (-30.0, 0.0, 1.0), (1, 1, 1))],
                             latency=0.05)
        far.start()
        rospy.sleep(0.6)
        near = Track("near", "default", (-2.25, 0.0, 1.0), (0.5, 0.5, 0.5), (0.5, 0.0, 0.0))
        close = ScenePublisher("src_b", [near], latency=0.05)
        t0 = close.start()
        rospy.sleep(2.0)
        close.stop()
        far.stop()

        msgs = col.contact_msgs(since=t0)
        for m in msgs:
            check_array_basics(self, m)
        reported = [m for m in msgs
                    if any(e.state != END for e in events_for(m, NEAR, "post"))]
        self.assertTrue(reported, "the nearest object %s was never monitored (max_tracks 2, "
                        "two far tracks from another topic came first); events seen: %r" % (
                            NEAR, sorted(set(fmt_event(e) for m in msgs for e in m.events))))
        first = (reported[0].header.stamp - t0).to_sec()
        self.assertLessEqual(first, 1.0, "%s first reported %.2f s after it appeared" % (
            NEAR, first))
        for m in reported:
            ev = [e for e in events_for(m, NEAR, "post") if e.state != END][0]
            dt = (m.header.stamp - t0).to_sec()
            self.assertAlmostEqual(ev.time_to_contact, (1.8 - 0.5 * dt) / 0.5, delta=TIME_TOL,
                                   msg="T-t0=%.3f %s" % (dt, fmt_event(ev)))
        del tf_pub


if __name__ == "__main__":
    rospy.init_node("test_max_tracks")
    rostest.rosrun("workspace_proximity", "test_max_tracks", MaxTracksTest)
