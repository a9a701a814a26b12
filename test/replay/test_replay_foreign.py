#!/usr/bin/env python3
"""replay_bag on bags of the foreign tracker types (issue 24), one small bag per family written
at test time with the upstream definitions (Python classes that Debian's genpy generates from
foreign_msgs/, as the upstream package's build would: each connection records the upstream
md5 and full definition), replayed offline beside the same scene as TrackedBoxArray.

The scene (as the rostests foreign_*): a 1 m cube "post" at the origin of base_link = world,
one person (0.6 x 0.6 x 1.8 m: the monitor's person size for a point, or the size the message
gives) walking from x = 1.6 m towards it at 0.25 m/s, 3 s of messages at 20 Hz received 50 ms
after their stamp. Families: people, position_measurements, spencer v1/v2/v3, pedsim v1/v2,
bayes v1/v2, leg_tracker, derived_objects (with and without covariance); and the types without
ids, through the multi-object tracker: vision_msgs/Detection3DArray, jsk BoundingBoxArray v1/v2,
MarkerArray, PoseArray and obstacle_detector/Obstacles (the person as a circle, and a static
wall segment out of reach: two tracks).

Checks per family, from 0.5 s after the first message (the types without velocity need two
sightings for a finite difference):
- every cycle has the pair's event, whose contact instant (stamp + time_to_contact) is the
  analytic one (the faces meet 3.2 s after the start) within 1 ms;
- at every cycle stamp both replays share (the same grid: the same bag start), status,
  separation, approach speed and raw scale equal the TrackedBoxArray replay's within 1e-6;
- for the types without ids (with the labels of test/ros/fixtures/obstacle_params.yaml), from
  1 s on: every cycle OK, with the pair's event between the post and a tracker id (t<n>), its
  contact instant never later than the analytic one (a new track's unknown velocity and the
  filter's errors may bring it earlier), and as many tracks as the scene has objects; from
  1.5 s on, beside the twin bag (the person as a TrackedBoxArray box of label unknown): the
  same contact instant (1 ms) and separation (1 mm), the approach speed plus the tracker's own
  steady 3 sigma velocity error 0.4472 m/s (2 mm/s), raw_scale the formula's (1e-6);
- a spencer track with a position covariance (3 sigma 0.3045 m): its contact instant 1.24 s
  earlier (the analytic one with that error rounded up to 0.31 m as margin) within 1 ms, and
  its raw scale the formula's with what the error exceeds Z_d taken off the separation;
- a foreign topic whose frame is never on tf ends the replay with exit status 5 naming it;
- a bag of a known type with another md5 (one more field) is refused naming the field, and
  one of an unknown type name is refused naming it (exit status 4, a message, no crash).

    test_replay_foreign.py REPLAY_BAG [unittest args]
"""
import math
import os
import shutil
import sys
import tempfile
import unittest

from replay_testlib import FIXTURES, ROOT, assert_same_ssm, main, outputs, run_replay, \
    write_world_tf

sys.path.insert(0, os.path.join(ROOT, "test", "foreign"))

import genpy  # noqa: E402
import rosbag  # noqa: E402

import make_fixtures  # noqa: E402
from foreign_scene import DETECTION_FAMILIES, FAMILIES, load_module  # noqa: E402

BAG_PROBLEM, INCOMPLETE = 4, 5
SPEED, START_X, HEIGHT = 0.25, 1.6, 0.9
T0 = 100.0
CONTACT = T0 + (START_X - 0.3 - 0.5) / SPEED
SKIP = 0.5
TRACKS = {"obstacles": 2}  # the person and the wall segment
VARIANCE = 0.0103  # m^2: test_a_covariance_widens_the_margin
TRACKER_LABELS = os.path.join(FIXTURES, "obstacle_params.yaml")
TRACKER_V_ERR = 0.4472  # the tracker's steady 3 sigma velocity error at 20 Hz with 5 cm noise
CONFIGS = [os.path.join(FIXTURES, "common_params.yaml"),
           os.path.join(FIXTURES, "foreign_params.yaml")]


