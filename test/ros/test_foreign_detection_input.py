#!/usr/bin/env python3
"""Detection types through the node (issue 24): vision_msgs/Detection3DArray (~family, one
monitor) or several types each to its own monitor (~families: jsk BoundingBoxArray v1 and v2,
MarkerArray, PoseArray), published with the upstream definition (genpy classes generated from
foreign_msgs/ at test time; Debian's for the two Debian types), one person
walking from x = 1.6 m towards a 1 m cube "post" at 0.25 m/s at 20 Hz (stamp = now - 50 ms),
results[0].id set to a class number that must never become a track id.

Checks, from 1 s after the start (the tracker confirms a track at its second hit; its velocity
is unknown until the filter knows it): every contacts array is OK with one event, between the
post and a track named by the multi-object tracker ("t<n>"), whose contact instant (stamp +
time_to_contact) is never later than the analytic one (the faces meet 3.2 s after the start;
the track's growth may bring it earlier, never later), within 5 ms.
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

import make_fixtures  # noqa: E402
from foreign_scene import DETECTION_FAMILIES, load_module  # noqa: E402
from wp_node_testlib import ContactEventArray, broadcast_static  # noqa: E402

SPEED, START_X, HEIGHT = 0.25, 1.6, 0.9
CONTACT_AFTER = (START_X - 0.3 - 0.5) / SPEED


class DetectionInput(unittest.TestCase):
    def test_detections_through_the_tracker(self):
        # One family on /scene/detections to the monitor in this namespace (~family), or each
        # of ~families on /scene/<family> to the monitor in namespace /<family>.
        families = rospy.get_param("~families", None)
        if families is None:
            routes = [(rospy.get_param("~family", "detections3d"), "/scene/detections",
                       "contacts")]
        else:
            routes = [(f, "/scene/" + f, "/" + f + "/contacts") for f in families]
        lock = threading.Lock()
        scenes = []
        for family, topic, contacts_topic in routes:
            package, versions, build = DETECTION_FAMILIES[family]
            m = load_module(make_fixtures, make_fixtures.generate(versions), package)
            cls = type(build(m, rospy.Time(1), (0, 0, 0), (0, 0, 0)))
            contacts = []

            def on_contacts(msg, into=contacts):
                with lock:
                    into.append(msg)
            scenes.append((family, m, build, rospy.Publisher(topic, cls, queue_size=10),
                           contacts, rospy.Subscriber(contacts_topic, ContactEventArray,
                                                      on_contacts, queue_size=200)))
        _static = broadcast_static([("world", "base_link", (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))])

        def ready(scene):
            with lock:
                return (scene[3].get_num_connections() >= 1 and bool(scene[4]) and
                        not any("robot body" in d for d in scene[4][-1].status_details))
        deadline = rospy.Time.now() + rospy.Duration(20.0)
        while rospy.Time.now() < deadline and not all(ready(s) for s in scenes):
            rospy.sleep(0.05)
        for scene in scenes:
            self.assertTrue(ready(scene), "%s: not subscribed or the post not posed" % scene[0])
        t0 = rospy.Time.now()
        rate = rospy.Rate(20.0)
        while rospy.Time.now() < t0 + rospy.Duration(3.0):
            stamp = rospy.Time.now() - rospy.Duration(0.05)
            t = (stamp - t0).to_sec()
            for family, m, build, pub, _, _ in scenes:
                pub.publish(build(m, stamp, (START_X - SPEED * t, 0.0, HEIGHT), (-SPEED, 0.0, 0.0)))
            rate.sleep()
        rospy.sleep(0.2)
        contact = (t0 + rospy.Duration(CONTACT_AFTER)).to_sec()
        for family, _, _, _, contacts, _ in scenes:
            with lock:
                steady = [c for c in contacts
                          if t0 + rospy.Duration(1.0) <= c.header.stamp <= t0 + rospy.Duration(3.0)]
            self.assertGreater(len(steady), 20, family)
            for c in steady:
                self.assertEqual(c.status, ContactEventArray.OK, "%s: %s" % (family,
                                                                          list(c.status_details)))
                self.assertEqual(len(c.events), 1, family)
                ev = c.events[0]
                ids = {ev.id_a, ev.id_b}
                self.assertIn("post", ids, family)
                other = (ids - {"post"}).pop().split("/")[-1]  # qualified by the topic
                self.assertTrue(other.startswith("t") and other[1:].isdigit(), (family, other))
                self.assertLessEqual(c.header.stamp.to_sec() + ev.time_to_contact,
                                     contact + 5e-3, family)


if __name__ == "__main__":
    rospy.init_node("test_foreign_detection_input")
    rostest.rosrun("workspace_proximity", "test_foreign_detection_input", DetectionInput, sys.argv)
