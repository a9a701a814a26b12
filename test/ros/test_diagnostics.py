#!/usr/bin/env python3
"""/diagnostics of proximity_monitor (status "proximity_monitor: proximity monitor",
~diagnostic_period 0.25 s, node at 20 Hz).

Scene (1 m cubes): a at (-0.4, 0, 0) and b at (0.4, 0, 0) overlap (a contact now); c at
(0, 5.5, 0) overlaps the robot body "post" (0.4 m cube on frame "carriage" at (0, 5, 0),
broadcast on /tf at 50 Hz); e at (10, -10, 0) moves +x at 0.2 m/s far from everything. So:
4 tracks, 1 robot body, 2 predicted contacts.

Phases and checks:
1. healthy, arrays at 20 Hz: level OK "predicting"; cycles increase at about the node's rate
   (+-40 %); cycle time (last, max) present, >= 0, max >= last; tracks 4, robot bodies 1,
   none unposed, predicted contacts 2, broad-phase pairs >= 2, no reset, no tf failure
   added; the source's rate within a factor 2 of 20 Hz and its age under 0.5 s; no dropped
   boxes other than superseded arrays.
2. bad boxes in the same arrays (NaN position, a zero edge, an empty id): "dropped:
   non-finite", "dropped: dimensions", "dropped: empty id" count up; still 4 tracks and OK.
3. irregular delivery: the same 20 arrays/s arrive in pairs 5 ms apart (two trackers on one
   topic): the rate stays within a factor 2 of 20 Hz.
4. the link's tf stops for 1.5 s: WARN "degraded: ... post ...", 1 body not posed, tf
   failures counting; OK again once tf is back.
5. the source goes silent: WARN "degraded: source /tracked_objects ...", once its age is
   over min(~source_timeout, ~track_timeout) (0.5 s here: never "clear" from a silent
   source whose tracks have just been dropped), and still WARN when the tracks are 0.
ERROR (a cycle longer than the period) is covered by test_diagnostics_overrun.py.
"""
import math
import os
import sys
import threading
import time
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402

from wp_node_testlib import (DiagnosticsCollector, ScenePublisher, TfBroadcaster,  # noqa: E402
                             Track, diag_values)

OK, WARN = 0, 1
RATE = 20.0
INPUT_RATE = 20.0
SOURCE = "/tracked_objects"
RATE_KEY = "source %s rate (Hz)" % SOURCE
AGE_KEY = "source %s age (s)" % SOURCE


class Malformed(Track):
    def __init__(self, box_id, spoil):
        Track.__init__(self, box_id, "default", (-0.4, 0.0, 0.0), (1, 1, 1))
        self.spoil = spoil

    def to_msg(self, stamp):
        b = Track.to_msg(self, stamp)
        self.spoil(b)
        return b


def nan_position(b):
    b.pose.position.x = math.nan


def zero_edge(b):
    b.dimensions.y = 0.0


class Source(object):
    """Publishes the scene: "steady" (20 Hz), "pairs" (two arrays 5 ms apart every 100 ms)
    or "silent"."""

    def __init__(self, scene):
        self.scene = scene
        self.mode = "steady"
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self.run)
        self.thread.daemon = True

    def run(self):
        while not self.stop.is_set() and not rospy.is_shutdown():
            mode = self.mode
            if mode == "steady":
                self.scene.publish_once()
                self.stop.wait(1.0 / INPUT_RATE)
            elif mode == "pairs":
                self.scene.publish_once()
                time.sleep(0.005)
                self.scene.publish_once()
                self.stop.wait(2.0 / INPUT_RATE - 0.005)
            else:
                self.stop.wait(0.02)


def num(values, key):
    return float(values[key])


