#!/usr/bin/env python3
"""The audit trail (~audit_log) through the topics.

The robot is a static 1 m cube ("post" on base_link); a person (0.5 x 0.5 x 1.8 m) is tracked
at 20 Hz. ~ssm/hold_time 0.2 s, max_increase_rate 5 / s, degraded_scale 0 (the default),
source_timeout 1 s, track_timeout 0.5 s. The scene, after the node is up and the scale is 1:
  B  the person stands 0.1 m from the post for 1 s: a protective stop (stop_begin), then 5 m
     away for 1.5 s: the scale rises (stop_end);
  C  the tracker goes silent: DEGRADED ("source /tracked_objects: ..."), and
     with it a stop (degraded_scale 0); then it publishes again: OK, and the stop ends;
  D  a change that validate() refuses (default_critical_time 5 s > warning_time 1 s):
     params_refused naming it; then ssm_hold_time 0.2 -> 0.3: params, naming the parameter with
     its old and new value and both fingerprints.
Checks on the file read with Python's csv module (RFC 4180): the header's columns; the node's
start line first, with the fingerprint safety_status showed; from B on exactly the lines
  stop_begin, stop_end, degraded, stop_begin, ok, stop_end, params_refused, params
(one per transition, not one per cycle: scores of cycles ran), each at a ROS stamp inside its phase and in
order; every line before the change carries the first fingerprint, the params line the new
one, which differs and which safety_status and /diagnostics ("config fingerprint") then show.
"""
import csv
import datetime
import os
import sys
import time
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402
from dynamic_reconfigure.client import Client  # noqa: E402

from wp_node_testlib import (DiagnosticsCollector, ScenePublisher, SsmCollector,  # noqa: E402
                             Track, broadcast_static, diag_values)

FAR = (5.0, 0.0, 0.9)
NEAR = (0.5 + 0.1 + 0.25, 0.0, 0.9)   # 0.1 m from the post's face
COLUMNS = ["wall_time", "ros_stamp", "kind", "reason", "config_fingerprint"]


def person(where):
    return Track("p1", "person", where, (0.5, 0.5, 1.8))


def stamp_of(row):
    sec, nsec = row["ros_stamp"].split(".")
    return rospy.Time(int(sec), int(nsec))


