#!/usr/bin/env python3
"""The offline replay of the shipped demo bag (test/bags/demo_cell.bag), end to end through
replay_bag as a user runs it (configuration files, URDF, report), checked against:

  1. the reviewed expected episodes (test/bags/demo_cell.episodes.csv): the same pairs and
     number of episodes, each starting and ending within one cycle of the reviewed times,
     with the same peak level;
  2. an independent geometric oracle (footprint_oracle.py) for every pair of tracked objects
     the configuration checks (the forklift with each person): at every cycle the pair is
     reported exactly when the oracle finds a contact within the horizon, with its time to
     contact (1 ms) and distance (1 mm), and the level the thresholds give;
  3. the same oracle's distance from the tool tip (a sphere posed by composing the bag's tf
     chain, interpolated to the cycle instant) to each tracked box (5 mm: the monitor
     extrapolates the newest transform with a finite-difference velocity instead);
  4. the bag itself read with the Python rosbag API: message counts and the cycle instants;
  5. the report: report.html self-contained with its two plots, one table row per episode,
     the configuration's fingerprint (also in the summary, another for another configuration);
  6. lz4- and bz2-compressed copies of the bag: the same events.csv, byte for byte.

    test_replay_episodes.py REPLAY_BAG [unittest args]
    test_replay_episodes.py REPLAY_BAG --print-episodes   (the episodes, in the file's format)
"""
import bisect
import math
import os
import re
import subprocess
import sys
import tempfile
import unittest

import numpy as np
import rosbag

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "tools"))
sys.path.insert(0, HERE)

import footprint_oracle as fo  # noqa: E402
import replay_data  # noqa: E402

BAG = os.path.join(ROOT, "test", "bags", "demo_cell.bag")
EXPECTED = os.path.join(ROOT, "test", "bags", "demo_cell.episodes.csv")
CONFIGS = [os.path.join(ROOT, "config", "proximity_monitor.yaml"),
           os.path.join(ROOT, "config", "demo_monitor.yaml"),
           # people at constant velocity, as reviewed and as the oracle predicts
           os.path.join(ROOT, "test", "bags", "demo_cell_constant_velocity.yaml")]
URDF = os.path.join(ROOT, "config", "demo_arm.urdf")
REPLAY_BAG = None  # from the command line

# The demo configuration's numbers the oracle needs (config/proximity_monitor.yaml).
RATE = 30.0
HORIZON = 2.0
MARGIN = {"person": 0.20, "forklift": 0.30}
THRESHOLDS = {  # warning_time, critical_time, warning_distance, critical_distance
    "person": (1.5, 0.6, 0.8, 0.3),
    "forklift": (2.0, 1.0, 1.0, 0.5),
}
ROBOT_MARGIN = 0.02
TIP_RADIUS = 0.06  # config/demo_arm.urdf, link tool_tip


def run_replay(out_dir, report=True, bag=BAG, configs=CONFIGS):
    cmd = [REPLAY_BAG, bag, "--urdf", URDF, "--out", out_dir]
    for c in configs:
        cmd += ["--config", c]
    if not report:
        cmd.append("--no-report")
    return subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE)


def level_of(ttc, dist, labels):
    """The level the thresholds give: the stricter of both labels' settings."""
    w_t = max(THRESHOLDS[l][0] for l in labels)
    c_t = max(THRESHOLDS[l][1] for l in labels)
    w_d = max(THRESHOLDS[l][2] for l in labels)
    c_d = max(THRESHOLDS[l][3] for l in labels)
    if ttc <= c_t or dist <= c_d:
        return "CRITICAL"
    if ttc <= w_t or dist <= w_d:
        return "WARNING"
    return "NOTICE"


def near_threshold(ttc, dist, labels, tol_t=2e-3, tol_d=2e-3):
    for l in labels:
        w_t, c_t, w_d, c_d = THRESHOLDS[l]
        if min(abs(ttc - w_t), abs(ttc - c_t)) < tol_t or min(abs(dist - w_d), abs(dist - c_d)) < tol_d:
            return True
    return False


def quat_matrix(q):
    x, y, z, w = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


