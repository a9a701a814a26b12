#!/usr/bin/env python3
"""Robot bodies from a ~robot_bodies YAML list under static tf.

tf (static, from this test): world -> base_link at z = 0.5; base_link -> tool0 at z = 1.0,
yawed 90 degrees. Bodies: "base" (1 m cube on base_link) and "gripper" (0.4 x 0.2 x 0.2 m on
tool0, offset 0.1 m along tool0's x). In world the gripper spans x [-0.1, 0.1],
y [-0.1, 0.3], z [1.4, 1.6]: both the offset and the frame's yaw matter. "flange" (0.1 m
cube on tool0, no offset) overlaps the gripper: a robot-robot pair, skipped by default.
Two 0.2 m cubes approach: "obj_x" (label default) along +x (gaps 1.0 m to the gripper and
1.05 m to the flange, 1 m/s) and "obj_y" (label person) along -y (gaps 1.5 m to the gripper
and 1.75 m to the flange, 1 m/s). Expected: exactly the object-robot pairs that touch, label
"robot" on the robot side, analytic numbers, and levels from the stricter of the two labels'
thresholds (robot bodies use robot_thresholds); nothing for "base", nothing robot-robot.
"""
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402

from wp_node_testlib import (StaticBody, Track, broadcast_robot_frames, checked_arrays,  # noqa: E402
                             check_scene_events, connected_collector, fmt_event, node_labels,
                             run_scene)

HORIZON = 5.0


class RobotBodiesYamlTest(unittest.TestCase):
    def test_robot_bodies_from_yaml(self):
        tf_pub = broadcast_robot_frames((0.0, 0.0, 0.5), [
            ("tool0", (0.0, 0.0, 1.0), (0.0, 0.0, 1.5707963267948966)),
        ])
        col = connected_collector(self)
        gripper = StaticBody("gripper", "robot", (0.0, 0.1, 1.5), (0.1, 0.2, 0.1))
        base = StaticBody("base", "robot", (0.0, 0.0, 0.5), (0.5, 0.5, 0.5))
        flange = StaticBody("flange", "robot", (0.0, 0.0, 1.5), (0.05, 0.05, 0.05))
        obj_x = Track("obj_x", "default", (-1.2, 0.1, 1.5), (0.2, 0.2, 0.2), (1.0, 0.0, 0.0))
        obj_y = Track("obj_y", "person", (0.0, 1.9, 1.5), (0.2, 0.2, 0.2), (0.0, -1.0, 0.0))
        labels = node_labels()
        t0, msgs = run_scene(col, [obj_x, obj_y], 1.5, 0.5)
        self.assertGreater(len(msgs), 15)
        checked = 0
        seen = set()
        for m in checked_arrays(self, msgs, t0, 1.4):
            checked += check_scene_events(self, m, [gripper, base, flange, obj_x, obj_y],
                                          HORIZON, thresholds=labels)
            for ev in m.events:
                self.assertEqual(ev.label_a, "robot", fmt_event(ev))
                seen.add((ev.id_a, ev.id_b))
        self.assertGreaterEqual(checked, 30, "too few events checked")
        self.assertEqual(seen, {("gripper", "obj_x"), ("gripper", "obj_y"), ("flange", "obj_x"),
                                ("flange", "obj_y")})
        del tf_pub


if __name__ == "__main__":
    rospy.init_node("test_robot_bodies_yaml")
    rostest.rosrun("workspace_proximity", "test_robot_bodies_yaml", RobotBodiesYamlTest)
