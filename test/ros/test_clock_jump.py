#!/usr/bin/env python3
"""Simulated clock that jumps back (bag loop, simulator reset), with /use_sim_time.

The test is the simulator: it publishes /clock itself in steps of 10 ms at about real time,
and at each step, stamped with that clock, the robot link's tf (world -> carriage, 50 Hz)
and the tracked boxes (20 Hz, stamped 20 ms before the step). The node's timer runs off
/clock. Scene, s = time since the scene's origin (1 m cubes unless said):

  a   from (-4, 0, 0) at +1 m/s along x        b  from (4, 0, 0) at -1 m/s: head-on with a,
                                                  time_to_contact 3.5 - s
  d   from (-7, 0, 0) at +1.5 m/s (first run only): catches up with a and meets b
  c   from (0, 8, 0) at -0.5 m/s along y       post (robot body, 0.4 m cube on "carriage")
                                                  from (0, 4, 0) at +0.25 m/s along y

Run 1: clock 100 s .. 103 s (scene origin 100 s). Then the clock jumps back to 50 s and the
scene restarts there (origin 50 s) without d, for 3 s, like a looping bag. Right after the
node's reset, one late tf message and one late box array stamped at the end of run 1 arrive
(a publisher that saw the jump later than the monitor); they must not poison the new run.

Checks: every array satisfies the contract and no event has NaN or times outside
[0, horizon]; from 0.5 s into each run the events equal the analytic prediction (times to
1 ms, including the robot link's velocity from tf); the first array after the jump carries
END for every pair of run 1, and d is never named again; contacts keep coming after the
jump; /diagnostics counts "history resets (clock jumps)" 0 before and >= 1 after the jump and
is back to OK with the three tracks.
"""
import os
import sys
import threading
import time
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402
import tf2_ros  # noqa: E402
from geometry_msgs.msg import TransformStamped  # noqa: E402
from rosgraph_msgs.msg import Clock  # noqa: E402

from wp_node_testlib import (END, ContactEventArray, DiagnosticsCollector,  # noqa: E402
                             Track, TrackedBoxArray, check_array_basics, check_event_numbers,
                             check_scene_events, degraded_about, diag_values, fmt_event,
                             state_sequence)

HORIZON = 6.0
STEP_NS = 10 * 1000 * 1000        # 10 ms of simulated time per /clock message
RUN1_NS = 100 * 10**9             # run 1 starts at clock 100 s
RUN2_NS = 50 * 10**9              # the clock jumps back to 50 s
RUN_STEPS = 300                   # 3 s per run
BOX_LATENCY = rospy.Duration(0.02)
POST_Y0, POST_V = 4.0, 0.25
RESETS = "history resets (clock jumps)"