class AuditTrailTest(unittest.TestCase):
    def wait_status(self, ssm, predicate, timeout, since):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            msgs = ssm.statuses(since=since)
            if msgs and predicate(msgs[-1]):
                return msgs[-1]
            rospy.sleep(0.05)
        return None

    def place(self, scene, where):
        with scene.lock:
            tr = person(where)
            tr.set_t0(scene.t0)
            scene.tracks = [tr]

    def test_every_transition_with_the_fingerprint(self):
        path = rospy.get_param("~log")
        wall_start = datetime.datetime.now(datetime.timezone.utc)
        self.tf = broadcast_static([("world", "base_link", (0, 0, 0), (0, 0, 0))])
        ssm = SsmCollector()
        diag = DiagnosticsCollector()
        scene = ScenePublisher("tracked_objects", [person(FAR)], latency=0.05)
        t0 = scene.start()
        up = self.wait_status(ssm, lambda m: m.speed_scale == 1.0, 15.0, t0)
        self.assertIsNotNone(up, "the scale never reached 1 with the person far")
        fp0 = up.config_fingerprint
        self.assertRegex(fp0, "^[0-9a-f]{16}$")
        st = diag.wait_for(lambda s, v: v.get("config fingerprint") == fp0, 10.0)
        self.assertIsNotNone(st, "/diagnostics without the fingerprint %s" % fp0)
        self.assertEqual(diag_values(st).get("audit log"), path)

        t_b = rospy.Time.now()                                    # B: a stop, and its end
        self.place(scene, NEAR)
        self.assertIsNotNone(self.wait_status(ssm, lambda m: m.speed_scale == 0.0, 3.0, t_b))
        rospy.sleep(0.5)
        t_b_far = rospy.Time.now()
        self.place(scene, FAR)
        self.assertIsNotNone(self.wait_status(ssm, lambda m: m.speed_scale == 1.0, 3.0, t_b_far))

        t_c = rospy.Time.now()                                    # C: a silent tracker
        scene.stop()
        self.assertIsNotNone(self.wait_status(
            ssm, lambda m: m.status == m.DEGRADED and m.speed_scale == 0.0, 4.0, t_c))
        rospy.sleep(0.3)
        t_c_back = rospy.Time.now()
        scene = ScenePublisher("tracked_objects", [person(FAR)], latency=0.05)
        scene.start(t_c_back)
        self.assertIsNotNone(self.wait_status(
            ssm, lambda m: m.status == m.OK and m.speed_scale == 1.0, 4.0, t_c_back))

        t_d = rospy.Time.now()                                    # D: parameter changes
        client = Client("proximity_monitor", timeout=20)
        cfg = client.update_configuration({"default_critical_time": 5.0})
        self.assertEqual(cfg["default_critical_time"], 0.4, "the invalid change was not refused")
        cfg = client.update_configuration({"ssm_hold_time": 0.3})
        self.assertEqual(cfg["ssm_hold_time"], 0.3)
        t_changed = rospy.Time.now()
        changed = self.wait_status(ssm, lambda m: m.config_fingerprint != fp0, 3.0, t_changed)
        self.assertIsNotNone(changed, "safety_status kept the old fingerprint")
        fp1 = changed.config_fingerprint
        self.assertRegex(fp1, "^[0-9a-f]{16}$")
        st = diag.wait_for(lambda s, v: v.get("config fingerprint") == fp1, 10.0)
        self.assertIsNotNone(st, "/diagnostics without the new fingerprint %s" % fp1)
        rospy.sleep(0.5)
        scene.stop()
        t_end = rospy.Time.now()
        statuses = ssm.statuses(since=t0)

        with open(path, newline="") as f:
            reader = csv.reader(f)
            header = next(reader)
            rows = [dict(zip(header, r)) for r in reader]
        self.assertEqual(header, COLUMNS)
        for r in rows:
            self.assertEqual(len(r), len(COLUMNS), r)
        ctx = "\n".join("%s %s %s %r %s" % (r["ros_stamp"], r["wall_time"], r["kind"], r["reason"],
                                            r["config_fingerprint"]) for r in rows)
        self.assertEqual(rows[0]["kind"], "start", ctx)
        self.assertIn("proximity_monitor started", rows[0]["reason"])
        # In order of ROS time and wall time, and the wall time UTC of this run.
        for a, b in zip(rows, rows[1:]):
            self.assertLessEqual(stamp_of(a), stamp_of(b), ctx)
            self.assertLessEqual(a["wall_time"], b["wall_time"], ctx)
        for r in rows:
            wall = datetime.datetime.strptime(r["wall_time"], "%Y-%m-%dT%H:%M:%S.%fZ").replace(
                tzinfo=datetime.timezone.utc)
            self.assertGreaterEqual(wall, wall_start - datetime.timedelta(seconds=30), ctx)
            self.assertLessEqual(wall, datetime.datetime.now(datetime.timezone.utc), ctx)

        # Up to B: the start-up's transitions (no data yet, held at 0 until it rises), ending OK
        # and not stopped.
        before = [r for r in rows[1:] if stamp_of(r) < t_b]
        self.assertTrue(set(r["kind"] for r in before) <= {"degraded", "ok", "stop_begin", "stop_end"},
                        ctx)
        for kind_on, kind_off in (("degraded", "ok"), ("stop_begin", "stop_end")):
            seq = [r["kind"] for r in before if r["kind"] in (kind_on, kind_off)]
            self.assertTrue(not seq or seq[-1] == kind_off, ctx)

        after = [r for r in rows if stamp_of(r) >= t_b]
        self.assertEqual([r["kind"] for r in after],
                         ["stop_begin", "stop_end", "degraded", "stop_begin", "ok", "stop_end",
                          "params_refused", "params"], ctx)
        phases = [(t_b, t_b_far), (t_b_far, t_c), (t_c, t_c_back), (t_c, t_c_back),
                  (t_c_back, t_d), (t_c_back, t_d), (t_d, t_changed), (t_d, t_changed)]
        for r, (lo, hi) in zip(after, phases):
            self.assertTrue(lo <= stamp_of(r) <= hi + rospy.Duration(0.1),
                            "%s at %s outside [%s, %s]\n%s" % (r["kind"], r["ros_stamp"], lo, hi, ctx))
        self.assertIn("p1", after[0]["reason"], ctx)                      # who stopped it
        self.assertIn("speed scale", after[1]["reason"], ctx)
        self.assertIn("source /tracked_objects", after[2]["reason"], ctx)
        self.assertIn("critical_time", after[6]["reason"], ctx)
        self.assertTrue(after[7]["reason"].startswith("ssm/hold_time: 0.2 -> 0.3; "), ctx)
        self.assertIn("fingerprint %s -> %s" % (fp0, fp1), after[7]["reason"], ctx)

        # The fingerprint: the first one on every line until the change, the new one on it.
        for r in rows[:-1]:
            self.assertEqual(r["config_fingerprint"], fp0, ctx)
        self.assertEqual(rows[-1]["config_fingerprint"], fp1, ctx)
        self.assertNotEqual(fp0, fp1)
        # safety_status: the old fingerprint before the change, the new one after it.
        for m in statuses:
            if m.header.stamp < t_d:
                self.assertEqual(m.config_fingerprint, fp0)
            elif m.header.stamp > t_changed + rospy.Duration(0.2) and m.header.stamp <= t_end:
                self.assertEqual(m.config_fingerprint, fp1)
        # One line per transition, not per cycle.
        self.assertGreater(len(statuses), 50)
        self.assertLess(len(rows), 20, ctx)
        os.remove(path)


if __name__ == "__main__":
    rospy.init_node("test_audit_trail")
    rostest.rosrun("workspace_proximity", "test_audit_trail", AuditTrailTest)
