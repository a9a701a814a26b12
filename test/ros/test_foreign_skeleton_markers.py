#!/usr/bin/env python3
"""Azure Kinect body tracking through the node (issue 24 item 4): the same capsules as boxes.

Two monitors with the same parameters (test/ros/fixtures: common, foreign and skeleton_params:
a 1 m cube "post" at the origin, speed and separation on, the body parts' diameters):
  /boxes/proximity_monitor  reads /scene/boxes  (TrackedBoxArray: the capsules' boxes, computed
                            here from the capsule's definition, with the body's velocity)
  /k4abt/proximity_monitor  reads /scene/k4abt  (visualization_msgs/MarkerArray as the Azure
                            Kinect ROS driver writes it: one SPHERE per joint, id body*100 +
                            joint, K4ABT order, 0.05 m; the topic in ~skeleton_marker_topics)

The scene: one body (id 1) of K4ABT's 32 joints, standing, left arm reaching towards the post,
walks from x = 1.6 m towards it at 0.25 m/s, published at 20 Hz (stamp = now - 50 ms). Its 31
bones (K4ABT's joint tree, written here from the SDK's joint hierarchy) are capsules of their
part's radius; a capsule's box is centred between its joints, its z axis along the bone, full
extents (d, d, length + d).

First 1 s of empty MarkerArrays (the driver's message while it sees nobody): the k4abt node is
OK with no events (an empty array says "no bodies"). Then the body.

Checks, from 0.5 s after the start (the joints' differences need two sightings):
- the same bones have events with the post in both monitors (at least 10; the bones of one
  body touch each other too: those events are not compared) (ids "<body>/<parent joint>-><joint>"), and for
  each, every contact instant (stamp + time_to_contact) of /k4abt is within 5 ms of the
  median instant of /boxes;
- every safety_status is OK, each raw_scale is ssm_scale(separation, approach_speed) within
  1e-3, and cycle by cycle the k4abt node's limiting bone, its separation within 1 mm and its
  approach speed within 1 mm/s are the boxes node's (interpolated to the same stamp).
"""
import math
import os
import re
import sys
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import rospy  # noqa: E402
import rostest  # noqa: E402
from geometry_msgs.msg import Pose, Twist, Vector3  # noqa: E402
from visualization_msgs.msg import Marker, MarkerArray  # noqa: E402

from wp_node_testlib import (ContactEventArray, ContactStatusRecorder, SafetyStatus, TrackedBox,  # noqa: E402
                             TrackedBoxArray, broadcast_static, ssm_scale)

SPEED = 0.25
START = (1.6, 0.0, 1.0)  # the pelvis at t0
SCENE_S = 3.0
SKIP_S = 0.5
BODY = 1

# K4ABT joints (k4abt_joint_id_t order; names as the driver's tf frames) and their parents.
JOINTS = ["Pelvis", "Spine_Naval", "Spine_Chest", "Neck", "Clavicle_left", "Shoulder_left",
          "Elbow_left", "Wrist_left", "Hand_left", "Handtip_left", "Thumb_left",
          "Clavicle_right", "Shoulder_right", "Elbow_right", "Wrist_right", "Hand_right",
          "Handtip_right", "Thumb_right", "Hip_left", "Knee_left", "Ankle_left", "Foot_left",
          "Hip_right", "Knee_right", "Ankle_right", "Foot_right", "Head", "Nose", "Eye_left",
          "Ear_left", "Eye_right", "Ear_right"]
PARENT = {"Spine_Naval": "Pelvis", "Spine_Chest": "Spine_Naval", "Neck": "Spine_Chest",
          "Clavicle_left": "Spine_Chest", "Shoulder_left": "Clavicle_left",
          "Elbow_left": "Shoulder_left", "Wrist_left": "Elbow_left", "Hand_left": "Wrist_left",
          "Handtip_left": "Hand_left", "Thumb_left": "Wrist_left",
          "Clavicle_right": "Spine_Chest", "Shoulder_right": "Clavicle_right",
          "Elbow_right": "Shoulder_right", "Wrist_right": "Elbow_right",
          "Hand_right": "Wrist_right", "Handtip_right": "Hand_right", "Thumb_right": "Wrist_right",
          "Hip_left": "Pelvis", "Knee_left": "Hip_left", "Ankle_left": "Knee_left",
          "Foot_left": "Ankle_left", "Hip_right": "Pelvis", "Knee_right": "Hip_right",
          "Ankle_right": "Knee_right", "Foot_right": "Ankle_right", "Head": "Neck",
          "Nose": "Head", "Eye_left": "Head", "Ear_left": "Head", "Eye_right": "Head",
          "Ear_right": "Head"}