class DiagnosticsTest(unittest.TestCase):
    def window(self, diags, start, end):
        with diags.lock:
            return [st for t, _, st in diags.statuses if start <= t <= end]

    def test_diagnostics(self):
        diags = DiagnosticsCollector()
        # world -> carriage at (0, 5, 0), re-stamped at 50 Hz, unless paused.
        link = TfBroadcaster("world", "carriage", lambda stamp: (0.0, 5.0, 0.0))
        tracks = [Track("a", "default", (-0.4, 0.0, 0.0), (1, 1, 1)),
                  Track("b", "default", (0.4, 0.0, 0.0), (1, 1, 1)),
                  Track("c", "default", (0.0, 5.5, 0.0), (1, 1, 1)),
                  Track("e", "default", (10.0, -10.0, 0.0), (1, 1, 1), (0.2, 0.0, 0.0))]
        scene = ScenePublisher("tracked_objects", tracks, latency=0.05)
        self.assertTrue(scene.wait_connected(), "the node did not subscribe")
        self.assertIsNotNone(diags.wait_for(lambda st, v: True, 10.0), "no diagnostics")
        t0 = rospy.Time.now()
        for tr in tracks:
            tr.set_t0(t0)
        source = Source(scene)
        source.thread.start()

        # 1. Healthy.
        start = time.monotonic()
        time.sleep(3.0)
        healthy = self.window(diags, start + 1.5, time.monotonic())
        self.assertGreaterEqual(len(healthy), 4, "%d statuses in 1.5 s" % len(healthy))
        first, last = diag_values(healthy[0]), diag_values(healthy[-1])
        for st in healthy:
            v = diag_values(st)
            ctx = "%d %s %s" % (st.level, st.message, v)
            self.assertEqual((st.level, st.message), (OK, "predicting"), ctx)
            self.assertEqual(st.hardware_id, "workspace_proximity", ctx)
            self.assertEqual(int(v["tracks"]), 4, ctx)
            self.assertEqual(int(v["robot bodies"]), 1, ctx)
            self.assertEqual(int(v["robot bodies not posed"]), 0, ctx)
            self.assertEqual(int(v["predicted contacts"]), 2, ctx)
            self.assertGreaterEqual(int(v["broad-phase pairs"]), 2, ctx)
            self.assertEqual(int(v["history resets (clock jumps)"]), 0, ctx)
            self.assertTrue(0.0 <= num(v, "cycle time (ms)") <= num(v, "max cycle time (ms)"),
                            ctx)
            self.assertTrue(0.5 * INPUT_RATE <= num(v, RATE_KEY) <= 2.0 * INPUT_RATE, ctx)
            self.assertTrue(0.0 <= num(v, AGE_KEY) < 0.5, ctx)
            self.assertNotIn("degraded", v, ctx)
            dropped = [k for k in v if k.startswith("dropped: ") and k != "dropped: superseded"]
            self.assertEqual(dropped, [], ctx)
        self.assertEqual(first["tf failures"], last["tf failures"],
                         "tf failures while tf is fine")
        cycles = [int(diag_values(st)["cycles"]) for st in healthy]
        self.assertEqual(cycles, sorted(set(cycles)), "cycles not increasing: %s" % cycles)
        span = self.stamp_of(diags, healthy[-1]) - self.stamp_of(diags, healthy[0])
        cycle_rate = (cycles[-1] - cycles[0]) / span
        self.assertTrue(0.6 * RATE <= cycle_rate <= 1.4 * RATE,
                        "%.1f cycles/s at %.0f Hz" % (cycle_rate, RATE))

        # 2. Bad boxes in the same arrays: dropped by reason, the rest is used.
        bad = [Malformed("bad_nan", nan_position), Malformed("bad_zero_edge", zero_edge),
               Malformed("", lambda b: None)]
        for b in bad:
            b.set_t0(t0)
        with scene.lock:
            scene.tracks.extend(bad)
        start = time.monotonic()
        want = ("dropped: non-finite", "dropped: dimensions", "dropped: empty id")
        st = diags.wait_for(lambda st, v: all(int(v.get(k, "0")) > 0 for k in want), 5.0,
                            since=start + 0.3)
        self.assertIsNotNone(st, "dropped boxes not counted: %s" % diag_values(diags.latest()))
        time.sleep(0.6)
        with scene.lock:
            for b in bad:
                scene.tracks.remove(b)
        for st in self.window(diags, start + 0.3, time.monotonic()):
            v = diag_values(st)
            self.assertEqual((st.level, int(v["tracks"]), int(v["predicted contacts"])),
                             (OK, 4, 2), "%s %s" % (st.message, v))
        counts = [int(diag_values(st).get("dropped: non-finite", "0"))
                  for st in self.window(diags, start, time.monotonic())]
        self.assertEqual(counts, sorted(counts), "a dropped count went down: %s" % counts)

        # 3. Irregular delivery: 20 arrays/s in pairs 5 ms apart.
        source.mode = "pairs"
        start = time.monotonic()
        time.sleep(3.0)
        pairs = self.window(diags, start + 2.0, time.monotonic())
        self.assertTrue(pairs, "no diagnostics while the source sent pairs")
        for st in pairs:
            v = diag_values(st)
            self.assertTrue(0.5 * INPUT_RATE <= num(v, RATE_KEY) <= 2.0 * INPUT_RATE,
                            "rate %s Hz reported for 20 arrays/s sent in pairs" % v[RATE_KEY])
            self.assertEqual(st.level, OK, "%s %s" % (st.message, v))
        source.mode = "steady"

        # 4. The link's tf stops: WARN naming the body, then OK again.
        before = diag_values(diags.latest())
        link.paused.set()
        start = time.monotonic()
        st = diags.wait_for(lambda st, v: st.level == WARN, 4.0, since=start)
        self.assertIsNotNone(st, "no WARN while the link's tf is missing: %s" % before)
        v = diag_values(st)
        self.assertTrue(st.message.startswith("degraded: ") and "post" in st.message,
                        st.message)
        self.assertEqual(int(v["robot bodies not posed"]), 1, v)
        self.assertGreater(int(v["tf failures"]), int(before["tf failures"]), v)
        self.assertTrue(any("post" in d for d in v["degraded[]"]), v)
        self.assertGreaterEqual(time.monotonic() - start, 0.4, "WARN before ~tf_timeout")
        time.sleep(1.0)
        link.paused.clear()
        start = time.monotonic()
        st = diags.wait_for(lambda st, v: st.level == OK, 4.0, since=start)
        self.assertIsNotNone(st, "still not OK after tf returned: %s" % diag_values(
            diags.latest()))
        self.assertEqual(int(diag_values(st)["robot bodies not posed"]), 0)

        # 5. The source goes silent: WARN naming it, tracks expire.
        source.mode = "silent"
        start = time.monotonic()
        st = diags.wait_for(lambda st, v: st.level == WARN, 5.0, since=start)
        self.assertIsNotNone(st, "no WARN while the source is silent: %s" % diag_values(
            diags.latest()))
        v = diag_values(st)
        self.assertTrue(st.message.startswith("degraded: source " + SOURCE), st.message)
        silent_after = 0.5  # min(~source_timeout 1.0, ~track_timeout 0.5)
        self.assertGreater(num(v, AGE_KEY), silent_after - 0.05, v)
        self.assertGreaterEqual(time.monotonic() - start, silent_after - 0.1,
                                "WARN before the source was silent for min(~source_timeout, "
                                "~track_timeout)")
        # Its tracks are dropped at about the same time; the status must not go back to OK.
        st = diags.wait_for(lambda st, v: int(v.get("tracks", "-1")) == 0, 3.0, since=start)
        self.assertIsNotNone(st, "tracks of the silent source never dropped: %s" % diag_values(
            diags.latest()))
        v = diag_values(st)
        self.assertEqual(st.level, WARN, "clear while the source is silent: %s" % v)
        self.assertEqual(int(v["predicted contacts"]), 0, v)
        source.stop.set()
        link.stop.set()

    @staticmethod
    def stamp_of(diags, status):
        with diags.lock:
            for _, stamp, st in diags.statuses:
                if st is status:
                    return stamp.to_sec()
        return math.nan


if __name__ == "__main__":
    rospy.init_node("test_diagnostics")
    rostest.rosrun("workspace_proximity", "test_diagnostics", DiagnosticsTest)
