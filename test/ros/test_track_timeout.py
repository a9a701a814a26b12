#!/usr/bin/env python3
"""Track timeout (track_timeout = 0.5 s, rate 20 Hz).

"anchor" (1 m cube at rest at the origin), "far" (at rest 20 m away) and "mover" (1 m cube
approaching the anchor at 1 m/s from 3 m, time to contact 3 s, horizon 5 s). After 1.2 s the
mover is no longer published (anchor and far still are). Expected: the pair (anchor, mover)
ONGOING until the mover is dropped, marked stale once the mover's stamp is older than
~stale_after (0.25 s), END once between 0.4 and 0.8 s after its last message,
then nothing; every marker the mover had in "bodies", "swept" and "velocity" is deleted with
action DELETE and not re-added; the anchor's body marker stays; no nearest / ttc_text marker
is added after the END.
"""
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402
from visualization_msgs.msg import Marker  # noqa: E402

from wp_node_testlib import (END, ScenePublisher, Track, check_array_basics,  # noqa: E402
                             connected_collector, events_for, fmt_event, state_sequence)

BODY_NAMESPACES = ("bodies", "swept", "velocity")


class TrackTimeoutTest(unittest.TestCase):
    def test_track_timeout(self):
        col = connected_collector(self)
        anchor = Track("anchor", "default", (0.0, 0.0, 0.0), (1, 1, 1))
        mover = Track("mover", "default", (-4.0, 0.0, 0.0), (1, 1, 1), (1.0, 0.0, 0.0))
        far = Track("far", "default", (20.0, 20.0, 0.0), (1, 1, 1))
        scene = ScenePublisher("tracked_objects", [anchor, mover, far], latency=0.0)
        t0 = scene.start()
        rospy.sleep(1.2)
        before_stop = rospy.Time.now()
        scene.deactivate(mover)
        last_pub = scene.last_wall["mover"]
        rospy.sleep(2.0)
        scene.stop()

        msgs = col.contact_msgs(since=t0)
        for m in msgs:
            check_array_basics(self, m)
        seq = state_sequence(msgs, "anchor", "mover")
        self.assertRegex(seq, r"^\.*BO+E\.*$", "state sequence of (anchor, mover): " + seq)
        end_msg = next(m for m in msgs
                       if any(e.state == END for e in events_for(m, "anchor", "mover")))
        delay = (end_msg.header.stamp - last_pub).to_sec()
        self.assertTrue(0.4 <= delay <= 0.8,
                        "END %.3f s after the mover's last message (track_timeout 0.5 s)" % delay)
        t_end = end_msg.header.stamp
        # Until ~stale_after (0.25 s) after the mover's last stamp its pair is fresh; from
        # then until the END it is stale.
        stale_checked = 0
        for m in msgs:
            age = (m.header.stamp - last_pub).to_sec()
            for ev in events_for(m, "anchor", "mover"):
                if ev.state == END:
                    continue
                if age < 0.15:
                    self.assertFalse(ev.stale, "age %.3f s: %s" % (age, fmt_event(ev)))
                elif age > 0.26:
                    self.assertTrue(ev.stale, "age %.3f s: %s" % (age, fmt_event(ev)))
                    stale_checked += 1
        self.assertGreaterEqual(stale_checked, 2, "too few cycles between stale and END")

        # Markers: what the mover had just before the stop, identified by position.
        arrays = col.marker_msgs()
        self.assertTrue(arrays, "no MarkerArray received")
        pre = [a for t, a in col.markers if t <= before_stop]
        self.assertTrue(pre, "no MarkerArray before the stop")
        mover_body_ids = set()
        anchor_body_ids = set()
        for arr in pre[-5:]:
            for mk in arr.markers:
                if mk.ns == "bodies" and mk.action == Marker.ADD:
                    x, y = mk.pose.position.x, mk.pose.position.y
                    if x < -1.6 and abs(y) < 0.5:
                        mover_body_ids.add(mk.id)
                    elif abs(x) < 0.1 and abs(y) < 0.1:
                        anchor_body_ids.add(mk.id)
        self.assertEqual(len(mover_body_ids), 1, "mover's body marker ids: %r" % mover_body_ids)
        self.assertEqual(len(anchor_body_ids), 1, "anchor's body marker ids: %r" % anchor_body_ids)
        mover_id = mover_body_ids.pop()
        anchor_id = anchor_body_ids.pop()

        # (ns, id) of every body-related marker refreshed just before the stop, and of those
        # still refreshed well after the END: the difference belongs to the mover.
        refreshed_before = set((mk.ns, mk.id) for mk in pre[-1].markers
                               if mk.action == Marker.ADD and mk.ns in BODY_NAMESPACES)
        late = [a for t, a in col.markers if t >= t_end + rospy.Duration(0.5)]
        self.assertTrue(late, "no MarkerArray after the END")
        refreshed_after = set((mk.ns, mk.id) for mk in late[-1].markers
                              if mk.action == Marker.ADD and mk.ns in BODY_NAMESPACES)
        self.assertIn(("bodies", anchor_id), refreshed_after, "anchor's body marker vanished")
        vanished = refreshed_before - refreshed_after
        self.assertIn(("bodies", mover_id), vanished)
        post = [a for t, a in col.markers if t >= before_stop]
        deleted = set()
        for arr in post:
            for mk in arr.markers:
                key = (mk.ns, mk.id)
                if mk.action == Marker.DELETE:
                    deleted.add(key)
                elif mk.action == Marker.ADD and key in deleted and key in vanished:
                    self.fail("marker %r re-added after its DELETE" % (key,))
        self.assertEqual(vanished - deleted, set(),
                         "markers of the dropped track that were never deleted with DELETE "
                         "(ns, id): %r" % sorted(vanished - deleted))
        for arr in late:
            for mk in arr.markers:
                if mk.action == Marker.ADD:
                    self.assertNotIn(mk.ns, ("nearest", "ttc_text"),
                                     "event marker added after the only event ended")


if __name__ == "__main__":
    rospy.init_node("test_track_timeout")
    rostest.rosrun("workspace_proximity", "test_track_timeout", TrackTimeoutTest)
