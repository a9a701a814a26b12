"""Shared by the offline replay tests (test/replay/test_replay_*.py; each imports it from its
own folder, which Python puts first on sys.path): the replay_bag executable from the command
line, the devel space's Python messages, the static world -> base_link transform the written
bags start with, one replay_bag run and its CSV outputs.

A test's main is `replay_testlib.main("test_x.py")`; its tests call `run_replay(...)`, which
reads the executable main() took from the command line.
"""
import csv
import os
import subprocess
import sys
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
FIXTURES = os.path.join(ROOT, "test", "ros", "fixtures")

REPLAY_BAG = None  # the replay_bag executable: main() takes it from the command line

# The keys of cycles.csv that speed and separation fills ("" when it does not apply).
SSM_KEYS = ("separation", "approach_speed", "raw_scale")


def main(script, devel_messages=True):
    """`script REPLAY_BAG [unittest args]`: takes REPLAY_BAG off the command line, with
    `devel_messages` puts this package's Python messages (the devel space beside replay_bag)
    on sys.path, and runs the calling module's tests."""
    global REPLAY_BAG
    if len(sys.argv) < 2:
        sys.exit("usage: %s REPLAY_BAG [unittest args]" % script)
    REPLAY_BAG = sys.argv.pop(1)
    if devel_messages:
        devel = os.path.normpath(os.path.join(os.path.dirname(REPLAY_BAG), "..", ".."))
        sys.path.insert(0, os.path.join(devel, "lib", "python3", "dist-packages"))
    unittest.main(module="__main__")


def write_world_tf(bag, t0):
    """Writes /tf_static world -> base_link (identity) stamped 0.5 s before `t0` (s)."""
    import genpy
    import geometry_msgs.msg as g
    from tf2_msgs.msg import TFMessage
    tf = g.TransformStamped()
    tf.header.stamp = genpy.Time.from_sec(t0 - 0.5)
    tf.header.frame_id, tf.child_frame_id = "world", "base_link"
    tf.transform.rotation.w = 1.0
    bag.write("/tf_static", TFMessage(transforms=[tf]), tf.header.stamp)


def read_csv(path):
    """The rows of a CSV file with a header line, as dicts."""
    with open(path) as f:
        return list(csv.DictReader(f))


def run_replay(bag, out, configs, extra=(), timeout=120):
    """replay_bag on `bag` into `out` without the report, with each of `configs` as --config,
    then the arguments `extra`; the finished subprocess (stdout and stderr captured)."""
    cmd = [REPLAY_BAG, bag, "--out", out, "--no-report"]
    for c in configs:
        cmd += ["--config", c]
    cmd += list(extra)
    return subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, timeout=timeout)


def outputs(out):
    """(events, cycles): the rows of events.csv and cycles.csv in the replay's `out` folder."""
    return read_csv(os.path.join(out, "events.csv")), read_csv(os.path.join(out, "cycles.csv"))


def assert_same_ssm(test, cycle, reference, msg):
    """`cycle`'s speed and separation columns are `reference`'s: empty where it is empty, else
    within 1e-6; `msg(key)` names a failure."""
    for key in SSM_KEYS:
        if reference[key] == "":
            test.assertEqual(cycle[key], "", msg(key))
        else:
            test.assertAlmostEqual(float(cycle[key]), float(reference[key]), delta=1e-6,
                                   msg=msg(key))
