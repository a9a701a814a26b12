#!/usr/bin/env python3
"""Flood: TrackedBoxArray at 300 Hz into a node cycling at 30 Hz, then a burst of 500 arrays
back-to-back, then 300 Hz again.

Scene (1 m cubes): a from (-5, 0, 0) at +0.5 m/s and b from (5, 0, 0) at -0.5 m/s, head-on;
at y = 5 a "probe" from (-4.5, 5, 0) moving +0.5 m/s whose messages carry no velocity (a
tracker without velocity estimates) and a "wall" from (6, 5, 0) at -1 m/s (velocity
reported). Each array is stamped when it is published and carries every box at that stamp.

The node extrapolates the wall to the cycle instant but not the probe, so the (probe, wall)
distance tells which array a contacts array was computed from: its stamp is
s = T - (distance - true gap at T) / 0.5. Checks:
- contacts arrive at about the node's rate during the flood and through the burst (30 Hz
  +-40 % over a 3 s window; no gap between arrays over 0.5 s);
- every array uses data at most 0.1 s older than the newest array published before its
  cycle (a queue processed one array per cycle would fall seconds behind), and its
  (probe, wall) time to contact is distance / 1 m/s, the analytic value for that data;
- the head-on pair (a, b) has its analytic time to contact, distance and separation time;
- /diagnostics counts the skipped arrays under "dropped: superseded" and reports the
  source's rate within a factor 2 of the measured publishing rate; the node is alive after.
"""
import os
import sys
import threading
import time
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402
from geometry_msgs.msg import Vector3  # noqa: E402

from wp_node_testlib import (END, TIME_TOL, DiagnosticsCollector, Track,  # noqa: E402
                             TrackedBoxArray, aabb_prediction, check_array_basics,
                             check_event_numbers, check_face_contact, connected_collector,
                             diag_values, events_for, fmt_event)

HORIZON = 10.0
RATE = 30.0
INPUT_RATE = 300.0
PROBE_V, WALL_V = 0.5, 1.0
SOURCE = "/tracked_objects"


class NoVelocity(Track):
    """A Track whose messages say it stands still."""

    def to_msg(self, stamp):
        b = Track.to_msg(self, stamp)
        b.twist.linear = Vector3(0.0, 0.0, 0.0)
        return b


class Flooder(object):
    """Publishes the scene from a thread; records every published stamp (monotonic order)."""

    def __init__(self, tracks):
        self.pub = rospy.Publisher("tracked_objects", TrackedBoxArray, queue_size=1000)
        self.tracks = tracks
        self.lock = threading.Lock()
        self.stamps = []
        self.phase_counts = {}

    def publish_one(self, phase):
        msg = TrackedBoxArray()
        msg.header.frame_id = "world"
        with self.lock:
            msg.header.stamp = rospy.Time.now()
            msg.boxes = [tr.to_msg(msg.header.stamp) for tr in self.tracks]
            self.pub.publish(msg)
            self.stamps.append(msg.header.stamp)
            self.phase_counts[phase] = self.phase_counts.get(phase, 0) + 1

    def steady(self, seconds, phase):
        period = 1.0 / INPUT_RATE
        start = time.monotonic()
        next_wall = start
        while time.monotonic() - start < seconds and not rospy.is_shutdown():
            self.publish_one(phase)
            next_wall += period
            delay = next_wall - time.monotonic()
            if delay > 0:
                time.sleep(delay)
            elif delay < -0.05:
                next_wall = time.monotonic()  # fell behind: no catch-up burst here
        return time.monotonic() - start

    def burst(self, count, phase):
        for _ in range(count):
            self.publish_one(phase)

    def newest_before(self, stamp):
        with self.lock:
            best = None
            for s in self.stamps:
                if s <= stamp:
                    best = s
            return best


