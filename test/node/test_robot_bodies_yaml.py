#!/usr/bin/env python3
"""Robot bodies from a ~robot_bodies YAML list under static tf.

tf (static, from this test): world -> base_link at z = 0.5; base_link -> tool0 at z = 1.0,
yawed 90 degrees. Bodies: "base" (1 m cube on base_link) and "gripper" (0.4 x 0.2 x 0.2 m on
tool0, offset 0.1 m along tool0's x). In world the gripper spans x [-0.1, 0.1],
y [-0.1, 0.3], z [1.4, 1.6]: both the offset and the frame's yaw matter.
Two 0.2 m cubes approach the gripper: "obj_x" along +x (gap 1.0 m at 1 m/s) and "obj_y"
along -y (gap 1.5 m at 1 m/s). Expected: events (gripper, obj_x) and (gripper, obj_y) with
label "robot" on the gripper side and analytic numbers; nothing for "base".
"""
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402

from wp_node_testlib import (Collector, ScenePublisher, StaticBody, Track,  # noqa: E402
                             broadcast_static, check_array_basics, check_scene_events,
                             events_for)

HORIZON = 5.0


class RobotBodiesYamlTest(unittest.TestCase):
    def test_robot_bodies_from_yaml(self):
        tf_pub = broadcast_static([
            ("world", "base_link", (0.0, 0.0, 0.5), (0.0, 0.0, 0.0)),
            ("base_link", "tool0", (0.0, 0.0, 1.0), (0.0, 0.0, 1.5707963267948966)),
        ])
        col = Collector()
        self.assertTrue(col.wait_for_node(), "proximity_monitor published no contacts")
        gripper = StaticBody("gripper", "robot", (0.0, 0.1, 1.5), (0.1, 0.2, 0.1))
        base = StaticBody("base", "robot", (0.0, 0.0, 0.5), (0.5, 0.5, 0.5))
        obj_x = Track("obj_x", "default", (-1.2, 0.1, 1.5), (0.2, 0.2, 0.2), (1.0, 0.0, 0.0))
        obj_y = Track("obj_y", "default", (0.0, 1.9, 1.5), (0.2, 0.2, 0.2), (0.0, -1.0, 0.0))
        scene = ScenePublisher("tracked_objects", [obj_x, obj_y], latency=0.05)
        t0 = scene.start()
        rospy.sleep(1.5)
        scene.stop()
        msgs = col.contact_msgs(since=t0 + rospy.Duration(0.5))
        self.assertGreater(len(msgs), 15)
        checked = 0
        for m in msgs:
            check_array_basics(self, m)
            if (m.header.stamp - t0).to_sec() > 1.4:
                break
            checked += check_scene_events(self, m, [gripper, base, obj_x, obj_y], HORIZON)
            for ev in events_for(m, "gripper", "obj_x") + events_for(m, "gripper", "obj_y"):
                self.assertEqual(ev.label_a, "robot")
        self.assertGreaterEqual(checked, 30, "too few events checked")
        del tf_pub


if __name__ == "__main__":
    rospy.init_node("test_robot_bodies_yaml")
    rostest.rosrun("workspace_proximity", "test_robot_bodies_yaml", RobotBodiesYamlTest)