def boxes_builder(label="person"):
    sys.path.insert(0, os.path.join(ROOT, "test", "ros"))
    from wp_node_testlib import Track, TrackedBoxArray
    person = Track("100", label, (START_X, 0.0, HEIGHT), (0.6, 0.6, 1.8),
                   velocity=(-SPEED, 0.0, 0.0))
    person.set_t0(genpy.Time.from_sec(T0))

    def build(_m, s, _p, _v):
        msg = TrackedBoxArray()
        msg.header.stamp = s
        msg.header.frame_id = "world"
        msg.boxes.append(person.to_msg(s))
        return msg
    return build


def write_bag(path, m, build, cls=None):
    with rosbag.Bag(path, "w") as bag:
        write_world_tf(bag, T0)
        for k in range(61):
            stamp = genpy.Time.from_sec(T0) + genpy.Duration.from_sec(0.05 * k)
            t = (stamp - genpy.Time.from_sec(T0)).to_sec()
            msg = build(m, stamp, (START_X - SPEED * t, 0.0, HEIGHT), (-SPEED, 0.0, 0.0))
            if cls is not None:
                out = cls()
                for name in msg.__slots__:
                    setattr(out, name, getattr(msg, name))
                msg = out
            bag.write("/people", msg, stamp + genpy.Duration.from_sec(0.05))


