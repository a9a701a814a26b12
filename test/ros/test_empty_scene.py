#!/usr/bin/env python3
"""Empty scene: with nothing to monitor the node still publishes an (empty) ContactEventArray
every cycle ("silence never means all clear"): at least 50 % of the nominal 20 Hz over 3 s,
frame_id = the fixed frame ("map"), strictly increasing stamps close to the current time,
status DEGRADED with a detail naming the silent source "tracked_objects" (an empty list is
not an all-clear when no input ever arrived), and no event or body markers.
"""
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402
from visualization_msgs.msg import Marker  # noqa: E402

from wp_node_testlib import (check_array_basics, connected_collector, degraded_about)  # noqa: E402

RATE = 20.0
WINDOW = 3.0


class EmptySceneTest(unittest.TestCase):
    def test_empty_arrays_at_rate(self):
        col = connected_collector(self)
        start = rospy.Time.now()
        rospy.sleep(WINDOW)
        end = rospy.Time.now()
        with col.lock:
            received = [(t, m) for t, m in col.contacts if start <= t <= end]
        n = len(received)
        self.assertGreaterEqual(n, int(0.5 * RATE * WINDOW),
                                "%d arrays in %.1f s at rate %.0f Hz" % (n, WINDOW, RATE))
        self.assertLessEqual(n, int(1.5 * RATE * WINDOW) + 1,
                             "%d arrays in %.1f s at rate %.0f Hz" % (n, WINDOW, RATE))
        prev = None
        for t, m in received:
            check_array_basics(self, m, frame_id="map")
            self.assertEqual(len(m.events), 0, "events in an empty scene: %r" % m.events)
            lag = (t - m.header.stamp).to_sec()
            self.assertTrue(-0.05 <= lag <= 0.5,
                            "stamp %.3f s before its receipt; expected the cycle instant" % lag)
            if prev is not None:
                self.assertGreater(m.header.stamp, prev, "stamps not increasing")
            prev = m.header.stamp
        # Nothing was ever received on tracked_objects: not an all-clear.
        for t, m in received:
            if (t - start).to_sec() > 1.0:
                self.assertTrue(degraded_about(m, "tracked_objects"),
                                "status %d %r: expected DEGRADED naming the silent source" % (
                                    m.status, m.status_details))
        for arr in col.marker_msgs():
            for mk in arr.markers:
                if mk.action == Marker.ADD:
                    self.assertNotIn(mk.ns, ("nearest", "ttc_text", "bodies", "ids"),
                                     "marker in an empty scene: %s/%d" % (mk.ns, mk.id))


if __name__ == "__main__":
    rospy.init_node("test_empty_scene")
    rostest.rosrun("workspace_proximity", "test_empty_scene", EmptySceneTest)