class BagData(object):
    """The bag read independently of the replay: arrays by receive time, and the tool tip's
    position in the world from each /tf message's chain."""

    def __init__(self, path):
        bag = rosbag.Bag(path)
        self.begin = bag.get_start_time()
        self.end = bag.get_end_time()
        self.counts = {t: i.message_count for t, i in bag.get_type_and_topic_info().topics.items()}
        self.arrays = [(t.to_nsec(), m) for _, m, t in bag.read_messages(topics=["/tracked_objects"])]
        self.receipts = [a[0] for a in self.arrays]
        self.tips = []
        for _, m, _t in bag.read_messages(topics=["/tf"]):
            chain = {}
            for tr in m.transforms:
                r = tr.transform.rotation
                p = tr.transform.translation
                chain[tr.child_frame_id] = (tr.header.frame_id, quat_matrix((r.x, r.y, r.z, r.w)),
                                            np.array([p.x, p.y, p.z]), tr.header.stamp.to_nsec())
            frame, pos = "tool_tip", np.zeros(3)
            while frame != "world":
                parent, rot, trans, _ = chain[frame]
                pos = rot.dot(pos) + trans
                frame = parent
            self.tips.append((chain["tool_tip"][3], pos))
        self.tip_stamps = [t[0] for t in self.tips]
        bag.close()

    def array_at(self, ns):
        """The newest array received at or before `ns` (what the cycle at `ns` predicts from)."""
        i = bisect.bisect_right(self.receipts, ns) - 1
        return self.arrays[i][1] if i >= 0 else None

    def boxes_at(self, ns):
        """{id: (label, Box2D at ns, z centre, half height)}: each box moved from its stamp to
        `ns` with its twist (the monitor's latency compensation)."""
        msg = self.array_at(ns)
        out = {}
        if msg is None:
            return out
        dt = (ns - msg.header.stamp.to_nsec()) * 1e-9
        for b in msg.boxes:
            q = b.pose.orientation
            yaw = 2.0 * math.atan2(q.z, q.w)  # upright boxes: a turn about z
            fp = fo.Box2D(b.pose.position.x, b.pose.position.y, yaw, b.dimensions.x / 2,
                          b.dimensions.y / 2, b.twist.linear.x, b.twist.linear.y, b.twist.angular.z)
            out[b.id] = (b.label, fp.at(dt), b.pose.position.z, b.dimensions.z / 2)
        return out

    def tip_at(self, ns):
        """The tool tip interpolated between the /tf messages around `ns` (None outside)."""
        i = bisect.bisect_right(self.tip_stamps, ns)
        if i <= 0 or i >= len(self.tips):
            return None
        (t0, p0), (t1, p1) = self.tips[i - 1], self.tips[i]
        return p0 + (ns - t0) / float(t1 - t0) * (p1 - p0)


class ReplayEpisodesTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.out = os.path.join(cls.tmp.name, "out")
        cls.replay = run_replay(cls.out)
        cls.summary = replay_data.read_summary(cls.out) if cls.replay.returncode == 0 else None
        if cls.summary is not None:
            cls.events = list(replay_data.read_events(os.path.join(cls.out, "events.csv")))
            cls.cycles = list(replay_data.read_cycles(os.path.join(cls.out, "cycles.csv")))
            cls.episodes = replay_data.episodes(cls.events)
        cls.bag = BagData(BAG)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def setUp(self):
        self.assertEqual(self.replay.returncode, 0, self.replay.stderr.decode(errors="replace"))

    def test_episodes_match_the_reviewed_file(self):
        expected = replay_data.read_expected(EXPECTED)
        self.assertGreater(len(expected), 0)
        problems = replay_data.compare_episodes(self.episodes, expected, 1.0 / RATE + 1e-6)
        self.assertEqual(problems, [], "\n".join(problems))

    def test_object_pairs_against_the_footprint_oracle(self):
        by_cycle = {}
        for e in self.events:
            by_cycle.setdefault(round(e.stamp * 1e9), {})[e.pair] = e
        compared = 0
        for c in self.cycles:
            ns = round(c["stamp"] * 1e9)
            boxes = self.bag.boxes_at(ns)
            for person in ("person_1", "person_2", "person_3"):
                if "forklift_1" not in boxes or person not in boxes:
                    continue
                (la, a, za, ha), (lb, b, zb, hb) = boxes["forklift_1"], boxes[person]
                self.assertLess(abs(za - zb), ha + hb)  # height intervals overlap: 2-D suffices
                reach = MARGIN[la] + MARGIN[lb]
                ttc = fo.first_contact(a, b, reach, HORIZON)
                gap = max(0.0, fo.distance(a, b) - reach)
                e = by_cycle.get(ns, {}).get(("forklift_1", person))
                reported = e is not None and e.state != "END"
                where = "forklift_1 <-> %s at t = %.3f s" % (person, c["t"])
                if ttc is not None and abs(ttc - HORIZON) < 2e-3:
                    continue  # on the horizon: either answer is right
                self.assertEqual(reported, ttc is not None, "%s: reported %s, oracle ttc %s" % (where, reported, ttc))
                if not reported:
                    continue
                compared += 1
                self.assertLessEqual(e.time_to_contact, ttc + 1e-3, where + ": later than the oracle")
                self.assertAlmostEqual(e.time_to_contact, ttc, delta=1e-3, msg=where)
                self.assertAlmostEqual(e.distance, gap, delta=1e-3, msg=where)
                if not near_threshold(ttc, gap, (la, lb)):
                    self.assertEqual(e.level, level_of(ttc, gap, (la, lb)), where)
        self.assertGreater(compared, 50, "too few object-pair predictions compared")

    def test_tool_tip_distances_against_the_tf_chain(self):
        compared = 0
        for e in self.events:
            if e.state == "END" or "tool_tip" not in e.pair:
                continue
            ns = round(e.stamp * 1e9)
            tip = self.bag.tip_at(ns)
            if tip is None:
                continue
            obj = e.pair[0] if e.pair[1] == "tool_tip" else e.pair[1]
            label, fp, z, hz = self.bag.boxes_at(ns)[obj]
            d = tip - np.array([fp.x, fp.y, z])
            c, s = math.cos(fp.yaw), math.sin(fp.yaw)
            local = np.array([c * d[0] + s * d[1], -s * d[0] + c * d[1], d[2]])
            outside = np.maximum(np.abs(local) - np.array([fp.hx, fp.hy, hz]), 0.0)
            gap = max(0.0, np.linalg.norm(outside) - TIP_RADIUS - ROBOT_MARGIN - MARGIN[label])
            self.assertAlmostEqual(e.distance, gap, delta=5e-3,
                                   msg="%s at t = %.3f s" % (" <-> ".join(e.pair), e.t))
            compared += 1
        self.assertGreater(compared, 100, "too few tool tip events compared")

    def test_counts_and_cycle_instants_against_the_bag(self):
        s = self.summary
        self.assertEqual(s["arrays"], self.bag.counts["/tracked_objects"])
        self.assertEqual(s["tf_messages"], self.bag.counts["/tf"])
        self.assertEqual(s["tf_static_messages"], self.bag.counts.get("/tf_static", 0))
        self.assertAlmostEqual(s["bag_begin"], self.bag.begin, delta=1e-6)
        self.assertAlmostEqual(s["bag_end"], self.bag.end, delta=1e-6)
        # A cycle every 1 / rate of bag time from the first message, up to the last one.
        period_ns = round(1e9 / RATE)
        begin_ns = round(self.bag.begin * 1e9)
        expected = (round(self.bag.end * 1e9) - begin_ns) // period_ns
        self.assertEqual(len(self.cycles), expected)
        for k, c in enumerate(self.cycles):
            self.assertLess(abs(round(c["stamp"] * 1e9) - (begin_ns + (k + 1) * period_ns)), 1000)
        self.assertEqual(s["cycles"], len(self.cycles))
        self.assertEqual(s["missing_frames"], [])
        self.assertGreaterEqual(s["speed_factor"], 1.0)  # sanity only; speed is measured in scripts/bench

    def test_the_shipped_person_growth_only_brings_contacts_earlier(self):
        # The shipped configuration (people's margins grow, docs/node.md "Tracked objects
        # within bounds"): a grown person contains the constant-velocity one at every instant, so
        # every contact predicted without growth is predicted with it too, never later, at a
        # level never lower; and a person's pair is reported at least as often.
        out = os.path.join(self.tmp.name, "growth")
        run = run_replay(out, report=False, configs=CONFIGS[:2])
        self.assertEqual(run.returncode, 0, run.stderr.decode(errors="replace"))
        # Another configuration, another fingerprint (16 hex digits in both summaries).
        fingerprint = replay_data.read_summary(out)["config_fingerprint"]
        self.assertRegex(fingerprint, "^[0-9a-f]{16}$")
        self.assertRegex(self.summary["config_fingerprint"], "^[0-9a-f]{16}$")
        self.assertNotEqual(fingerprint, self.summary["config_fingerprint"])
        grown = {}
        for e in replay_data.read_events(os.path.join(out, "events.csv")):
            if e.state != "END":
                grown[(round(e.stamp * 1e9), e.pair)] = e
        compared = 0
        for e in self.events:
            if e.state == "END":
                continue
            g = grown.get((round(e.stamp * 1e9), e.pair))
            self.assertIsNotNone(g, "%s at %.3f s: lost with growth" % (e.pair, e.t))
            self.assertLessEqual(g.time_to_contact, e.time_to_contact + 1e-6, e.pair)
            self.assertGreaterEqual(replay_data.LEVEL_RANK[g.level], replay_data.LEVEL_RANK[e.level],
                                    e.pair)
            compared += 1
        self.assertGreater(compared, 500)
        self.assertGreater(len(grown), compared)  # people reached only through growth

    def test_compressed_copies_replay_identically(self):
        with open(os.path.join(self.out, "events.csv"), "rb") as f:
            plain = f.read()
        for compression in ("lz4", "bz2"):
            copy = os.path.join(self.tmp.name, "%s.bag" % compression)
            with rosbag.Bag(BAG) as inp, rosbag.Bag(copy, "w", compression=compression) as out:
                for topic, msg, t in inp.read_messages():
                    out.write(topic, msg, t)
            out_dir = os.path.join(self.tmp.name, "out-" + compression)
            run = run_replay(out_dir, report=False, bag=copy)
            self.assertEqual(run.returncode, 0, run.stderr.decode(errors="replace"))
            with open(os.path.join(out_dir, "events.csv"), "rb") as f:
                self.assertEqual(f.read(), plain, compression)

    def test_speed_scale_per_cycle(self):
        # Speed and separation monitoring with the defaults: every cycle has a scale; while
        # DEGRADED it is degraded_scale (0); it never exceeds the raw scale, which is the
        # formula of its limiting pair's separation and approach speed.
        per_speed = 0.1 + 0.3 / 2.0
        limited = stopped = 0
        for c in self.cycles:
            self.assertIsNotNone(c["speed_scale"], c)
            self.assertTrue(0.0 <= c["speed_scale"] <= c["raw_scale"] + 1e-6 <= 1.0 + 1e-6, c)
            if c["status"] == "DEGRADED":
                self.assertEqual(c["speed_scale"], 0.0, c)
            if c["ssm_object"]:
                d, v_h = c["separation"], c["approach_speed"]
                self.assertAlmostEqual(c["required_separation"],
                                       v_h * 0.4 + 1.0 * per_speed + 0.22, delta=2e-6, msg=c)
                raw = min(1.0, max(0.0, (d - v_h * 0.4 - 0.22) / per_speed))
                self.assertAlmostEqual(c["raw_scale"], raw, delta=1e-5, msg=c)  # 6 decimals in the CSV
                self.assertIn(c["ssm_robot"], ("base_link", "shoulder_link", "upper_arm", "forearm",
                                               "tool", "tool_tip"))
                limited += 1
            else:
                self.assertEqual(c["raw_scale"], 1.0, c)
            stopped += c["speed_scale"] == 0.0 and c["status"] == "OK"
        self.assertGreater(limited, 100)
        self.assertGreater(stopped, 20)

    def test_report(self):
        stdout = self.replay.stdout.decode()
        self.assertIn("episodes (%d):" % len(self.episodes), stdout)
        self.assertIn("x real time", stdout)
        # The configuration's fingerprint in the printed summary and the report.
        fingerprint = self.summary["config_fingerprint"]
        self.assertIn("config: fingerprint %s\n" % fingerprint, stdout)
        with open(os.path.join(self.out, "report.html")) as f:
            page = f.read()
        self.assertIn(fingerprint, page)
        # min_ttc, speed_scale, timelines
        self.assertEqual(len(re.findall(r'src="data:image/png;base64,[A-Za-z0-9+/=]{1000,}"', page)), 3)
        self.assertNotIn('src="http', page)  # self-contained
        rows = re.findall(r"<tr class=\"(notice|warning|critical)\">", page)
        self.assertEqual(len(rows), len(self.episodes))
        self.assertIn("protective stops", page)
        for name in ("min_ttc.png", "speed_scale.png", "timelines.png"):
            with open(os.path.join(self.out, name), "rb") as f:
                self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")


def main():
    global REPLAY_BAG
    if len(sys.argv) < 2:
        sys.exit("usage: test_replay_episodes.py REPLAY_BAG [unittest args | --print-episodes]")
    REPLAY_BAG = sys.argv.pop(1)
    if "--print-episodes" in sys.argv:
        with tempfile.TemporaryDirectory() as tmp:
            run = run_replay(tmp, report=False)
            if run.returncode != 0:
                sys.exit(run.stderr.decode(errors="replace"))
            eps = replay_data.episodes(replay_data.read_events(os.path.join(tmp, "events.csv")))
            replay_data.write_expected(eps, sys.stdout)
        return
    unittest.main()


if __name__ == "__main__":
    main()
