#!/usr/bin/env python3
"""replay_bag on skeleton bags (issue 24 item 4): the replay reads skeletons as the node does.

Bags written at test time: the Azure Kinect body of test/ros/test_foreign_skeleton_markers.py
(a MarkerArray of 32 joint SPHEREs on /people, declared in ~skeleton_marker_topics) and the
ROS4HRI body of test/ros/test_foreign_rep155.py (hri_msgs/IdsList on /people, the upstream
definition through genpy, and its link frames on /tf), each beside a bag of the same body's
capsule boxes as TrackedBoxArray on /people. Same parameters (test/ros/fixtures: common,
foreign, skeleton_params), 3 s of messages at 20 Hz received 50 ms after their stamp.

Checks, from 0.5 s after the first message (the joints' differences need two sightings): at
every cycle stamp, the skeleton replay's events (ids, state, time to contact, distance) are
the boxes replay's, numbers within 1e-6, and its status, separation, approach speed and raw
scale too; the robot has events with at least 8 bones.

    test_replay_skeletons.py REPLAY_BAG [unittest args]
"""
import os
import shutil
import sys
import tempfile
import unittest

from replay_testlib import FIXTURES, ROOT, assert_same_ssm, main, outputs, run_replay, \
    write_world_tf

sys.path.insert(0, os.path.join(ROOT, "test", "foreign"))
sys.path.insert(0, os.path.join(ROOT, "test", "ros"))

import genpy  # noqa: E402
import rosbag  # noqa: E402
from tf2_msgs.msg import TFMessage  # noqa: E402

import make_fixtures  # noqa: E402

T0 = 100.0
SKIP = 0.5
CONFIGS = [os.path.join(FIXTURES, n) for n in ("common_params.yaml", "foreign_params.yaml",
                                               "skeleton_params.yaml")]


def write_bag(path, messages):
    """`messages(stamp, t)`: a list of (topic, message) for the stamp."""
    with rosbag.Bag(path, "w") as bag:
        write_world_tf(bag, T0)
        for k in range(61):
            stamp = genpy.Time.from_sec(T0) + genpy.Duration.from_sec(0.05 * k)
            t = 0.05 * k
            for topic, msg in messages(stamp, t):
                # tf as a tracker's own: written at the stamp; the rest received 50 ms later.
                at = stamp if topic == "/tf" else stamp + genpy.Duration.from_sec(0.05)
                bag.write(topic, msg, at)


class ReplaySkeletons(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp()

    def tearDown(self):
        shutil.rmtree(self.tmp)

    def replay(self, name, messages, extra):
        bag = os.path.join(self.tmp, name + ".bag")
        write_bag(bag, messages)
        topics = os.path.join(self.tmp, name + ".yaml")
        with open(topics, "w") as f:
            f.write("input_topics: [/people]\n" + extra)
        out = os.path.join(self.tmp, "out-" + name)
        run = run_replay(bag, out, CONFIGS + [topics])
        self.assertEqual(run.returncode, 0, "%s: %s" % (name, run.stderr.decode(errors="replace")))
        return outputs(out)

    def compare(self, skeleton, boxes):
        (events, cycles), (ref_events, ref_cycles) = skeleton, boxes

        def by_stamp(rows):
            out = {}
            for e in rows:
                if float(e["stamp"]) >= T0 + SKIP:
                    out.setdefault(e["stamp"], {})[(e["id_a"], e["id_b"])] = e
            return out
        mine, ref = by_stamp(events), by_stamp(ref_events)
        self.assertGreater(len(ref), 40)
        self.assertEqual(sorted(mine), sorted(ref))
        bones = set()
        for stamp in ref:
            self.assertEqual(sorted(mine[stamp]), sorted(ref[stamp]), stamp)
            for pair, r in ref[stamp].items():
                e = mine[stamp][pair]
                self.assertEqual(e["state"], r["state"], (stamp, pair))
                for key in ("time_to_contact", "distance"):
                    self.assertAlmostEqual(float(e[key]), float(r[key]), delta=1e-6,
                                           msg="%s %s %s" % (stamp, pair, key))
                if "post" in pair:
                    bones.add(pair)
        self.assertGreaterEqual(len(bones), 8, bones)
        ref_cycles = {c["stamp"]: c for c in ref_cycles}
        compared = 0
        for c in cycles:
            if float(c["stamp"]) < T0 + SKIP:
                continue
            r = ref_cycles[c["stamp"]]
            compared += 1
            self.assertEqual(c["status"], r["status"], "%s / %s" % (c["details"], r["details"]))
            assert_same_ssm(self, c, r, lambda key: key)
        self.assertGreater(compared, 40)

    def test_k4abt_markers(self):
        import rospy  # noqa: F401  (rospy.Duration in the markers' lifetime)
        import test_foreign_skeleton_markers as k
        skeleton = self.replay("k4abt", lambda s, t: [("/people", k.k4abt_msg(s, t))],
                               "skeleton_marker_topics: [/people]\n")
        boxes = self.replay("k4abt_boxes", lambda s, t: [("/people", k.boxes_msg(s, t))], "")
        self.compare(skeleton, boxes)

    def test_rep155(self):
        import test_foreign_rep155 as h
        root = make_fixtures.generate({})
        try:
            m = make_fixtures.load(root, "hri_msgs")

            def messages(s, t):
                ids = m.IdsList(ids=[h.BODY])
                ids.header.stamp = s
                return [("/tf", TFMessage(transforms=h.link_transforms(s, t))), ("/people", ids)]
            skeleton = self.replay("rep155", messages, "")
        finally:
            shutil.rmtree(root)
        boxes = self.replay("rep155_boxes", lambda s, t: [("/people", h.boxes_msg(s, t))], "")
        self.compare(skeleton, boxes)


if __name__ == "__main__":
    main("test_replay_skeletons.py")  # with the devel space's TrackedBoxArray
