#!/usr/bin/env python3
"""Robustness: a valid head-on pair ("good_a", "good_b": 1 m cubes, gap 4 m, closing 2 m/s)
published together, in the same arrays, with malformed boxes lying on top of good_a (NaN
position, NaN twist, zero / negative edge, empty id, zero quaternion, a duplicate id, an edge
over the size limit) and, in arrays of their own on the same topic, boxes in an empty
frame_id, in a frame tf does not know, stamped 2 s in the future (> ~max_future) and stamped
2 s ago (> ~track_timeout). Further away: extreme but valid boxes (a 1 mm cube, a box at
300 m/s, one spinning at 60 rad/s, one with an absurd 1e300 m/s twist). Expected for 2.5 s:
the node keeps publishing at >= 50 % of its rate, no event names a malformed box, and the good
pair's events keep their analytic time_to_contact (1 ms).
"""
import math
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402

from wp_node_testlib import (END, ScenePublisher, Track, aabb_prediction,  # noqa: E402
                             check_array_basics, check_face_contact, connected_collector,
                             events_for, fmt_event)

HORIZON = 10.0
NAN = float("nan")


class Malformed(Track):
    """A Track whose message is spoiled by `spoil(box)` after it is built."""

    def __init__(self, box_id, spoil, position=(-2.5, 0.0, 0.0), size=(1, 1, 1)):
        Track.__init__(self, box_id, "default", position, size, (1.0, 0.0, 0.0))
        self.spoil = spoil

    def to_msg(self, stamp):
        b = Track.to_msg(self, stamp)
        self.spoil(b)
        return b


def set_attr(path, value):
    def spoil(b):
        obj = b
        for name in path[:-1]:
            obj = getattr(obj, name)
        setattr(obj, path[-1], value)
    return spoil


def zero_quat(b):
    b.pose.orientation.x = b.pose.orientation.y = b.pose.orientation.z = 0.0
    b.pose.orientation.w = 0.0


class RobustnessTest(unittest.TestCase):
    def test_bad_input_is_harmless(self):
        col = connected_collector(self)
        good_a = Track("good_a", "default", (-2.5, 0.0, 0.0), (1, 1, 1), (1.0, 0.0, 0.0))
        good_b = Track("good_b", "default", (2.5, 0.0, 0.0), (1, 1, 1), (-1.0, 0.0, 0.0))
        # the same id twice in one array: the first one counts
        dup_first = Track("dup", "default", (0.0, 40.0, 0.0), (1, 1, 1))
        dup_second = Track("dup", "default", (-2.5, 0.0, 0.0), (1, 1, 1), (1.0, 0.0, 0.0))
        malformed = [
            Malformed("bad_nan_position", set_attr(("pose", "position", "x"), NAN)),
            Malformed("bad_nan_twist", set_attr(("twist", "linear", "y"), NAN)),
            Malformed("bad_inf_angular", set_attr(("twist", "angular", "z"), math.inf)),
            Malformed("bad_zero_edge", set_attr(("dimensions", "y"), 0.0)),
            Malformed("bad_negative_edge", set_attr(("dimensions", "z"), -1.0)),
            Malformed("", lambda b: None),
            Malformed("bad_zero_quaternion", zero_quat),
            Malformed("bad_huge_edge", set_attr(("dimensions", "x"), 1e7)),
        ]
        extreme = [
            Track("tiny", "default", (300.0, 0.0, 0.0), (1e-3, 1e-3, 1e-3), (0.0, 0.0, 1.0)),
            Track("fast", "default", (600.0, -1500.0, 0.0), (1, 1, 1), (0.0, 300.0, 0.0)),
            Track("spinner", "default", (900.0, 0.0, 0.0), (2.0, 0.1, 0.1), yaw=0.0,
                  yaw_rate=60.0),
            Track("absurd", "default", (1200.0, 0.0, 0.0), (1, 1, 1), (0.0, 1e300, 0.0)),
        ]
        good = ScenePublisher("tracked_objects",
                              [good_a, good_b, dup_first, dup_second] + malformed + extreme,
                              latency=0.05)
        no_frame = ScenePublisher("tracked_objects",
                                  [Track("ghost_empty_frame", "default", (-2.5, 0, 0), (1, 1, 1))],
                                  frame_id="", rate=3.0)
        bad_frame = ScenePublisher("tracked_objects",
                                   [Track("ghost_unknown_frame", "default", (-2.5, 0, 0),
                                          (1, 1, 1))],
                                   frame_id="nowhere", rate=3.0)
        # stamped 2 s ahead (beyond ~max_future = 0.5 s) and 2 s old (beyond ~track_timeout)
        future = ScenePublisher("tracked_objects",
                                [Track("ghost_future", "default", (-2.5, 0, 0), (1, 1, 1),
                                       (1.0, 0.0, 0.0))],
                                rate=3.0, latency=-2.0)
        old = ScenePublisher("tracked_objects",
                             [Track("ghost_old", "default", (-2.5, 0, 0), (1, 1, 1),
                                    (1.0, 0.0, 0.0))],
                             rate=3.0, latency=2.0)
        publishers = (good, no_frame, bad_frame, future, old)
        for p in publishers:
            p.wait_connected()
        t0 = rospy.Time.now()
        for p in publishers:
            p.start(t0)
        rospy.sleep(2.5)
        for p in publishers:
            p.stop()
        end = rospy.Time.now()

        msgs = col.contact_msgs(since=t0)
        self.assertGreaterEqual(len(msgs), 25, "only %d arrays in 2.5 s at 20 Hz" % len(msgs))
        with col.lock:
            recent = [t for t, m in col.contacts if t >= end - rospy.Duration(0.5)]
        self.assertGreaterEqual(len(recent), 5, "the node stopped publishing")
        allowed = {"good_a", "good_b", "spinner", "tiny", "fast", "absurd"}
        half = (0.5, 0.5, 0.5)
        checked = 0
        for m in msgs:
            check_array_basics(self, m)
            for ev in m.events:
                self.assertTrue({ev.id_a, ev.id_b} <= allowed,
                                "event names a malformed box (or the second box of a "
                                "duplicated id): " + fmt_event(ev))
            dt = (m.header.stamp - t0).to_sec()
            if dt < 0.3:
                continue
            for ev in events_for(m, "good_a", "good_b"):
                if ev.state == END:
                    continue
                ca, va = good_a.state(m.header.stamp)
                cb, vb = good_b.state(m.header.stamp)
                exp = aabb_prediction(ca, half, va, cb, half, vb, HORIZON)
                check_face_contact(self, ev, exp, ca, half, cb, half, "T-t0=%.3f" % dt)
                checked += 1
        self.assertGreaterEqual(checked, 20, "good pair checked in only %d cycles" % checked)


if __name__ == "__main__":
    rospy.init_node("test_robustness")
    rostest.rosrun("workspace_proximity", "test_robustness", RobustnessTest)