# Offsets from the pelvis (m): standing, the left arm reaching forward (-x), the right hanging.
OFFSET = {"Pelvis": (0, 0, 0), "Spine_Naval": (0, 0, 0.2), "Spine_Chest": (0, 0, 0.4),
          "Neck": (0, 0, 0.6), "Clavicle_left": (0, 0.05, 0.55), "Shoulder_left": (0, 0.2, 0.5),
          "Elbow_left": (-0.1, 0.22, 0.25), "Wrist_left": (-0.3, 0.22, 0.2),
          "Hand_left": (-0.38, 0.22, 0.2), "Handtip_left": (-0.46, 0.22, 0.2),
          "Thumb_left": (-0.36, 0.18, 0.22), "Clavicle_right": (0, -0.05, 0.55),
          "Shoulder_right": (0, -0.2, 0.5), "Elbow_right": (0, -0.22, 0.25),
          "Wrist_right": (0, -0.22, 0.0), "Hand_right": (0, -0.22, -0.08),
          "Handtip_right": (0, -0.22, -0.16), "Thumb_right": (-0.02, -0.2, -0.06),
          "Hip_left": (0, 0.1, 0), "Knee_left": (0, 0.1, -0.45), "Ankle_left": (0, 0.1, -0.85),
          "Foot_left": (-0.12, 0.1, -0.95), "Hip_right": (0, -0.1, 0),
          "Knee_right": (0, -0.1, -0.45), "Ankle_right": (0, -0.1, -0.85),
          "Foot_right": (-0.12, -0.1, -0.95), "Head": (0, 0, 0.75), "Nose": (-0.1, 0, 0.75),
          "Eye_left": (-0.08, 0.03, 0.8), "Ear_left": (0, 0.07, 0.77),
          "Eye_right": (-0.08, -0.03, 0.8), "Ear_right": (0, -0.07, 0.77)}
# The part of each bone, by its child joint (docs/node.md, "Skeletons"), and the parts'
# diameters (fixtures/skeleton_params.yaml).
PART = {}
for j in JOINTS[1:]:
    p = PARENT[j]
    if j.startswith(("Hand", "Thumb")):
        PART[j] = "hand"
    elif j.startswith(("Elbow", "Wrist")):
        PART[j] = "arm"
    elif j.startswith(("Knee", "Ankle", "Foot")):
        PART[j] = "leg"
    elif j in ("Head", "Nose", "Eye_left", "Ear_left", "Eye_right", "Ear_right"):
        PART[j] = "head"
    else:
        PART[j] = "torso"  # spine, neck, clavicles, shoulders, hips
DIAMETER = {"head": 0.24, "torso": 0.40, "arm": 0.12, "hand": 0.10, "leg": 0.18}


def joint_at(name, t):
    o = OFFSET[name]
    return (START[0] + o[0] - SPEED * t, START[1] + o[1], START[2] + o[2])


def capsule_box(a, b, diameter):
    """(centre, quaternion x y z w, dimensions) of the capsule's tight box."""
    d = [b[i] - a[i] for i in range(3)]
    length = math.sqrt(sum(c * c for c in d))
    centre = tuple(0.5 * (a[i] + b[i]) for i in range(3))
    u = [c / length for c in d]
    # The rotation taking z to u: about z x u by acos(u_z) (any turn about u gives this box).
    axis = (-u[1], u[0], 0.0)
    s = math.sqrt(axis[0] ** 2 + axis[1] ** 2)
    angle = math.acos(max(-1.0, min(1.0, u[2])))
    if s < 1e-12:
        q = (0.0, 0.0, 0.0, 1.0) if u[2] > 0 else (1.0, 0.0, 0.0, 0.0)
    else:
        h = math.sin(0.5 * angle) / s
        q = (axis[0] * h, axis[1] * h, 0.0, math.cos(0.5 * angle))
    return centre, q, (diameter, diameter, length + diameter)


