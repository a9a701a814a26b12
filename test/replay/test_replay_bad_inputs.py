#!/usr/bin/env python3
"""replay_bag on bad bags and bad configurations: each gives a message naming the problem on
stderr and its documented non-zero exit status, never a crash (a signal, an abort, an uncaught
exception). The bad bags are made from the shipped demo bag with the Python rosbag API:

  missing input topic, no tf at all, a robot frame never on tf, the boxes' frame never on tf,
  an unindexed bag (a recording whose writer died before closing it), a bag truncated before
  its index, one cut inside its index, a chunk overwritten with garbage, an index entry
  pointing outside its chunk, a message whose list claims ten million entries, 60 reproducible
  random damages (plain and lz4), a file that is not a bag, no file; and configurations with a value out of range (the node's validate()
  message), a value of the wrong type, a YAML syntax error, a URDF that does not parse.

    test_replay_bad_inputs.py REPLAY_BAG [unittest args]
"""
import io
import os
import random
import subprocess
import sys
import tempfile
import unittest

import rosbag

import replay_testlib
from replay_testlib import ROOT, main, run_replay

BAG = os.path.join(ROOT, "test", "bags", "demo_cell.bag")
CONFIGS = [os.path.join(ROOT, "config", "proximity_monitor.yaml"),
           os.path.join(ROOT, "config", "demo_monitor.yaml")]
URDF = os.path.join(ROOT, "config", "demo_arm.urdf")

# replayUsage(): the exit statuses.
CONFIG, BAG_PROBLEM, INCOMPLETE = 3, 4, 5


def copy_bag(src, dst, keep=lambda topic, msg: msg, compression="none"):
    """Writes the messages of `src` that `keep` returns (possibly changed) into `dst`."""
    with rosbag.Bag(src) as inp, rosbag.Bag(dst, "w", compression=compression) as out:
        for topic, msg, t in inp.read_messages():
            msg = keep(topic, msg)
            if msg is not None:
                out.write(topic, msg, t)


class BadInputsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def path(self, name):
        return os.path.join(self.tmp.name, name)

    def replay(self, bag, configs=CONFIGS, urdf=URDF, extra=()):
        return run_replay(bag, self.path("out-" + os.path.basename(bag)), configs,
                          (["--urdf", urdf] if urdf else []) + list(extra))

    def assertFails(self, run, status, *words):
        err = run.stderr.decode(errors="replace")
        self.assertGreater(run.returncode, 0, "crashed or succeeded (status %d): %s" % (run.returncode, err))
        self.assertEqual(run.returncode, status, err)
        for bad in ("terminate called", "Segmentation", "Aborted", "core dumped"):
            self.assertNotIn(bad, err)
        for w in words:
            self.assertIn(w, err)
        return err

    # ---- bags ----

    def test_missing_input_topic(self):
        bag = self.path("no_boxes.bag")
        copy_bag(BAG, bag, lambda topic, msg: msg if topic != "/tracked_objects" else None)
        self.assertFails(self.replay(bag), BAG_PROBLEM, "has no topic /tracked_objects",
                         "/tf (tf2_msgs/TFMessage)")
        # Another input topic than the bag's.
        self.assertFails(self.replay(BAG, extra=["--input-topic", "/tracker/boxes"]), BAG_PROBLEM,
                         "has no topic /tracker/boxes")

    def test_no_tf_at_all(self):
        bag = self.path("no_tf.bag")
        copy_bag(BAG, bag, lambda topic, msg: msg if topic == "/tracked_objects" else None)
        self.assertFails(self.replay(bag), BAG_PROBLEM, "has no /tf or /tf_static",
                         "'base_link'", "'tool_tip'")

    def test_robot_frame_without_tf(self):
        bag = self.path("no_tool_tip.bag")

        def drop_tip(topic, msg):
            if topic == "/tf":
                msg.transforms = [t for t in msg.transforms if t.child_frame_id != "tool_tip"]
            return msg
        copy_bag(BAG, bag, drop_tip)
        run = self.replay(bag)
        self.assertFails(run, INCOMPLETE, "no tf for frame 'tool_tip' (robot body 'tool_tip')")
        # The rest was replayed and written.
        self.assertTrue(os.path.getsize(os.path.join(self.path("out-no_tool_tip.bag"), "events.csv")) > 1000)
        self.assertIn(b"MISSING", run.stdout)

    def test_boxes_frame_without_tf(self):
        bag = self.path("camera_frame.bag")

        def to_camera(topic, msg):
            if topic == "/tracked_objects":
                msg.header.frame_id = "camera"
            return msg
        copy_bag(BAG, bag, to_camera)
        run = self.replay(bag)
        self.assertFails(run, INCOMPLETE, "no tf for frame 'camera' (the tracked boxes' frame)")
        self.assertIn(b"frame ", run.stdout)  # the drops, by reason, in the summary

    def test_unindexed_bag(self):
        bag = self.path("unindexed.bag")
        # A writer that dies before closing: the header's index position is never written.
        script = ("import os, rosbag\n"
                  "out = rosbag.Bag(%r, 'w')\n"
                  "for topic, msg, t in rosbag.Bag(%r).read_messages():\n"
                  "    out.write(topic, msg, t)\n"
                  "out._file.flush()\n"
                  "os._exit(0)\n" % (bag, BAG))
        subprocess.run([sys.executable, "-c", script], check=True)
        self.assertFails(self.replay(bag), BAG_PROBLEM, "not indexed", "rosbag reindex")

    def test_truncated_bag(self):
        with open(BAG, "rb") as f:
            data = f.read()
        half = self.path("half.bag")
        with open(half, "wb") as f:
            f.write(data[:len(data) // 2])
        self.assertFails(self.replay(half), BAG_PROBLEM, "truncated", "index should start at byte")
        # Cut inside the index (at the end of the file): the record that runs past the end.
        tail = self.path("tail.bag")
        with open(tail, "wb") as f:
            f.write(data[:-10])
        self.assertFails(self.replay(tail), BAG_PROBLEM, "truncated or damaged at byte",
                         "chunk info record of the index")

    def test_damaged_chunk(self):
        with open(BAG, "rb") as f:
            data = bytearray(f.read())
        middle = len(data) // 2
        data[middle:middle + 400] = b"\xff" * 400
        bag = self.path("damaged.bag")
        with open(bag, "wb") as f:
            f.write(bytes(data))
        self.assertFails(self.replay(bag), BAG_PROBLEM, "damaged at byte", "chunk 1 of 1: a record at offset")

    def test_damaged_index_entry(self):
        # An index entry (after the chunk) pointing elsewhere: rosbag would read outside its
        # chunk buffer (it crashed on such bags); the check names the entry.
        with rosbag.Bag(BAG) as b:
            index_pos = b._index_data_pos
        with open(BAG, "rb") as f:
            data = bytearray(f.read())
        # The last index record before the bag's index: its last entry's offset is its last 4 bytes.
        data[index_pos - 4:index_pos] = (0x7FFFFFF0).to_bytes(4, "little")
        bag = self.path("bad_index.bag")
        with open(bag, "wb") as f:
            f.write(bytes(data))
        self.assertFails(self.replay(bag), BAG_PROBLEM, "does not point at its message")

    def test_damaged_list_count(self):
        # A /tf message whose list of transforms claims ten million entries: ROS's deserialiser
        # would allocate and construct them all before finding the bytes missing.
        bag = self.path("bad_count.bag")
        with rosbag.Bag(BAG) as inp, rosbag.Bag(bag, "w") as out:
            for i, (topic, msg, t) in enumerate(inp.read_messages()):
                if topic == "/tf" and i > 100 and not getattr(self, "_patched", False):
                    buf = io.BytesIO()
                    msg.serialize(buf)
                    data = bytearray(buf.getvalue())
                    data[0:4] = (10 ** 7).to_bytes(4, "little")
                    out.write(topic, (msg._type, bytes(data), msg._md5sum, None, type(msg)), t, raw=True)
                    self._patched = True
                else:
                    out.write(topic, msg, t)
        self.assertFails(self.replay(bag), BAG_PROBLEM, "claims 10000000 elements", "on /tf")

    def test_random_damage_never_crashes(self):
        # Reproducible random damage to the bag, plain and lz4-compressed: bytes overwritten,
        # blocks overwritten, the file cut anywhere. Each run ends with a status (0 when only
        # message contents were hit: the monitor rejects or uses them), never a signal or hang.
        lz4 = self.path("lz4.bag")
        copy_bag(BAG, lz4, compression="lz4")
        sources = []
        for path in (BAG, lz4):
            with open(path, "rb") as f:
                sources.append(f.read())
        rng = random.Random(2026)
        statuses = {}
        for i in range(60):
            data = bytearray(sources[i % 2])
            kind = rng.randrange(3)
            if kind == 0:
                for _ in range(rng.randrange(1, 40)):
                    data[rng.randrange(len(data))] = rng.randrange(256)
            elif kind == 1:
                data = data[:rng.randrange(len(data))]
            else:
                at = rng.randrange(len(data))
                n = min(rng.randrange(1, 2000), len(data) - at)
                data[at:at + n] = bytes(rng.randrange(256) for _ in range(n))
            bag = self.path("random.bag")
            with open(bag, "wb") as f:
                f.write(bytes(data))
            run = self.replay(bag)
            err = run.stderr.decode(errors="replace")
            self.assertIn(run.returncode, (0, BAG_PROBLEM, INCOMPLETE),
                          "damage %d (kind %d): status %d: %s" % (i, kind, run.returncode, err[-500:]))
            statuses[run.returncode] = statuses.get(run.returncode, 0) + 1
        self.assertGreater(statuses.get(BAG_PROBLEM, 0), 30, statuses)

    def test_not_a_bag_and_no_file(self):
        text = self.path("notes.bag")
        with open(text, "w") as f:
            f.write("not a bag\n")
        self.assertFails(self.replay(text), BAG_PROBLEM, "not a ROS bag")
        self.assertFails(self.replay(self.path("missing.bag")), BAG_PROBLEM, "cannot open the file")

    # ---- configuration ----

    def write(self, name, text):
        with open(self.path(name), "w") as f:
            f.write(text)
        return self.path(name)

    def test_bad_configuration(self):
        # Out of range: the node's validate() message, as proximity_monitor prints it.
        self.assertFails(self.replay(BAG, configs=CONFIGS + [self.write("rate.yaml", "rate: -1.0\n")]),
                         CONFIG, "invalid parameter ~rate = -1: must be in [0.1, 1000] Hz")
        self.assertFails(self.replay(BAG, configs=[self.write("label.yaml",
                                                              "labels: {person: {critical_time: 5.0}}\n")]),
                         CONFIG, "invalid parameter ~labels/person/critical_time = 5")
        # Wrong type, as the node's reader names it.
        self.assertFails(self.replay(BAG, configs=[self.write("type.yaml", "horizon: long\n")]),
                         CONFIG, "invalid parameter ~horizon: must be a number")
        self.assertFails(self.replay(BAG, configs=[self.write("syntax.yaml", "rate: [30\n")]),
                         CONFIG, "syntax.yaml:", "YAML syntax error")
        self.assertFails(self.replay(BAG, configs=[self.path("none.yaml")]), CONFIG, "cannot read")
        self.assertFails(self.replay(BAG, urdf=self.write("arm.urdf", "<robot name='x'><link>")),
                         CONFIG, "arm.urdf")
        # A bad command line: usage, status 2.
        run = subprocess.run([replay_testlib.REPLAY_BAG, BAG, "--rate-factor", "0"],
                             stderr=subprocess.PIPE)
        self.assertEqual(run.returncode, 2)
        self.assertIn(b"usage: replay_bag", run.stderr)


if __name__ == "__main__":
    main("test_replay_bad_inputs.py", devel_messages=False)
