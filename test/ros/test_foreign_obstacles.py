#!/usr/bin/env python3
"""obstacle_detector/Obstacles through the node (issue 24), beside its TrackedBoxArray twin.

foreign_obstacles.test starts three monitors with the same parameters (common_params.yaml,
foreign_params.yaml: a 1 m cube "post" at the origin of base_link = world, speed and
separation on; obstacle_params.yaml: the labels `unknown` and `segment` with growth bounds
above the multi-object tracker's own errors):
  /boxes/proximity_monitor     reads /scene/boxes    (TrackedBoxArray: the twin)
  /foreign/proximity_monitor   reads /scene/foreign  (obstacle_detector/Obstacles)
  /refusing/proximity_monitor  reads /scene/foreign, /scene/wrong_md5, /scene/unknown_type
The Obstacles publisher uses the upstream definition (genpy classes generated from
foreign_msgs/ at test time: the upstream md5 and full text).

The scene, at 20 Hz (stamp = now - 50 ms): a circle (true_radius 0.3, radius 0.55; its
velocity field says (9, 9): never read) walks from x = 1.6 m towards the post at 0.25 m/s, and
a static wall segment from (-1, -1.5) to (1, -1.5). The twin: a 0.6 x 0.6 x 1.8 m box of label
`unknown` at the circle's place with its true velocity, and a 2.0 x 0.1 x 2.0 m box of label
`segment` on the wall (the label's thickness and height), both standing on z = 0.

Analytic oracle (docs/node.md, "Tracked objects within bounds"): a box measured at t_m grows
by R(s) = 0.15 + min(0.8 s + 2 s^2, (2 + |v|) s) s after t_m, so its contact with the post
comes at f(t_m) = t_m + s* with gap(t_m) - |v| s* = R(s*): the circle's gap is
0.8 - 0.25 (t_m - t0), the wall's 0.95 (v = 0). A cycle at P that used the message stamped
t_m reports the instant max(f(t_m), P).

Checks, from 1.5 s after the start (the tracker's track confirmed at its second detection,
its velocity known and its errors below the labels' after about 0.4 s, its estimate converged
on the noise-free motion by 1.5 s):
- in both /boxes and /foreign, every contacts array is OK and has the post's two events (the
  circle's, of label unknown, and the wall's, of label segment), each at the analytic instant
  of one of the published stamps up to P within 5 ms; the foreign events name tracker ids
  (t<n>); both nodes publish about as many arrays (within 25 %);
- in both, every safety_status is OK with the circle as the limiting pair: separation
  d(P) = 0.8 - 0.25 (P - t0) within 2 mm; approach speed 0.25 in the twin (1 mm/s) and
  0.25 + 0.447 in the foreign node (the tracker's own 3 sigma velocity error, its steady state
  at 20 Hz: speed and separation add it; within 0.1 m/s for the publishing jitter); raw_scale
  = ssm_scale(d, approach) within 2e-3;
- /refusing is DEGRADED naming the type and "extra_field", and my_tracker/Obstacles, and still
  has the post's two events from /scene/foreign.
"""
import os
import sys
import threading
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "foreign"))

import rospy  # noqa: E402
import rostest  # noqa: E402
import geometry_msgs.msg as g  # noqa: E402

import make_fixtures  # noqa: E402  (genpy classes from foreign_msgs/)
import twin_check  # noqa: E402
from test_foreign_inputs import RefusalScene  # noqa: E402
from wp_node_testlib import Track, TrackedBoxArray  # noqa: E402

SPEED, START_X = 0.25, 1.6
GAP0 = START_X - 0.3 - 0.5        # 0.8 m between the circle's and the post's faces at t0
WALL_GAP = 1.5 - 0.05 - 0.5       # 0.95 m between the wall's and the post's faces
SCENE_S, SKIP_S = 3.0, 1.5


class ForeignObstacles(unittest.TestCase):
    def obstacles(self, m, stamp, x):
        msg = m.Obstacles()
        msg.header.stamp, msg.header.frame_id = stamp, "world"
        msg.segments.append(m.SegmentObstacle(first_point=g.Point(-1.0, -1.5, 0.0),
                                              last_point=g.Point(1.0, -1.5, 0.0)))
        msg.circles.append(m.CircleObstacle(center=g.Point(x, 0.0, 0.0),
                                            velocity=g.Vector3(9.0, 9.0, 0.0),
                                            radius=0.55, true_radius=0.3))
        return msg

    def test_obstacles_beside_their_twin(self):
        root = make_fixtures.generate({})
        m = make_fixtures.load(root, "obstacle_detector")
        scene = RefusalScene(m.Obstacles)
        recorders = scene.recorders
        scene.wait_ready(self)

        circle = Track("circle", "unknown", (START_X, 0.0, 0.9), (0.6, 0.6, 1.8),
                       velocity=(-SPEED, 0.0, 0.0))
        wall = Track("wall", "segment", (0.0, -1.5, 1.0), (2.0, 0.1, 2.0))
        t0 = rospy.Time.now()
        circle.set_t0(t0)
        wall.set_t0(t0)
        stamps = []
        rate = rospy.Rate(20.0)
        while rospy.Time.now() < t0 + rospy.Duration(SCENE_S):
            stamp = rospy.Time.now() - rospy.Duration(0.05)
            stamps.append(stamp.to_sec())
            boxes = TrackedBoxArray()
            boxes.header.stamp, boxes.header.frame_id = stamp, "world"
            boxes.boxes.append(circle.to_msg(stamp))
            boxes.boxes.append(wall.to_msg(stamp))
            x = START_X - SPEED * (stamp - t0).to_sec()
            scene.publish(boxes, lambda: self.obstacles(m, stamp, x))
            rate.sleep()
        rospy.sleep(0.3)

        since, until = t0 + rospy.Duration(SKIP_S), t0 + rospy.Duration(SCENE_S)
        t0s = t0.to_sec()
        counts = {}
        for ns in ("boxes", "foreign"):
            contacts, status = recorders[ns].since(since)
            contacts = [c for c in contacts if c.header.stamp <= until]
            status = [s for s in status if s.header.stamp <= until]
            counts[ns] = twin_check.check_monitor(
                self, ns, contacts, status, stamps, t0s,
                {"unknown": (lambda t: GAP0 - SPEED * t, SPEED),
                 "segment": (lambda t: WALL_GAP, 0.0)},
                lambda t: GAP0 - SPEED * t, SPEED, tracked=(ns == "foreign"))
        twin_check.check_counts(self, counts)

        contacts, _ = recorders["refusing"].since(since)
        self.assertGreater(len(contacts), 15)
        for c in contacts:
            scene.check_refusals(self, c)
            self.assertEqual(len([e for e in c.events if "post" in (e.id_a, e.id_b)]), 2,
                             "the good input stopped working")


if __name__ == "__main__":
    rospy.init_node("test_foreign_obstacles")
    rostest.rosrun("workspace_proximity", "test_foreign_obstacles", ForeignObstacles, sys.argv)