def capsule_tracked_box(box_id, part, a, b):
    """The capsule of `part` between joints a and b as the TrackedBox the node should make of
    it: its tight box (capsule_box), label person/<part>, the body's velocity."""
    centre, q, dims = capsule_box(a, b, DIAMETER[part])
    box = TrackedBox()
    box.id = box_id
    box.label = "person/" + part
    box.pose = Pose()
    box.pose.position.x, box.pose.position.y, box.pose.position.z = centre
    (box.pose.orientation.x, box.pose.orientation.y, box.pose.orientation.z,
     box.pose.orientation.w) = q
    box.dimensions = Vector3(*dims)
    box.twist = Twist()
    box.twist.linear = Vector3(-SPEED, 0.0, 0.0)
    return box


def bone_id(j):
    return "%d/%s->%s" % (BODY, PARENT[j], j)


def boxes_msg(stamp, t):
    msg = TrackedBoxArray()
    msg.header.stamp = stamp
    msg.header.frame_id = "world"
    for j in JOINTS[1:]:
        msg.boxes.append(capsule_tracked_box(bone_id(j), PART[j], joint_at(PARENT[j], t),
                                             joint_at(j, t)))
    return msg


def k4abt_msg(stamp, t):
    """As the driver's getBodyMarker fills each marker (k4a_ros_device.cpp)."""
    msg = MarkerArray()
    for index, name in enumerate(JOINTS):
        m = Marker()
        m.header.frame_id = "world"
        m.header.stamp = stamp
        m.lifetime = rospy.Duration(0.25)
        m.id = BODY * 100 + index
        m.type = Marker.SPHERE
        m.color.r, m.color.a = 1.0, 1.0
        m.scale = Vector3(0.05, 0.05, 0.05)
        m.pose.position.x, m.pose.position.y, m.pose.position.z = joint_at(name, t)
        m.pose.orientation.w = 1.0
        msg.markers.append(m)
    return msg


Recorder = ContactStatusRecorder  # wp_node_testlib


