#!/usr/bin/env python3
"""Robot bodies from the URDF on robot_description (fixtures/test_robot.urdf) under static tf.

Links (tf published here, static): base_link at the origin (box 0.6 x 0.6 x 0.5 m raised
0.25 m by its collision origin), tool at z = 2 (0.2 x 0.1 x 0.1 m box offset 0.1 m along x),
ball at (3, 0, 1) (sphere r = 0.25 m), post at (-3, 0, 0.5) (cylinder r = 0.1 m, length 1 m
along z), beam at (0, 3, 1) yawed 90 degrees (box 1.0 x 0.2 x 0.4 m, collision origin 0.2 m
along the link's x and rolled 90 degrees: in world x [-0.2, 0.2], y [2.7, 3.7], z [0.9, 1.1])
and camera_link at z = 3 (visual only: no body). A 0.2 m cube approaches each one face-on at
1 m/s with gaps 1.0, 1.0, 1.5, 2.1, 1.2 and 1.2 m. Face-on, with the approaching face
centred on the sphere / cylinder, every number equals that of the shapes' bounding boxes, so
the exact axis-aligned prediction applies. Bodies are named after their links, label "robot".
"""
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402

from wp_node_testlib import (StaticBody, Track, broadcast_robot_frames, check_array_basics,  # noqa: E402
                             check_scene_events, connected_collector, fmt_event, run_scene)

HORIZON = 5.0


class RobotUrdfTest(unittest.TestCase):
    def test_robot_bodies_from_urdf(self):
        tf_pub = broadcast_robot_frames((0.0, 0.0, 0.0), [
            ("tool", (0.0, 0.0, 2.0), (0.0, 0.0, 0.0)),
            ("ball", (3.0, 0.0, 1.0), (0.0, 0.0, 0.0)),
            ("post", (-3.0, 0.0, 0.5), (0.0, 0.0, 0.0)),
            ("beam", (0.0, 3.0, 1.0), (0.0, 0.0, 1.5707963267948966)),
            ("camera_link", (0.0, 0.0, 3.0), (0.0, 0.0, 0.0)),
        ])
        col = connected_collector(self)
        robot = [
            StaticBody("base_link", "robot", (0.0, 0.0, 0.25), (0.3, 0.3, 0.25)),
            StaticBody("tool", "robot", (0.1, 0.0, 2.0), (0.1, 0.05, 0.05)),
            StaticBody("ball", "robot", (3.0, 0.0, 1.0), (0.25, 0.25, 0.25)),
            StaticBody("post", "robot", (-3.0, 0.0, 0.5), (0.1, 0.1, 0.5)),
            StaticBody("beam", "robot", (0.0, 3.2, 1.0), (0.2, 0.5, 0.1)),
        ]
        cube = (0.2, 0.2, 0.2)
        objects = [
            Track("o_base", "default", (-1.4, 0.0, 0.25), cube, (1.0, 0.0, 0.0)),
            Track("o_tool", "default", (1.3, 0.0, 2.0), cube, (-1.0, 0.0, 0.0)),
            Track("o_ball", "default", (3.0, 1.85, 1.0), cube, (0.0, -1.0, 0.0)),
            Track("o_post", "default", (-3.0, -2.3, 0.5), cube, (0.0, 1.0, 0.0)),
            Track("o_cam", "default", (0.0, 1.2, 3.0), cube, (0.0, -1.0, 0.0)),
            Track("o_beam", "default", (1.5, 3.2, 1.0), cube, (-1.0, 0.0, 0.0)),
        ]
        t0, msgs = run_scene(col, objects, 1.3, 0.5)
        self.assertGreater(len(msgs), 10)
        checked = 0
        seen = set()
        for m in msgs:
            check_array_basics(self, m)
            for ev in m.events:
                self.assertNotIn("camera_link", (ev.id_a, ev.id_b),
                                 "a link without collision became a body: " + fmt_event(ev))
            if (m.header.stamp - t0).to_sec() > 1.2:
                break
            checked += check_scene_events(self, m, robot + objects, HORIZON)
            seen.update((e.id_a, e.id_b) for e in m.events)
        self.assertGreaterEqual(checked, 30, "too few events checked")
        self.assertEqual(seen, {("base_link", "o_base"), ("o_tool", "tool"),
                                ("ball", "o_ball"), ("o_post", "post"), ("beam", "o_beam")})
        del tf_pub


if __name__ == "__main__":
    rospy.init_node("test_robot_urdf")
    rostest.rosrun("workspace_proximity", "test_robot_urdf", RobotUrdfTest)
