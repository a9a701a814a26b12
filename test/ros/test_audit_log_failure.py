#!/usr/bin/env python3
"""A failed write to ~audit_log: unknown is never clear.

The node runs under a file size limit of 400 bytes (prlimit in the launch file): the header
and the start line fit, the first transition's line (DEGRADED at the first cycle, before tf and
the tracker are heard) does not. A person stands 5 m from the robot body "post", tf and the
tracker are fresh, so without the failure the status would turn OK. Checks: the node keeps
running; once the failure is reported every contacts array and every safety_status is DEGRADED
(2 s of cycles), a status_details line names the file and says the trail is incomplete,
/diagnostics counts the lost lines; the file holds the header and the start line, whole.
"""
import csv
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402

from wp_node_testlib import (ContactEventArray, DiagnosticsCollector, SafetyStatus,  # noqa: E402
                             ScenePublisher, SsmCollector, Track, broadcast_static,
                             connected_collector, degraded_about, diag_values)


class AuditLogFailureTest(unittest.TestCase):
    def test_a_lost_line_keeps_the_status_degraded(self):
        path = rospy.get_param("~log")
        self.tf = broadcast_static([("world", "base_link", (0, 0, 0), (0, 0, 0))])
        ssm = SsmCollector()
        diag = DiagnosticsCollector()
        col = connected_collector(self)
        scene = ScenePublisher("tracked_objects",
                               [Track("p1", "person", (5.0, 0.0, 0.9), (0.5, 0.5, 1.8))],
                               latency=0.05)
        scene.start()
        self.assertTrue(col.wait_until(
            lambda msgs: any(degraded_about(m, "the audit trail is incomplete") for m in msgs),
            10.0), "the failure was never reported")
        first = next(m for m in col.contact_msgs()
                     if degraded_about(m, "the audit trail is incomplete"))
        line = [d for d in first.status_details if "audit trail" in d][0]
        self.assertIn(path, line)
        rospy.sleep(2.0)
        scene.stop()
        arrays = col.contact_msgs(since=first.header.stamp)
        self.assertGreater(len(arrays), 30)
        for m in arrays:
            self.assertEqual(m.status, ContactEventArray.DEGRADED)
            self.assertIn(line, m.status_details)
        # Everything else is fresh: the audit log is the only reason at the end.
        self.assertEqual(arrays[-1].status_details, [line])
        statuses = ssm.statuses(since=first.header.stamp)
        self.assertGreater(len(statuses), 30)
        for m in statuses:
            self.assertEqual(m.status, SafetyStatus.DEGRADED)
        st = diag.wait_for(lambda s, v: "audit log lines lost" in v, 5.0)
        self.assertIsNotNone(st, "/diagnostics does not count the lost lines")
        self.assertGreaterEqual(int(diag_values(st)["audit log lines lost"]), 1)

        with open(path, newline="") as f:
            rows = list(csv.reader(f))
        self.assertEqual(rows[0], ["wall_time", "ros_stamp", "kind", "reason", "config_fingerprint"])
        self.assertEqual(rows[1][2], "start")
        self.assertEqual(len(rows[1]), 5)
        self.assertLessEqual(os.path.getsize(path), 400)
        os.remove(path)


if __name__ == "__main__":
    rospy.init_node("test_audit_log_failure")
    rostest.rosrun("workspace_proximity", "test_audit_log_failure", AuditLogFailureTest)