def median(values):
    v = sorted(values)
    return v[len(v) // 2]


TOPICS = ("/scene/boxes/", "/scene/k4abt/", "/humans/bodies/tracked/")


def without_topic(track_id):
    """A track id without the input topic that qualifies it (several input topics)."""
    for topic in TOPICS:
        if track_id.startswith(topic):
            return track_id[len(topic):]
    return track_id


def check_same(test, recorders, t0, skeleton_ns, min_bones, must_have):
    """The checks of the module's docstring: the skeleton node `skeleton_ns` against "boxes"."""
    since, until = t0 + rospy.Duration(SKIP_S), t0 + rospy.Duration(SCENE_S)
    instants, statuses = {}, {}
    for ns in ("boxes", skeleton_ns):
        contacts, status = recorders[ns].between(since, until)
        test.assertGreater(len(contacts), 20, "%s: %d contact arrays" % (ns, len(contacts)))
        per_id = {}
        for c in contacts:
            test.assertEqual(c.status, ContactEventArray.OK, "%s: %s" % (ns, c.status_details))
            for e in c.events:
                # The robot's events (the bones of one body touch each other too).
                if e.state == e.END or "post" not in (e.id_a, e.id_b):
                    continue
                other = e.id_b if e.id_a == "post" else e.id_a
                bone = without_topic(other)
                per_id.setdefault(bone, []).append(c.header.stamp.to_sec() + e.time_to_contact)
        instants[ns] = per_id
        test.assertGreater(len(status), 20, "%s: %d safety_status" % (ns, len(status)))
        rows = []
        for s in status:
            test.assertEqual(s.status, SafetyStatus.OK, "%s: %s" % (ns, s.reason))
            if s.separation == float("inf"):
                continue
            # The limiting bone, without its topic and side (the scenes are symmetric in y).
            bone = without_topic(s.id_object).replace("_left", "").replace("_right", "")
            bone = re.sub(r"(^|/|>)[lr]_", r"\1", bone)
            rows.append((s.header.stamp.to_sec(), bone, s.separation, s.approach_speed))
            test.assertAlmostEqual(s.raw_scale, ssm_scale(s.separation, s.approach_speed),
                                   delta=1e-3, msg=ns)
        statuses[ns] = rows

    bones = set(instants["boxes"])
    test.assertEqual(set(instants[skeleton_ns]), bones)
    test.assertGreaterEqual(len(bones), min_bones, bones)
    test.assertIn(must_have, bones)
    for bone in bones:
        reference = median(instants["boxes"][bone])
        for instant in instants[skeleton_ns][bone]:
            test.assertAlmostEqual(instant, reference, delta=5e-3,
                                   msg="%s: contact at %.4f, boxes %.4f" % (bone, instant, reference))
    test.assertGreater(len(statuses["boxes"]), 5, "no status within reach")
    test.assertGreater(len(statuses[skeleton_ns]), 5, "no status within reach")
    # Cycle by cycle (the two nodes' timers differ by a few ms): the skeleton node's limiting
    # bone, separation and approach speed are the boxes node's, interpolated linearly to
    # the skeleton node's stamp between the two boxes cycles around it. Where the limiting
    # bone changes between those cycles there is nothing to interpolate: skipped, at most
    # one cycle in five. Bones the same distance away tie (the torso and the hip facing the
    # post), and which one a node names depends on its pair order: a cycle whose bone differs
    # but whose separation and speed are the interpolated ones within the tolerance is such a
    # tie and counts as compared.
    compared = 0
    ref = statuses["boxes"]
    for stamp, bone, separation, speed in statuses[skeleton_ns]:
        after = next((i for i, r in enumerate(ref) if r[0] >= stamp), None)
        if after is None or after == 0:
            continue
        r0, r1 = ref[after - 1], ref[after]
        if r1[0] - r0[0] > 0.1:
            continue
        w = (stamp - r0[0]) / (r1[0] - r0[0])
        want_separation = r0[2] + w * (r1[2] - r0[2])
        want_speed = r0[3] + w * (r1[3] - r0[3])
        if r0[1] != bone or r1[1] != bone:
            if (abs(separation - want_separation) <= 1e-3 and abs(speed - want_speed) <= 1e-3):
                compared += 1  # a tie
            continue
        compared += 1
        test.assertAlmostEqual(separation, want_separation, delta=1e-3,
                               msg="%s at %.3f" % (bone, stamp))
        test.assertAlmostEqual(speed, want_speed, delta=1e-3,
                               msg="%s at %.3f" % (bone, stamp))
    test.assertGreater(compared, 0.8 * len(statuses[skeleton_ns]),
                       "%d of %d compared" % (compared, len(statuses[skeleton_ns])))


class SkeletonMarkers(unittest.TestCase):
    def test_same_capsules_as_boxes(self):
        k4abt_pub = rospy.Publisher("/scene/k4abt", MarkerArray, queue_size=10)
        boxes_pub = rospy.Publisher("/scene/boxes", TrackedBoxArray, queue_size=10)
        recorders = {ns: Recorder("/" + ns) for ns in ("boxes", "k4abt")}
        _static = broadcast_static([("world", "base_link", (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))])
        deadline = rospy.Time.now() + rospy.Duration(20.0)

        while rospy.Time.now() < deadline and not (
                k4abt_pub.get_num_connections() >= 1 and boxes_pub.get_num_connections() >= 1 and
                all(r.posed() for r in recorders.values())):
            rospy.sleep(0.05)
        self.assertTrue(all(r.posed() for r in recorders.values()), "the post is not posed")
        self.assertGreaterEqual(k4abt_pub.get_num_connections(), 1)
        self.assertGreaterEqual(boxes_pub.get_num_connections(), 1)

        # Nobody in view first: the driver publishes empty MarkerArrays (no header at all).
        empty_from = rospy.Time.now()
        rate = rospy.Rate(20.0)
        while rospy.Time.now() < empty_from + rospy.Duration(1.0):
            k4abt_pub.publish(MarkerArray())
            rate.sleep()
        contacts, _ = recorders["k4abt"].between(empty_from + rospy.Duration(0.5),
                                                 empty_from + rospy.Duration(1.0))
        self.assertGreater(len(contacts), 5)
        for c in contacts:
            self.assertEqual(c.status, ContactEventArray.OK, "no bodies: %s" % c.status_details)
            self.assertEqual(len(c.events), 0)

        t0 = rospy.Time.now()
        while rospy.Time.now() < t0 + rospy.Duration(SCENE_S):
            stamp = rospy.Time.now() - rospy.Duration(0.05)
            t = (stamp - t0).to_sec()
            boxes_pub.publish(boxes_msg(stamp, t))
            k4abt_pub.publish(k4abt_msg(stamp, t))
            rate.sleep()
        rospy.sleep(0.3)

        check_same(self, recorders, t0, "k4abt", 10, bone_id("Spine_Naval"))

if __name__ == "__main__":
    rospy.init_node("test_foreign_skeleton_markers")
    rostest.rosrun("workspace_proximity", "test_foreign_skeleton_markers", SkeletonMarkers, sys.argv)
