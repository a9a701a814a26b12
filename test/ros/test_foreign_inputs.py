#!/usr/bin/env python3
"""A foreign tracker type through the node (issue 24): the same scene as TrackedBoxArray.

The .test file names the family (~family: a name of test/foreign/foreign_scene.py) and starts three monitors with the same parameters (speed and
separation on, a 1 m cube "post" at the origin of base_link = world):
  /boxes/proximity_monitor     reads /scene/boxes     (workspace_proximity/TrackedBoxArray)
  /foreign/proximity_monitor   reads /scene/foreign   (the family's type)
  /refusing/proximity_monitor  reads /scene/foreign, /scene/wrong_md5, /scene/unknown_type
The publishers use the upstream definitions: Python classes that Debian's genpy generates
from foreign_msgs/ at test time (as the upstream package's build would), so each message
carries the upstream md5 and full definition. /scene/wrong_md5 carries the family's type name
with a definition that has one more field (extra_field) and so another md5;
/scene/unknown_type the family's layout under the type name my_tracker/<Type>.

The scene: one person (0.6 x 0.6 x 1.8 m; the foreign types give a point, the monitor's
person size) walks from x = 1.6 m towards the post at 0.25 m/s, published at 20 Hz (stamp =
now - 50 ms, position at the stamp). leg_tracker gives no velocity: the node differences two
sightings. Analytic oracle: the faces meet at t0 + 3.2 s; the separation at stamp s is
d(s) = 0.8 - 0.25 (s - t0), the approach speed 0.25 m/s, raw_scale ssm_scale(d, 0.25) once
d is within the speed and separation reach S_p(1 m/s) (0.57 m; beyond it: no pair, scale 1).

Checks, from 0.5 s after the start (the finite difference needs two sightings):
- in both /boxes and /foreign, every contacts array has the pair's event, and its contact
  instant (stamp + time_to_contact) is t0 + 3.2 s within 5 ms; both nodes publish about as
  many arrays (within 25 %);
- in both, every safety_status is OK, with separation d(stamp) and approach speed 0.25 within
  1 mm and 1 mm/s, and raw_scale ssm_scale(d, 0.25) within 1e-3 (more than 10 of them): the foreign node's numbers
  match the TrackedBoxArray node's within these tolerances;
- /refusing is DEGRADED with a status detail naming the type and "extra_field" and one naming
  my_tracker/<Type>, and its
  contacts still carry the person's event from /scene/foreign (the other input keeps working).
"""
import os
import sys
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "foreign"))

import rospy  # noqa: E402
import rostest  # noqa: E402

import make_fixtures  # noqa: E402  (genpy classes from foreign_msgs/)
from foreign_scene import FAMILIES  # noqa: E402  (one person in each type)
from wp_node_testlib import (ContactEventArray, ContactStatusRecorder, SafetyStatus, Track,  # noqa: E402
                             TrackedBoxArray, SSM_DEFAULTS, broadcast_static, ssm_required,
                             ssm_scale)

SPEED = 0.25
START_X = 1.6
HEIGHT = 0.9
GAP0 = START_X - 0.3 - 0.5                       # 0.8 m between the faces at t0
CONTACT_AFTER = GAP0 / SPEED                     # 3.2 s
# Speed and separation look no farther than S_p(robot_max_speed) with v_h = SPEED (ssm.md)
REACH = ssm_required(SPEED, SSM_DEFAULTS["robot_max_speed"])
SCENE_S = 3.0
SKIP_S = 0.5

def top_class(msg):
    return type(msg)


def wrong_md5_class(cls):
    """The type name with one more field: another layout, another md5."""
    class Wrong(cls):
        __slots__ = []
        _md5sum = "0123456789abcdef0123456789abcdef"
        _full_text = "float64 extra_field\n" + cls._full_text
    return Wrong


def unknown_type_class(cls):
    """The same layout under a type name nobody reads."""
    class Unknown(cls):
        __slots__ = []
        _type = "my_tracker/" + cls._type.split("/")[1]
    return Unknown


def as_class(msg, cls):
    """`msg`'s fields in an instance of `cls` (rospy publishes instances of its class only)."""
    out = cls()
    for name in msg.__slots__:
        setattr(out, name, getattr(msg, name))
    return out


Recorder = ContactStatusRecorder  # wp_node_testlib


