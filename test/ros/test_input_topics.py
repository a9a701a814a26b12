#!/usr/bin/env python3
"""~input_topics = [cam_left, /cam_right/objects]: one subscription per topic, ids prefixed
with the resolved topic name. Both topics carry a box with id "7": on /cam_left it moves at
1 m/s towards the other one, at rest 3 m away on /cam_right/objects (time to contact 3 s,
horizon 5 s). Expected: one pair ("/cam_left/7", "/cam_right/objects/7") with analytic
numbers, and no bare "7". A box published on the default topic "tracked_objects" (not in
~input_topics) right next to them must be ignored. Status: OK while both sources publish;
once /cam_right/objects has been silent for over ~source_timeout (1 s) while cam_left goes
on, DEGRADED with a detail naming /cam_right/objects (and none naming /cam_left).
"""
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402

from wp_node_testlib import (ScenePublisher, Track, check_array_basics,  # noqa: E402
                             check_scene_events, connected_collector, degraded_about, events_for,
                             fmt_event)

HORIZON = 5.0
LEFT, RIGHT = "/cam_left/7", "/cam_right/objects/7"


class Renamed(object):
    """A Track seen under the id the node gives it."""

    def __init__(self, track, new_id):
        self.track, self.id, self.label, self.half = track, new_id, track.label, track.half

    def state(self, stamp):
        return self.track.state(stamp)


class InputTopicsTest(unittest.TestCase):
    def test_two_topics_same_id(self):
        col = connected_collector(self)
        left = Track("7", "default", (-2.0, 0.0, 0.0), (1, 1, 1), (1.0, 0.0, 0.0))
        right = Track("7", "default", (2.0, 0.0, 0.0), (1, 1, 1))
        stray = Track("8", "default", (0.0, 0.0, 0.0), (1, 1, 1))
        pubs = [ScenePublisher("cam_left", [left], latency=0.05),
                ScenePublisher("/cam_right/objects", [right], latency=0.1),
                ScenePublisher("tracked_objects", [stray], latency=0.05)]
        for p in pubs[:2]:
            self.assertTrue(p.wait_connected(), "the node did not subscribe " + p.pub.name)
        # not in ~input_topics: nobody should listen to tracked_objects
        self.assertFalse(pubs[2].wait_connected(0.5), "the node subscribes tracked_objects too")
        t0 = rospy.Time.now()
        for p in pubs:
            p.start(t0)
        rospy.sleep(1.8)
        pubs[1].stop()          # /cam_right/objects falls silent, cam_left goes on
        t_silent = rospy.Time.now()
        rospy.sleep(1.6)
        for p in pubs:
            p.stop()
        msgs = col.contact_msgs(since=t0 + rospy.Duration(0.5))
        for m in msgs:
            dt = (m.header.stamp - t0).to_sec()
            silent = (m.header.stamp - t_silent).to_sec()
            if dt <= 1.75:
                self.assertEqual(m.status, 0, "status with both sources fresh: %r" % (
                    m.status_details,))
            elif silent > 1.1:   # ~source_timeout = 1 s
                self.assertTrue(degraded_about(m, "/cam_right/objects"),
                                "%.2f s after /cam_right/objects fell silent: status %d %r" % (
                                    silent, m.status, m.status_details))
                self.assertFalse(any("/cam_left" in d for d in m.status_details),
                                 "the live source is reported: %r" % (m.status_details,))
        self.assertGreater(len(msgs), 15)
        bodies = [Renamed(left, LEFT), Renamed(right, RIGHT)]
        checked = 0
        for m in msgs:
            check_array_basics(self, m)
            for ev in m.events:
                self.assertEqual((ev.id_a, ev.id_b), (LEFT, RIGHT), "unexpected " + fmt_event(ev))
            if (m.header.stamp - t0).to_sec() <= 1.75:
                checked += check_scene_events(self, m, bodies, HORIZON)
        self.assertGreaterEqual(checked, 15, "pair (%s, %s) reported in only %d cycles" % (
            LEFT, RIGHT, checked))
        self.assertTrue(any(events_for(m, LEFT, RIGHT) for m in msgs))


if __name__ == "__main__":
    rospy.init_node("test_input_topics")
    rostest.rosrun("workspace_proximity", "test_input_topics", InputTopicsTest)