def to_time(ns):
    return rospy.Time(ns // 10**9, ns % 10**9)


class MovingRobotBody(object):
    """The robot body "post" on frame carriage (axis-aligned, translating along y)."""

    def __init__(self, origin):
        self.id = "post"
        self.label = "robot"
        self.half = (0.2, 0.2, 0.2)
        self.origin = origin

    def y(self, stamp):
        return POST_Y0 + POST_V * (stamp - self.origin).to_sec()

    def state(self, stamp):
        return (0.0, self.y(stamp), 0.0), (0.0, POST_V, 0.0)


def make_run(origin, with_d):
    tracks = [Track("a", "default", (-4.0, 0.0, 0.0), (1, 1, 1), (1.0, 0.0, 0.0), t0=origin),
              Track("b", "default", (4.0, 0.0, 0.0), (1, 1, 1), (-1.0, 0.0, 0.0), t0=origin),
              Track("c", "default", (0.0, 8.0, 0.0), (1, 1, 1), (0.0, -0.5, 0.0), t0=origin)]
    if with_d:
        tracks.append(Track("d", "default", (-7.0, 0.0, 0.0), (1, 1, 1), (1.5, 0.0, 0.0),
                            t0=origin))
    return tracks, MovingRobotBody(origin)


class ContactsInOrder(object):
    """Every contacts array, in order of receipt (no rospy time: it is simulated here)."""

    def __init__(self):
        self.lock = threading.Lock()
        self.msgs = []
        self.sub = rospy.Subscriber("contacts", ContactEventArray, self._on, queue_size=500)

    def _on(self, msg):
        with self.lock:
            self.msgs.append(msg)

    def all(self):
        with self.lock:
            return list(self.msgs)


class Simulator(object):
    def __init__(self):
        self.clock_pub = rospy.Publisher("/clock", Clock, queue_size=20)
        self.box_pub = rospy.Publisher("tracked_objects", TrackedBoxArray, queue_size=20)
        self.tf = tf2_ros.TransformBroadcaster()

    def wait_connected(self, contacts, diags, timeout=15.0):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline and not rospy.is_shutdown():
            if (self.clock_pub.get_num_connections() >= 1 and
                    self.box_pub.get_num_connections() >= 1 and
                    self.tf.pub_tf.get_num_connections() >= 1 and
                    contacts.sub.get_num_connections() >= 1 and
                    diags.sub.get_num_connections() >= 1):
                return True
            time.sleep(0.05)
        return False

    def publish_clock(self, stamp):
        self.clock_pub.publish(Clock(clock=stamp))

    def publish_tf(self, body, stamp):
        t = TransformStamped()
        t.header.stamp = stamp
        t.header.frame_id = "world"
        t.child_frame_id = "carriage"
        t.transform.translation.y = body.y(stamp)
        t.transform.rotation.w = 1.0
        self.tf.sendTransform(t)

    def publish_boxes(self, tracks, stamp):
        msg = TrackedBoxArray()
        msg.header.stamp = stamp
        msg.header.frame_id = "world"
        msg.boxes = [tr.to_msg(stamp) for tr in tracks]
        self.box_pub.publish(msg)

    def run(self, start_ns, tracks, body, on_step=None):
        """Publishes RUN_STEPS steps of 10 ms from start_ns at about real time (no catching
        up when the machine is slow: simulated time then just runs slower)."""
        next_wall = time.monotonic()
        for k in range(RUN_STEPS + 1):
            if rospy.is_shutdown():
                return
            stamp = to_time(start_ns + k * STEP_NS)
            self.publish_clock(stamp)
            if k % 2 == 0:
                self.publish_tf(body, stamp)
            if k % 5 == 0:
                self.publish_boxes(tracks, stamp - BOX_LATENCY)
            if on_step is not None:
                on_step(k, stamp)
            next_wall += STEP_NS * 1e-9
            delay = next_wall - time.monotonic()
            if delay > 0:
                time.sleep(delay)
            elif delay < -0.1:
                next_wall = time.monotonic()


class ClockJumpTest(unittest.TestCase):
    def test_clock_jump(self):
        contacts = ContactsInOrder()
        diags = DiagnosticsCollector()
        sim = Simulator()
        self.assertTrue(sim.wait_connected(contacts, diags), "the node did not connect")
        time.sleep(0.5)  # the node's tf listener connects to /tf as well

        run1_tracks, run1_post = make_run(to_time(RUN1_NS), with_d=True)
        sim.run(RUN1_NS, run1_tracks, run1_post)
        end1 = to_time(RUN1_NS + RUN_STEPS * STEP_NS)

        run2_tracks, run2_post = make_run(to_time(RUN2_NS), with_d=False)
        late = {"sent": None}

        def send_late(k, stamp):
            # Once the node has published from the new clock (it has reset), a publisher
            # that noticed the jump later than the monitor delivers one more tf and box
            # array stamped at the end of run 1.
            if late["sent"] is None and any(
                    m.header.stamp < end1 - rospy.Duration(10.0) for m in contacts.all()[-5:]):
                sim.publish_tf(run1_post, end1)
                sim.publish_boxes(run1_tracks, end1)
                late["sent"] = stamp

        sim.run(RUN2_NS, run2_tracks, run2_post, send_late)
        time.sleep(0.5)  # the last arrays and diagnostics arrive; the clock stands still

        msgs = contacts.all()
        self.assertIsNotNone(late["sent"], "no contacts array after the jump")
        jump_at = to_time(RUN1_NS)
        first_post = next((i for i, m in enumerate(msgs) if m.header.stamp < jump_at), None)
        self.assertIsNotNone(first_post)
        pre, post = msgs[:first_post], msgs[first_post:]
        for m in post:
            self.assertLess(m.header.stamp, jump_at,
                            "an array stamped before the jump came after it")

        # Every array: contract and sane numbers.
        for m in msgs:
            check_array_basics(self, m)
            check_event_numbers(self, m, HORIZON)

        # Run 1: analytic from 0.5 s on (connections, tf history for the link's velocity).
        bodies1 = run1_tracks + [run1_post]
        checked1 = 0
        for m in pre:
            if (m.header.stamp - to_time(RUN1_NS)).to_sec() >= 0.5:
                self.assertEqual(m.status, ContactEventArray.OK, m.status_details)
                checked1 += check_scene_events(self, m, bodies1, HORIZON) > 0
        self.assertGreaterEqual(checked1, 20, "run 1 checked in only %d arrays" % checked1)
        active = set((e.id_a, e.id_b) for e in pre[-1].events if e.state != END)
        self.assertEqual(active, {("a", "b"), ("a", "d"), ("b", "d"), ("c", "post")},
                         "pairs at the end of run 1: %s" % [fmt_event(e) for e in pre[-1].events])

        # The reset: END for every pair of run 1 in the first array after the jump.
        reset = post[0]
        ended = set((e.id_a, e.id_b) for e in reset.events if e.state == END)
        self.assertEqual(ended, active, "first array after the jump: %s" % [
            fmt_event(e) for e in reset.events])
        for m in post[1:]:
            for e in m.events:
                self.assertNotIn("d", (e.id_a, e.id_b), "a track of run 1 only came back: " +
                                 fmt_event(e))
        for pair in (("a", "b"), ("c", "post")):
            seq = state_sequence(post, *pair)
            self.assertRegex(seq, r"^E\.*BO+$", "%s after the jump: %s" % (pair, seq))

        # The late transform (stamped ahead of the clock) was noticed, not used.
        self.assertTrue(any(degraded_about(m, "ahead of the clock") for m in post),
                        "the late tf was not reported: %s" % [
                            list(m.status_details) for m in post if m.status_details])

        # Run 2: contacts keep coming and are analytic again from 0.5 s on.
        self.assertGreaterEqual(len(post), 30, "only %d arrays in 3 s after the jump" % len(post))
        bodies2 = run2_tracks + [run2_post]
        checked2 = 0
        for m in post:
            s = (m.header.stamp - to_time(RUN2_NS)).to_sec()
            if s >= 0.5:
                self.assertEqual(m.status, ContactEventArray.OK, "s=%.2f %r" % (
                    s, m.status_details))
                self.assertEqual(check_scene_events(self, m, bodies2, HORIZON), 2)
                checked2 += 1
        self.assertGreaterEqual(checked2, 20, "run 2 checked in only %d arrays" % checked2)

        # Diagnostics: no reset before the jump, counted after it, healthy at the end.
        statuses = [(stamp, st) for stamp, st in diags.since(0.0)]
        before = [st for stamp, st in statuses if stamp >= jump_at]
        after = [st for stamp, st in statuses if stamp < jump_at and
                 stamp >= to_time(RUN2_NS)]
        self.assertTrue(before, "no diagnostics before the jump")
        for st in before:
            self.assertEqual(int(diag_values(st)[RESETS]), 0)
        self.assertGreaterEqual(len(after), 2, "diagnostics stopped after the jump (%d)" %
                                len(after))
        for st in after:
            self.assertGreaterEqual(int(diag_values(st)[RESETS]), 1, diag_values(st))
        last = diag_values(after[-1])
        self.assertEqual(after[-1].level, 0, "%s %s" % (after[-1].message, last))
        self.assertEqual(int(last["tracks"]), 3, last)
        self.assertEqual(int(last["robot bodies not posed"]), 0, last)


if __name__ == "__main__":
    rospy.init_node("test_clock_jump")
    rostest.rosrun("workspace_proximity", "test_clock_jump", ClockJumpTest)