class RefusalScene(object):
    """A foreign type's rostest scene (foreign_*.test): messages of `cls` on /scene/foreign
    (the foreign and refusing monitors read it), the same with another md5 on /scene/wrong_md5
    and under an unknown type name on /scene/unknown_type (the refusing monitor), the twin
    TrackedBoxArray on /scene/boxes; world = base_link on tf; a recorder per monitor."""

    def __init__(self, cls):
        self.cls = cls
        self.wrong_cls, self.unknown_cls = wrong_md5_class(cls), unknown_type_class(cls)
        self.foreign_pub = rospy.Publisher("/scene/foreign", cls, queue_size=10)
        self.wrong_pub = rospy.Publisher("/scene/wrong_md5", self.wrong_cls, queue_size=10)
        self.unknown_pub = rospy.Publisher("/scene/unknown_type", self.unknown_cls, queue_size=10)
        self.boxes_pub = rospy.Publisher("/scene/boxes", TrackedBoxArray, queue_size=10)
        self.recorders = {ns: Recorder("/" + ns) for ns in ("boxes", "foreign", "refusing")}
        self._static = broadcast_static([("world", "base_link", (0.0, 0.0, 0.0),
                                          (0.0, 0.0, 0.0))])

    def wait_ready(self, tc):
        """Waits (at most 20 s) for every monitor to subscribe and to pose the post (its tf
        listener has the static transform) before the scene starts; asserts both."""
        deadline = rospy.Time.now() + rospy.Duration(20.0)
        while rospy.Time.now() < deadline and not (
                self.foreign_pub.get_num_connections() >= 2 and
                self.wrong_pub.get_num_connections() >= 1 and
                self.unknown_pub.get_num_connections() >= 1 and
                self.boxes_pub.get_num_connections() >= 1 and
                all(r.posed() for r in self.recorders.values())):
            rospy.sleep(0.05)
        tc.assertTrue(all(r.posed() for r in self.recorders.values()), "the post is not posed")
        tc.assertGreaterEqual(self.foreign_pub.get_num_connections(), 2,
                              "monitors not subscribed")
        tc.assertGreaterEqual(self.boxes_pub.get_num_connections(), 1)
        tc.assertGreaterEqual(self.wrong_pub.get_num_connections(), 1,
                              "the refusing monitor did not connect to the wrong md5")

    def publish(self, boxes, message):
        """The twin's `boxes`, and `message()` (a new foreign message each call) on the three
        foreign topics."""
        self.boxes_pub.publish(boxes)
        self.foreign_pub.publish(message())
        self.wrong_pub.publish(as_class(message(), self.wrong_cls))
        self.unknown_pub.publish(as_class(message(), self.unknown_cls))

    def check_refusals(self, tc, c):
        """One contacts message `c` of the refusing monitor: DEGRADED, naming the type with
        another md5 (its extra_field) and the unknown type name."""
        tc.assertEqual(c.status, ContactEventArray.DEGRADED)
        named = [d for d in c.status_details if self.cls._type in d and "extra_field" in d]
        tc.assertTrue(named, "the refusal is not named: %s" % list(c.status_details))
        named = [d for d in c.status_details if self.unknown_cls._type in d]
        tc.assertTrue(named, "the unknown type is not named: %s" % list(c.status_details))


class ForeignInputs(unittest.TestCase):
    def test_same_scene(self):
        family = rospy.get_param("~family")
        package, versions, build = FAMILIES[family]
        root = make_fixtures.generate(versions)
        m = make_fixtures.load(root, package)
        sample = build(m, rospy.Time(1), (0, 0, 0), (0, 0, 0))
        cls = top_class(sample)
        rospy.loginfo("family %s: %s md5 %s", family, cls._type, cls._md5sum)
        scene = RefusalScene(cls)
        recorders = scene.recorders
        scene.wait_ready(self)

        person = Track("100", "person", (START_X, 0.0, HEIGHT), (0.6, 0.6, 1.8),
                       velocity=(-SPEED, 0.0, 0.0))
        t0 = rospy.Time.now()
        person.set_t0(t0)
        rate = rospy.Rate(20.0)
        while rospy.Time.now() < t0 + rospy.Duration(SCENE_S):
            stamp = rospy.Time.now() - rospy.Duration(0.05)
            pos, vel = person.state(stamp)
            boxes = TrackedBoxArray()
            boxes.header.stamp = stamp
            boxes.header.frame_id = "world"
            boxes.boxes.append(person.to_msg(stamp))
            scene.publish(boxes, lambda: build(m, stamp, pos, vel))
            rate.sleep()
        rospy.sleep(0.3)

        since = t0 + rospy.Duration(SKIP_S)
        contact_instant = (t0 + rospy.Duration(CONTACT_AFTER)).to_sec()
        counts = {}
        for ns in ("boxes", "foreign"):
            contacts, status = recorders[ns].since(since)
            contacts = [c for c in contacts if c.header.stamp <= t0 + rospy.Duration(SCENE_S)]
            status = [s for s in status if s.header.stamp <= t0 + rospy.Duration(SCENE_S)]
            self.assertGreater(len(contacts), 20, "%s: %d contact arrays" % (ns, len(contacts)))
            counts[ns] = len(contacts)
            for c in contacts:
                self.assertEqual(c.status, ContactEventArray.OK, "%s: %s" % (ns, c.status_details))
                self.assertEqual(len(c.events), 1, "%s: %d events" % (ns, len(c.events)))
                instant = c.header.stamp.to_sec() + c.events[0].time_to_contact
                self.assertAlmostEqual(instant, contact_instant, delta=5e-3,
                                       msg="%s: contact at %.4f, expected %.4f" % (
                                           ns, instant, contact_instant))
            self.assertGreater(len(status), 20, "%s: %d safety_status" % (ns, len(status)))
            within = 0
            for s in status:
                self.assertEqual(s.status, SafetyStatus.OK, "%s: %s" % (ns, s.reason))
                d = GAP0 - SPEED * (s.header.stamp - t0).to_sec()
                if s.separation == float("inf"):
                    # Not yet within reach: full speed.
                    self.assertGreater(d, REACH - 5e-3, ns)
                    self.assertEqual(s.raw_scale, 1.0, ns)
                    continue
                within += 1
                self.assertAlmostEqual(s.separation, d, delta=1e-3, msg=ns)
                self.assertAlmostEqual(s.approach_speed, SPEED, delta=1e-3, msg=ns)
                self.assertAlmostEqual(s.raw_scale, ssm_scale(d, SPEED), delta=1e-3, msg=ns)
            self.assertGreater(within, 10, "%s: %d statuses within reach" % (ns, within))
        self.assertLess(abs(counts["boxes"] - counts["foreign"]), 0.25 * counts["boxes"], counts)

        contacts, _ = recorders["refusing"].since(since)
        self.assertGreater(len(contacts), 20)
        for c in contacts:
            scene.check_refusals(self, c)
            self.assertEqual(len(c.events), 1, "the good input stopped working")


if __name__ == "__main__":
    rospy.init_node("test_foreign_inputs")
    rostest.rosrun("workspace_proximity", "test_foreign_inputs", ForeignInputs, sys.argv)
