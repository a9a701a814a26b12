#!/usr/bin/env python3
"""Detection types through the node (issue 24), beside their TrackedBoxArray twin:
vision_msgs/Detection3DArray (~family, one monitor) or several types each to its own monitor
(~families: jsk BoundingBoxArray v1 and v2, MarkerArray, PoseArray), published with the
upstream definition (genpy classes generated from foreign_msgs/ at test time; Debian's for the
two Debian types), one person walking from x = 1.6 m towards a 1 m cube "post" at 0.25 m/s at
20 Hz (stamp = now - 50 ms), results[0].id set to a class number that must never become a
track id. The twin monitor (namespace /boxes) reads /scene/boxes: the same person as a
TrackedBoxArray box of label `unknown` (0.6 x 0.6 x 1.8 m) with its true velocity. All monitors
load fixtures/obstacle_params.yaml (label `unknown`'s growth bounds above the tracker's own).

Checks, from 1.5 s after the start (the track confirmed at its second hit, its velocity known
after about 0.4 s, converged by 1.5 s), in the twin and in every family's monitor
(twin_check.check_monitor): every contacts array OK with one event with the post (the foreign
ones naming a tracker id "t<n>"), at the growth bound's analytic instant of one of the
published stamps within 5 ms; every safety_status OK with separation 0.8 - 0.25 t within 2 mm,
approach speed 0.25 within 1 mm/s in the twin and 0.25 + 0.447 (the tracker's steady 3 sigma
velocity error at 20 Hz) within 0.1 m/s through the tracker, raw_scale = ssm_scale within 2e-3;
about as many arrays as the twin (within 25 %). Compared by stamps, never by arrival.
"""
import os
import sys
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "foreign"))

import rospy  # noqa: E402
import rostest  # noqa: E402

import make_fixtures  # noqa: E402
from foreign_scene import DETECTION_FAMILIES, load_module  # noqa: E402
import twin_check  # noqa: E402
from test_foreign_inputs import Recorder  # noqa: E402
from wp_node_testlib import Track, TrackedBoxArray, broadcast_static  # noqa: E402

SPEED, START_X, HEIGHT = 0.25, 1.6, 0.9
GAP0 = START_X - 0.3 - 0.5        # 0.8 m between the person's and the post's faces at t0
SCENE_S, SKIP_S = 3.0, 1.5


class DetectionInput(unittest.TestCase):
    def test_detections_through_the_tracker(self):
        # One family on /scene/detections to the monitor in this namespace (~family), or each
        # of ~families on /scene/<family> to the monitor in namespace /<family>.
        families = rospy.get_param("~families", None)
        if families is None:
            routes = [(rospy.get_param("~family", "detections3d"), "/scene/detections",
                       rospy.get_namespace().rstrip("/"))]
        else:
            routes = [(f, "/scene/" + f, "/" + f) for f in families]
        scenes = []
        for family, topic, ns in routes:
            package, versions, build = DETECTION_FAMILIES[family]
            m = load_module(make_fixtures, make_fixtures.generate(versions), package)
            cls = type(build(m, rospy.Time(1), (0, 0, 0), (0, 0, 0)))
            scenes.append((family, m, build, rospy.Publisher(topic, cls, queue_size=10),
                           Recorder(ns)))
        boxes_pub = rospy.Publisher("/scene/boxes", TrackedBoxArray, queue_size=10)
        twin = Recorder("/boxes")
        _static = broadcast_static([("world", "base_link", (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))])

        def ready(pub, r):
            return pub.get_num_connections() >= 1 and r.posed()
        pairs = [(s[0], s[3], s[4]) for s in scenes] + [("boxes", boxes_pub, twin)]
        deadline = rospy.Time.now() + rospy.Duration(20.0)
        while rospy.Time.now() < deadline and not all(ready(p, r) for _, p, r in pairs):
            rospy.sleep(0.05)
        for name, pub, r in pairs:
            self.assertTrue(ready(pub, r), "%s: not subscribed or the post not posed" % name)
        person = Track("person", "unknown", (START_X, 0.0, HEIGHT), (0.6, 0.6, 1.8),
                       velocity=(-SPEED, 0.0, 0.0))
        t0 = rospy.Time.now()
        person.set_t0(t0)
        stamps = []
        rate = rospy.Rate(20.0)
        while rospy.Time.now() < t0 + rospy.Duration(SCENE_S):
            stamp = rospy.Time.now() - rospy.Duration(0.05)
            stamps.append(stamp.to_sec())
            t = (stamp - t0).to_sec()
            boxes = TrackedBoxArray()
            boxes.header.stamp, boxes.header.frame_id = stamp, "world"
            boxes.boxes.append(person.to_msg(stamp))
            boxes_pub.publish(boxes)
            for family, m, build, pub, _ in scenes:
                pub.publish(build(m, stamp, (START_X - SPEED * t, 0.0, HEIGHT), (-SPEED, 0.0, 0.0)))
            rate.sleep()
        rospy.sleep(0.3)
        since, until = t0 + rospy.Duration(SKIP_S), t0 + rospy.Duration(SCENE_S)
        t0s = t0.to_sec()
        counts = {}
        for name, _, r in pairs:
            contacts, status = r.since(since)
            contacts = [c for c in contacts if c.header.stamp <= until]
            status = [s for s in status if s.header.stamp <= until]
            counts[name] = twin_check.check_monitor(
                self, name, contacts, status, stamps, t0s,
                {"unknown": (lambda t: GAP0 - SPEED * t, SPEED)},
                lambda t: GAP0 - SPEED * t, SPEED, tracked=(name != "boxes"))
        twin_check.check_counts(self, counts)

if __name__ == "__main__":
    rospy.init_node("test_foreign_detection_input")
    rostest.rosrun("workspace_proximity", "test_foreign_detection_input", DetectionInput, sys.argv)
