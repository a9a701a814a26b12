#!/usr/bin/env python3
"""No robot link is dropped silently (fixtures/broken_meshes.urdf): base_link (a box) and
dae_link (a COLLADA mesh, bounded by its box) are bodies; missing_mesh_link's STL does not
exist, so the link cannot be modelled.
1. For 3 s of fresh data every contacts array is DEGRADED with a line naming
   missing_mesh_link, "cannot be modelled" and the missing file; a probe approaching dae_link
   and base_link gets events with both (they are modelled); /diagnostics says WARN naming it.
2. The same URDF with ~require_all_links: true: the node exits by itself with a non-zero
   status, naming the element.
"""
import os
import subprocess
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402

from wp_node_testlib import (END, DiagnosticsCollector, ScenePublisher, Track,  # noqa: E402
                             broadcast_robot_frames, check_array_basics, connected_collector,
                             degraded_about, find_node_binary)

WARN = 1


class RobotUnmodelledTest(unittest.TestCase):
    def test_a_missing_mesh_keeps_the_status_degraded(self):
        tf_pub = broadcast_robot_frames((0.0, 0.0, 0.0), [
            ("missing_mesh_link", (2.0, 0.0, 1.0), (0.0, 0.0, 0.0)),
            ("dae_link", (-2.0, 0.0, 1.0), (0.0, 0.0, 0.0)),
        ])
        diags = DiagnosticsCollector()
        col = connected_collector(self)
        # A 0.4 m cube from x = -5 at 1 m/s along +x at the height of dae_link (z = 1.25) and
        # one towards base_link: both links are in its way within the 10 s horizon.
        scene = ScenePublisher("tracked_objects", [
            Track("probe", "default", (-5.0, 0.0, 1.25), (0.4, 0.4, 0.4), (1.0, 0.0, 0.0)),
            Track("probe_base", "default", (0.0, 4.0, 0.25), (0.4, 0.4, 0.4), (0.0, -1.0, 0.0))],
            latency=0.05)
        start = scene.start()
        rospy.sleep(1.0)
        checked_from = rospy.Time.now()
        rospy.sleep(3.0)
        scene.stop()
        msgs = col.contact_msgs(since=checked_from)
        self.assertGreaterEqual(len(msgs), 50)  # 3 s at 20 Hz
        pairs = set()
        for m in msgs:
            check_array_basics(self, m)
            self.assertTrue(degraded_about(m, "missing_mesh_link"),
                            "status %d %r: a link that cannot be modelled must keep DEGRADED" % (
                                m.status, list(m.status_details)))
            line = [d for d in m.status_details if "missing_mesh_link" in d][0]
            self.assertIn("cannot be modelled", line)
            self.assertIn("missing_mesh.stl", line)
            for ev in m.events:
                if ev.state != END:
                    pairs.add((ev.id_a, ev.id_b))
        self.assertIn(("dae_link", "probe"), pairs, "the DAE link is not a body: %r" % pairs)
        self.assertIn(("base_link", "probe_base"), pairs, "base_link is not a body: %r" % pairs)
        st = diags.wait_for(lambda s, v: s.level == WARN and "missing_mesh_link" in s.message, 5.0)
        self.assertIsNotNone(st, "no diagnostics WARN naming the link: %r" % diags.latest())
        del tf_pub, start

    def test_require_all_links_refuses_to_start(self):
        binary = find_node_binary()
        self.assertTrue(binary)
        rospy.set_param("/strict_description", rospy.get_param("/robot_description"))
        proc = subprocess.Popen(
            [binary, "__name:=strict_monitor", "_require_all_links:=true",
             "_robot_description_param:=/strict_description"],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        try:
            out, err = proc.communicate(timeout=15)
        except subprocess.TimeoutExpired:
            proc.kill()
            out, err = proc.communicate()
            self.fail("the node kept running with ~require_all_links and an unmodelled link")
        text = out.decode(errors="replace") + err.decode(errors="replace")
        self.assertGreater(proc.returncode, 0, text[-2000:])
        self.assertIn("missing_mesh_link", text)
        self.assertIn("require_all_links", text)


if __name__ == "__main__":
    rospy.init_node("test_robot_unmodelled")
    rostest.rosrun("workspace_proximity", "test_robot_unmodelled", RobotUnmodelledTest)
