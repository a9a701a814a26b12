#!/usr/bin/env python3
"""~cycle_trigger: input (trigger_source boxes_b of input_topics [boxes_a, boxes_b], rate 2 Hz).

The test is the simulator: it publishes /clock in 10 ms steps at about real time, and holds
the clock still for 60 ms of wall time after each array it sends, so that the node receives
the array at exactly the array's instant. Simulated seconds from S = 100 s:
  0 .. 3   arrays of boxes_b at 0.13, 0.77, 1.42, 2.05, 2.71 (more than a period apart) and of
           boxes_a at 0.33 and 1.90;
  3 .. 5   a flood: an array of boxes_b at every step (100 Hz);
  5 .. 7   silence.
Checks on the contacts arrays (one per cycle, stamped with the cycle's instant):
- every boxes_b array of the first phase has a cycle stamped exactly at its instant, and no
  cycle is stamped at a boxes_a array's instant (it only waits for the next cycle);
- between cycles there is never more than a period (0.5 s) plus the time the timer takes to
  notice it (a step, 10 ms, and the callback's delay: 50 ms allowed): the floor timer;
- the flood runs at most rate x 2 s + 2 (the burst) + 1 (a floor cycle) cycles, and at least 3;
- in silence, cycles come a period after each other.
"""
import os
import sys
import threading
import time
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402
from rosgraph_msgs.msg import Clock  # noqa: E402

from wp_node_testlib import ContactEventArray, Track, TrackedBoxArray, WallPacer  # noqa: E402

START_NS = 100 * 10**9
STEP_NS = 10 * 10**6
B_TIMES = [0.13, 0.77, 1.42, 2.05, 2.71]
A_TIMES = [0.33, 1.90]
PERIOD = 0.5


def ns_of(s):
    return START_NS + int(round(s * 1e9))


def to_time(ns):
    return rospy.Time(ns // 10**9, ns % 10**9)


class CycleTriggerTest(unittest.TestCase):
    def test_input_trigger(self):
        clock_pub = rospy.Publisher("/clock", Clock, queue_size=20)
        pubs = {"a": rospy.Publisher("boxes_a", TrackedBoxArray, queue_size=200),
                "b": rospy.Publisher("boxes_b", TrackedBoxArray, queue_size=200)}
        lock = threading.Lock()
        cycles = []

        def on_contacts(msg):
            with lock:
                cycles.append(msg.header.stamp.to_nsec())

        sub = rospy.Subscriber("contacts", ContactEventArray, on_contacts, queue_size=1000)
        deadline = time.monotonic() + 15.0
        while time.monotonic() < deadline and not (
                clock_pub.get_num_connections() >= 1 and sub.get_num_connections() >= 1 and
                all(p.get_num_connections() >= 1 for p in pubs.values())):
            time.sleep(0.05)

        def send(which, ns):
            msg = TrackedBoxArray()
            msg.header.stamp = to_time(ns)
            msg.header.frame_id = "world"
            msg.boxes = [Track(which + "1", "default", (3.0, 0.0, 0.5), (1, 1, 1),
                               t0=to_time(ns)).to_msg(to_time(ns))]
            pubs[which].publish(msg)

        b_ns = set(ns_of(s) for s in B_TIMES)
        a_ns = set(ns_of(s) for s in A_TIMES)
        flood = (ns_of(3.0), ns_of(5.0))
        pacer = WallPacer(STEP_NS * 1e-9)
        for k in range(701):
            ns = START_NS + k * STEP_NS
            clock_pub.publish(Clock(clock=to_time(ns)))
            due = [which for which, times in (("a", a_ns), ("b", b_ns)) if ns in times]
            if due:
                # The clock and the arrays travel on separate connections: hold the clock at the
                # array's instant until the node has it, so that the array arrives at that instant.
                time.sleep(0.05)
            for which in due:
                send(which, ns)
            if flood[0] <= ns < flood[1]:
                send("b", ns)
            if due:
                time.sleep(0.06)  # the clock stands still while the node takes the array
                pacer.restart()
            pacer.wait()
        time.sleep(0.3)
        with lock:
            stamps = sorted(cycles)
        self.assertGreater(len(stamps), 15)
        at = set(stamps)
        for ns in sorted(b_ns):
            self.assertIn(ns, at, "no cycle at the boxes_b array of %.2f s" % ((ns - START_NS) * 1e-9))
        for ns in sorted(a_ns):
            self.assertNotIn(ns, at, "a cycle at the boxes_a array of %.2f s" % ((ns - START_NS) * 1e-9))
        for prev, cur in zip(stamps, stamps[1:]):
            self.assertLessEqual((cur - prev) * 1e-9, PERIOD + 0.05,
                                 "no cycle from %.3f to %.3f s" % ((prev - START_NS) * 1e-9,
                                                                  (cur - START_NS) * 1e-9))
        in_flood = [s for s in stamps if flood[0] <= s < flood[1]]
        self.assertLessEqual(len(in_flood), int(2.0 * 2.0) + 2 + 1, "flood cycles %r" % in_flood)
        self.assertGreaterEqual(len(in_flood), 3)
        silence = [s for s in stamps if s >= ns_of(5.2)]
        self.assertGreaterEqual(len(silence), 3)
        for prev, cur in zip(silence, silence[1:]):
            self.assertGreaterEqual((cur - prev) * 1e-9, PERIOD - 1e-6, "faster than the rate in silence")


if __name__ == "__main__":
    rospy.init_node("test_cycle_trigger")
    rostest.rosrun("workspace_proximity", "test_cycle_trigger", CycleTriggerTest)