class ReplayForeign(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp()
        with open(os.path.join(cls.tmp, "topics.yaml"), "w") as f:
            f.write("input_topics: [/people]\n")
        cls.boxes = cls.replay(cls, "boxes", None, boxes_builder())
        # The twin of the types without ids: the person as a box of label unknown, whose
        # growth bounds (obstacle_params.yaml) exceed the tracker's own errors.
        cls.unknown_boxes = cls.replay(cls, "unknown_boxes", None, boxes_builder("unknown"),
                                       configs=[TRACKER_LABELS])

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp)

    def replay(self, name, m, build, cls=None, expect_ok=True, configs=()):
        bag = os.path.join(self.tmp, name + ".bag")
        write_bag(bag, m, build, cls)
        out = os.path.join(self.tmp, "out-" + name)
        topics = os.path.join(self.tmp, "topics.yaml")
        run = run_replay(bag, out, CONFIGS + list(configs) + [topics])
        if not expect_ok:
            return run
        if run.returncode != 0:
            raise AssertionError("%s: replay_bag exit %d: %s" % (
                name, run.returncode, run.stderr.decode(errors="replace")))
        return outputs(out)

    def check(self, family):
        package, versions, build = FAMILIES[family]
        root = make_fixtures.generate(versions)
        try:
            m = make_fixtures.load(root, package)
            events, cycles = self.replay(family, m, build)
        finally:
            shutil.rmtree(root)
        steady = [c for c in cycles if T0 + SKIP <= float(c["stamp"]) <= T0 + 3.0]
        self.assertGreater(len(steady), 40, family)
        by_stamp = {}
        for e in events:
            by_stamp.setdefault(e["stamp"], []).append(e)
        for c in steady:
            evs = by_stamp.get(c["stamp"], [])
            self.assertEqual(len(evs), 1, "%s at %s: %d events" % (family, c["stamp"], len(evs)))
            instant = float(c["stamp"]) + float(evs[0]["time_to_contact"])
            self.assertAlmostEqual(instant, CONTACT, delta=1e-3, msg=family)
        reference = {c["stamp"]: c for c in self.boxes[1]}
        compared = 0
        for c in steady:
            r = reference.get(c["stamp"])
            if r is None:
                continue
            compared += 1
            self.assertEqual(c["status"], r["status"], "%s: %s / %s" % (family, c["details"],
                                                                      r["details"]))
            assert_same_ssm(self, c, r, lambda key: "%s %s at %s" % (family, key, c["stamp"]))
        self.assertGreater(compared, 40, family)

    def check_detections(self, family):
        # Through the multi-object tracker: ids are its own; a new track's velocity is unknown
        # (it grows at the label's speed) and a known one carries the filter's error, so the
        # predicted contact may come early, never late. With the labels of obstacle_params.yaml
        # (growth bounds above the tracker's own errors) its twin is the person as a
        # TrackedBoxArray box of label unknown: from 1.5 s on (the filter converged on the
        # noise-free walk) the same contact instant (1 ms) and separation (1 mm), and the
        # approach speed plus the tracker's own steady 3 sigma velocity error, which speed and
        # separation add (2 mm/s); raw_scale the formula's (1e-6).
        sys.path.insert(0, os.path.join(ROOT, "test", "ros"))
        from wp_node_testlib import ssm_scale
        package, versions, build = DETECTION_FAMILIES[family]
        root = make_fixtures.generate(versions)
        try:
            events, cycles = self.replay(family, load_module(make_fixtures, root, package), build,
                                         configs=[TRACKER_LABELS])
        finally:
            shutil.rmtree(root)
        steady = [c for c in cycles if T0 + 1.0 <= float(c["stamp"]) <= T0 + 3.0]
        self.assertGreater(len(steady), 30, family)
        by_stamp = {}
        for e in events:
            by_stamp.setdefault(e["stamp"], []).append(e)
        twin_cycles = {c["stamp"]: c for c in self.unknown_boxes[1]}
        twin_events = {e["stamp"]: e for e in self.unknown_boxes[0]}
        compared = 0
        for c in steady:
            self.assertEqual(c["status"], "OK", "%s: %s" % (family, c["details"]))
            evs = by_stamp.get(c["stamp"], [])
            self.assertEqual(len(evs), 1, "%s at %s: %d events" % (family, c["stamp"], len(evs)))
            # The tracker's ids ("t<n>", qualified by the topic), never the message's.
            ids = [evs[0]["id_a"].split("/")[-1], evs[0]["id_b"].split("/")[-1]]
            self.assertIn("post", ids)
            self.assertTrue(any(i.startswith("t") and i[1:].isdigit() for i in ids),
                            "%s: not a tracker id: %s" % (family, evs[0]))
            instant = float(c["stamp"]) + float(evs[0]["time_to_contact"])
            self.assertLessEqual(instant, CONTACT + 5e-3, "%s: late at %s" % (family, c["stamp"]))
            self.assertEqual(int(c["tracks"]), TRACKS.get(family, 1), "%s at %s" % (
                family, c["stamp"]))
            twin = twin_cycles.get(c["stamp"])
            if float(c["stamp"]) < T0 + 1.5 or twin is None:
                continue
            compared += 1
            where = "%s at %s" % (family, c["stamp"])
            twin_instant = float(c["stamp"]) + float(twin_events[c["stamp"]]["time_to_contact"])
            self.assertAlmostEqual(instant, twin_instant, delta=1e-3, msg=where)
            self.assertAlmostEqual(float(c["separation"]), float(twin["separation"]), delta=1e-3,
                                   msg=where)
            self.assertAlmostEqual(float(c["approach_speed"]),
                                   float(twin["approach_speed"]) + TRACKER_V_ERR, delta=2e-3,
                                   msg=where)
            self.assertAlmostEqual(float(c["raw_scale"]),
                                   ssm_scale(float(c["separation"]), float(c["approach_speed"])),
                                   delta=1e-6, msg=where)
        self.assertGreater(compared, 20, family)

    def test_a_covariance_widens_the_margin(self):
        # spencer v2 with a position variance of 0.0103 m^2 on x, y and z: the track's own 3
        # sigma position error is 3 sqrt(0.0103) = 0.3045 m, which the margin takes rounded up
        # to the centimetre, 0.31 m (docs/node.md: "A track's own uncertainty"; the label's is
        # 0), so the faces' gap 0.8 - 0.25 t closes at t = 1.96 s instead of 3.2 s; speed and
        # separation take what the error exceeds Z_d (0.1 m) off the separation.
        sys.path.insert(0, os.path.join(ROOT, "test", "ros"))
        from wp_node_testlib import ssm_scale
        package, versions, plain = FAMILIES["spencer_v2"]

        def covariant(m, s, p, v):
            msg = plain(m, s, p, v)
            cov = [0.0] * 36
            cov[0] = cov[7] = cov[14] = VARIANCE
            msg.tracks[0].pose.covariance = cov
            return msg
        root = make_fixtures.generate(versions)
        try:
            events, cycles = self.replay("covariance", make_fixtures.load(root, package), covariant)
        finally:
            shutil.rmtree(root)
        error = 3.0 * math.sqrt(VARIANCE)
        margin = math.ceil(100.0 * error) / 100.0
        contact = T0 + (START_X - 0.3 - 0.5 - margin) / SPEED
        steady = [c for c in cycles if T0 + SKIP <= float(c["stamp"]) <= T0 + 3.0]
        self.assertGreater(len(steady), 40)
        by_stamp = {e["stamp"]: e for e in events}
        scaled = 0
        for c in steady:
            self.assertEqual(c["status"], "OK", c["details"])
            stamp = float(c["stamp"])
            instant = stamp + float(by_stamp[c["stamp"]]["time_to_contact"])
            self.assertAlmostEqual(instant, max(contact, stamp), delta=1e-3, msg=c["stamp"])
            if c["separation"] != "":
                scaled += 1
                self.assertAlmostEqual(float(c["raw_scale"]),
                                       ssm_scale(float(c["separation"]) - (error - 0.1), SPEED),
                                       delta=1e-6)
        self.assertGreater(scaled, 10)

    def test_a_frame_without_tf_is_reported(self):
        # As for TrackedBoxArray: the replay ends with exit status 5 naming the frame.
        package, versions, build = FAMILIES["leg_tracker"]

        def elsewhere(m, s, p, v):
            msg = build(m, s, p, v)
            msg.header.frame_id = "tracker_frame"
            return msg
        root = make_fixtures.generate(versions)
        try:
            run = self.replay("no_tf", make_fixtures.load(root, package), elsewhere,
                              expect_ok=False)
        finally:
            shutil.rmtree(root)
        err = run.stderr.decode(errors="replace")
        self.assertEqual(run.returncode, INCOMPLETE, err)
        self.assertIn("tracker_frame", err)

    def test_wrong_md5_and_unknown_type_refused(self):
        package, versions, build = FAMILIES["people"]
        root = make_fixtures.generate(versions)
        try:
            m = make_fixtures.load(root, package)

            class Wrong(m.People):
                __slots__ = []
                _md5sum = "0123456789abcdef0123456789abcdef"
                _full_text = "float64 extra_field\n" + m.People._full_text

            class Unknown(m.People):
                __slots__ = []
                _type = "my_tracker/People"

            for name, cls, words in (("wrong_md5", Wrong, ["people_msgs/People", "extra_field"]),
                                     ("unknown_type", Unknown, ["my_tracker/People"])):
                run = self.replay(name, m, build, cls, expect_ok=False)
                err = run.stderr.decode(errors="replace")
                self.assertEqual(run.returncode, BAG_PROBLEM, err)
                for w in words:
                    self.assertIn(w, err)
                for bad in ("terminate called", "Segmentation", "Aborted", "core dumped"):
                    self.assertNotIn(bad, err)
        finally:
            shutil.rmtree(root)


def _add(family):
    setattr(ReplayForeign, "test_" + family, lambda self: self.check(family))


for _family in FAMILIES:
    _add(_family)


def _add_detections(family):
    setattr(ReplayForeign, "test_" + family, lambda self: self.check_detections(family))


for _family in DETECTION_FAMILIES:
    _add_detections(_family)


if __name__ == "__main__":
    main("test_replay_foreign.py")  # with the devel space's TrackedBoxArray