class FloodTest(unittest.TestCase):
    def test_flood(self):
        diags = DiagnosticsCollector()
        col = connected_collector(self)
        a = Track("a", "default", (-5.0, 0.0, 0.0), (1, 1, 1), (0.5, 0.0, 0.0))
        b = Track("b", "default", (5.0, 0.0, 0.0), (1, 1, 1), (-0.5, 0.0, 0.0))
        probe = NoVelocity("probe", "default", (-4.5, 5.0, 0.0), (1, 1, 1), (PROBE_V, 0, 0))
        wall = Track("wall", "default", (6.0, 5.0, 0.0), (1, 1, 1), (-WALL_V, 0.0, 0.0))
        tracks = [a, b, probe, wall]
        flood = Flooder(tracks)
        deadline = time.monotonic() + 10.0
        while flood.pub.get_num_connections() < 1 and time.monotonic() < deadline:
            time.sleep(0.02)
        t0 = rospy.Time.now()
        for tr in tracks:
            tr.set_t0(t0)
        steady_seconds = flood.steady(4.0, "steady")
        burst_start = rospy.Time.now()
        flood.burst(500, "burst")
        burst_end = rospy.Time.now()
        flood.steady(1.5, "after")
        end = rospy.Time.now()
        time.sleep(0.3)
        measured_rate = flood.phase_counts["steady"] / steady_seconds
        rospy.loginfo("flood: published %r, steady %.0f Hz, burst took %.3f s",
                      flood.phase_counts, measured_rate, (burst_end - burst_start).to_sec())

        msgs = [m for m in col.contact_msgs(since=t0) if m.header.stamp <= end]
        # Rate: 30 Hz +-40 % over a 3 s window of the flood, and no long gap anywhere.
        window = [m for m in msgs if t0 + rospy.Duration(0.5) <= m.header.stamp <
                  t0 + rospy.Duration(3.5)]
        self.assertTrue(0.6 * 3 * RATE <= len(window) <= 1.4 * 3 * RATE,
                        "%d contacts arrays in 3 s at %.0f Hz" % (len(window), RATE))
        stamps = [m.header.stamp.to_sec() for m in msgs]
        gaps = [y - x for x, y in zip(stamps, stamps[1:])]
        self.assertLess(max(gaps), 0.5, "longest gap between contacts arrays %.3f s" % max(gaps))
        through_burst = [m for m in msgs if burst_start <= m.header.stamp <= end]
        span = (end - burst_start).to_sec()
        self.assertGreaterEqual(len(through_burst), 0.6 * RATE * span,
                                "%d arrays in the %.2f s from the burst on" % (
                                    len(through_burst), span))

        # Freshness and analytic numbers.
        half = (0.5, 0.5, 0.5)
        ages = []
        checked = 0
        for m in msgs:
            check_array_basics(self, m)
            check_event_numbers(self, m, HORIZON)
            T = m.header.stamp
            if (T - t0).to_sec() < 0.3:
                continue
            pw = [e for e in events_for(m, "probe", "wall") if e.state != END]
            ab = [e for e in events_for(m, "a", "b") if e.state != END]
            self.assertEqual((len(pw), len(ab)), (1, 1), "T-t0=%.3f: %s" % (
                (T - t0).to_sec(), [fmt_event(e) for e in m.events]))
            ev = pw[0]
            (cp, _), (cw, _) = probe.state(T), wall.state(T)
            true_gap = cw[0] - cp[0] - 1.0
            used = T - rospy.Duration((ev.distance - true_gap) / PROBE_V)
            newest = flood.newest_before(T)
            ctx = "T-t0=%.4f %s data used from T-%.4f s, newest published T-%.4f s" % (
                (T - t0).to_sec(), fmt_event(ev), (T - used).to_sec(),
                (T - newest).to_sec() if newest else float("nan"))
            self.assertGreaterEqual((T - used).to_sec(), -2e-3, "data from the future? " + ctx)
            self.assertLessEqual((newest - used).to_sec(), 0.1, "stale data: " + ctx)
            ages.append((T - used).to_sec())
            self.assertAlmostEqual(ev.time_to_contact, ev.distance / WALL_V, delta=TIME_TOL,
                                   msg=ctx)
            ca, va = a.state(T)
            cb, vb = b.state(T)
            exp = aabb_prediction(ca, half, va, cb, half, vb, HORIZON)
            check_face_contact(self, ab[0], exp, ca, half, cb, half, "T-t0=%.3f" % (
                (T - t0).to_sec()))
            checked += 1
        self.assertGreaterEqual(checked, 100, "checked only %d arrays" % checked)
        ages.sort()
        rospy.loginfo("flood: age of the data used: median %.4f s, max %.4f s",
                      ages[len(ages) // 2], ages[-1])

        # Diagnostics: superseded arrays counted, the source's rate plausible, node alive.
        last = diags.wait_for(lambda st, v: True, 5.0, since=time.monotonic())
        self.assertIsNotNone(last, "no diagnostics after the flood")
        v = diag_values(last)
        published = sum(flood.phase_counts.values())
        superseded = int(v.get("dropped: superseded", "0"))
        self.assertGreaterEqual(superseded, 0.25 * published,
                                "superseded %d of %d published: %s" % (superseded, published, v))
        self.assertLessEqual(superseded, published, v)
        rates = [float(diag_values(st)["source %s rate (Hz)" % SOURCE])
                 for stamp, st in diags.since(0.0)
                 if t0 + rospy.Duration(1.5) <= stamp <= burst_start]
        self.assertTrue(rates, "no diagnostics during the steady flood")
        for r in rates:
            self.assertTrue(0.5 * measured_rate <= r <= 2.0 * measured_rate,
                            "source rate %.1f Hz reported, %.1f Hz published" % (
                                r, measured_rate))
        with col.lock:
            n_before = len(col.contacts)
        time.sleep(0.5)
        with col.lock:
            self.assertGreater(len(col.contacts), n_before, "the node stopped publishing")


if __name__ == "__main__":
    rospy.init_node("test_flood")
    rostest.rosrun("workspace_proximity", "test_flood", FloodTest)
