#!/usr/bin/env python3
"""~marker_rate: a 20 Hz node with marker_rate 5 Hz and one moving box. Over 4 s the
contacts arrive at about 20 Hz (+-40 %) and the MarkerArrays at about 5 Hz (+-40 %);
consecutive MarkerArrays are stamped at least a marker period less half a cycle (0.175 s)
apart; every MarkerArray still has the box's markers.
"""
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402

from wp_node_testlib import (ScenePublisher, Track, connected_collector)  # noqa: E402

RATE, MARKER_RATE, WINDOW = 20.0, 5.0, 4.0


class MarkerRateTest(unittest.TestCase):
    def test_markers_throttled(self):
        col = connected_collector(self)
        box = Track("box", "default", (0.0, 0.0, 0.5), (1, 1, 1), (0.3, 0.0, 0.0))
        scene = ScenePublisher("tracked_objects", [box])
        scene.start()
        rospy.sleep(1.0)
        start = rospy.Time.now()
        rospy.sleep(WINDOW)
        end = rospy.Time.now()
        scene.stop()
        contacts = [m for m in col.contact_msgs(since=start) if m.header.stamp <= end]
        with col.lock:
            marker_arrays = [m for t, m in col.markers if start <= t <= end and m.markers]
        self.assertGreaterEqual(len(contacts), 0.6 * RATE * WINDOW, len(contacts))
        self.assertLessEqual(len(contacts), 1.4 * RATE * WINDOW, len(contacts))
        n = len(marker_arrays)
        self.assertGreaterEqual(n, 0.6 * MARKER_RATE * WINDOW, "%d MarkerArrays" % n)
        self.assertLessEqual(n, 1.4 * MARKER_RATE * WINDOW, "%d MarkerArrays" % n)
        # The node publishes when a marker period (less half a cycle) has passed since the
        # last MarkerArray: their stamps (the cycle instants) are at least 0.175 s apart.
        stamps = [arr.markers[0].header.stamp for arr in marker_arrays]
        gaps = [(b - a).to_sec() for a, b in zip(stamps, stamps[1:])]
        self.assertTrue(gaps and min(gaps) >= 0.17, "MarkerArrays %s s apart" % gaps)
        for arr in marker_arrays:
            bodies = [mk for mk in arr.markers if mk.ns == "bodies" and mk.action == mk.ADD]
            self.assertEqual(len(bodies), 1, "bodies markers: %d" % len(bodies))


if __name__ == "__main__":
    rospy.init_node("test_marker_rate")
    rostest.rosrun("workspace_proximity", "test_marker_rate", MarkerRateTest)
