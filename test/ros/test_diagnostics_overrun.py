#!/usr/bin/env python3
"""/diagnostics ERROR when a cycle overruns its period.

The node runs at 1 000 Hz (period 1 ms). The scene: 1 500 boxes (0.5 m, 1 m/s in random
directions) in a 30 m square with a 2 s horizon, about 20 broad-phase neighbours each and
hundreds of predicted contacts, published at 5 Hz: a cycle takes several milliseconds, far
beyond the period on any machine of this class. Checks, over every status received:
- level ERROR exactly when the status's own "cycle time (ms)" is over the period (statuses
  within 1 µs of it are skipped), and then the message says "cycle takes ... longer than
  the 1.0 ms period";
- while the scene is published, ERROR is reported (at least 3 statuses);
- contacts keep coming while the node overruns (it degrades its rate, never stops): at least
  5 arrays stamped in the loaded seconds;
- after the scene stops, the tracks time out, the cycle is short again and the level comes
  back below ERROR (WARN: the source is silent); a quiet status whose cycle a preempted
  moment still made longer than the period is ERROR by the first rule.
The assertion is the logic (ERROR iff the reported cycle time exceeds the period), not a
wall-clock time: the scene is heavy enough that overruns happen on any plausible machine.
"""
import math
import os
import random
import sys
import threading
import time
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402

from wp_node_testlib import (DiagnosticsCollector, TrackedBox, TrackedBoxArray,  # noqa: E402
                             connected_collector, diag_values)

ERROR = 2
PERIOD_MS = 1.0
COUNT = 1500
SIDE = 30.0


def heavy_scene():
    rng = random.Random(5)
    arr = TrackedBoxArray()
    arr.header.frame_id = "world"
    for i in range(COUNT):
        b = TrackedBox()
        b.id = "b%04d" % i
        b.label = "default"
        b.pose.position.x = rng.uniform(-SIDE / 2, SIDE / 2)
        b.pose.position.y = rng.uniform(-SIDE / 2, SIDE / 2)
        b.pose.position.z = 0.5
        b.pose.orientation.w = 1.0
        b.dimensions.x = b.dimensions.y = b.dimensions.z = 0.5
        a = rng.uniform(0.0, 6.283)
        b.twist.linear.x = math.cos(a)
        b.twist.linear.y = math.sin(a)
        arr.boxes.append(b)
    return arr


class DiagnosticsOverrunTest(unittest.TestCase):
    def test_error_on_overrun(self):
        diags = DiagnosticsCollector()
        col = connected_collector(self)
        pub = rospy.Publisher("tracked_objects", TrackedBoxArray, queue_size=1)
        scene = heavy_scene()
        stop = threading.Event()

        def publish():
            while not stop.is_set() and not rospy.is_shutdown():
                scene.header.stamp = rospy.Time.now()
                pub.publish(scene)
                stop.wait(0.2)

        thread = threading.Thread(target=publish)
        thread.daemon = True
        start = time.monotonic()
        loaded_from = rospy.Time.now() + rospy.Duration(1.0)
        thread.start()
        time.sleep(5.0)
        loaded_to = rospy.Time.now()
        stop.set()
        thread.join()
        loaded = diags.since(start)
        quiet_start = time.monotonic()
        # Tracks time out after ~track_timeout (1 s); then cycles are short again.
        st = diags.wait_for(lambda st, v: int(v.get("tracks", "-1")) == 0, 10.0,
                            since=quiet_start)
        self.assertIsNotNone(st, "tracks never timed out")
        time.sleep(1.0)
        # The statuses from here on; on a loaded machine (ctest runs two tests at a time) the
        # next one may take longer than the 0.2 s period, so wait for it rather than a fixed
        # time. An empty cycle preempted by the other test can still take over 1 ms (seen once
        # in CI: 1.03 ms, rightly ERROR by the rule checked below), so the level must come
        # back below ERROR, not stay there in every quiet status.
        quiet_from = time.monotonic()
        back = diags.wait_for(lambda st, v: st.level != ERROR, 10.0, since=quiet_from)
        quiet = diags.since(quiet_from)

        errors = 0
        for _, st in diags.since(start):
            v = diag_values(st)
            cycle = float(v["cycle time (ms)"])
            if abs(cycle - PERIOD_MS) < 1e-3:
                continue
            if cycle > PERIOD_MS:
                errors += 1
                self.assertEqual(st.level, ERROR, "cycle %.3f ms but level %d %r" %
                                 (cycle, st.level, st.message))
                self.assertTrue(st.message.startswith("cycle takes"), st.message)
                self.assertIn("longer than the 1.0 ms period", st.message)
            else:
                self.assertNotEqual(st.level, ERROR, "ERROR with cycle %.3f ms: %r" %
                                    (cycle, st.message))
        loaded_errors = sum(1 for _, st in loaded if st.level == ERROR)
        self.assertGreaterEqual(loaded_errors, 3, "the heavy scene never overran: %s" %
                                [diag_values(st).get("cycle time (ms)") for _, st in loaded])
        # Contacts keep coming while the node overruns: every array stamped in the 4 loaded
        # seconds counts. (How many depends on how fast this Python subscriber keeps up with
        # arrays of hundreds of events on a loaded machine, so the bar is "not silent".)
        contacts_during = len([m for m in col.contact_msgs(since=loaded_from)
                               if m.header.stamp <= loaded_to])
        self.assertGreaterEqual(contacts_during, 5, "contacts stopped while overrunning")
        self.assertTrue(quiet, "no status after the scene stopped")
        self.assertIsNotNone(back, "still ERROR 10 s after the scene stopped: %s" % [
            (st.message, diag_values(st).get("cycle time (ms)")) for _, st in quiet])
        rospy.loginfo("overrun: %d ERROR statuses while loaded (of %d), %d in all", loaded_errors,
                      len(loaded), errors)


if __name__ == "__main__":
    rospy.init_node("test_diagnostics_overrun")
    rostest.rosrun("workspace_proximity", "test_diagnostics_overrun", DiagnosticsOverrunTest)
