#!/usr/bin/env python3
"""cloud_tracker's invalid configuration: for each bad setting, start the cloud_tracker binary
under its own node name with that private parameter and check it exits on its own (within 8 s)
with a non-zero status (not a signal) and stderr naming the parameter. Positive control: the
same start-up with valid parameters keeps running until interrupted.
"""
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402

from wp_node_testlib import (  # noqa: E402
    find_node_binary, run_for, start_node_binary, startup_refusals)

TOPICS = {"cloud_topics": ["/cam/points"], "scan_topics": ["/scan"]}

# (case name, params set on the server, words one of which the error must contain)
CASES = [
    ("no_topics", {"cloud_topics": [], "scan_topics": []}, ["cloud_topics"]),
    ("topics_not_a_list", {"cloud_topics": "/cam/points"}, ["cloud_topics"]),
    ("voxel_size_zero", dict(TOPICS, voxel_size=0.0), ["voxel_size"]),
    ("volume_five_numbers", dict(TOPICS, volume=[0, 0, 0, 1, 1]), ["volume"]),
    ("volume_inverted", dict(TOPICS, volume=[1, 0, 0, 0, 1, 1]), ["volume"]),
    ("volume_too_many_voxels", dict(TOPICS, volume=[-100, -100, -100, 100, 100, 100]),
     ["max_cells"]),
    ("scan_band_inverted", dict(TOPICS, scan_band=[1.0, 0.0]), ["scan_band"]),
    ("source_timeout_zero", dict(TOPICS, source_timeout=0.0), ["source_timeout"]),
    ("self_max_speed_negative", dict(TOPICS, self_max_speed=-1.0), ["self_max_speed"]),
    ("unseen_limit_above_one", dict(TOPICS, unseen_limit=2.0), ["unseen_limit"]),
    ("sensor_fov_unknown_topic",
     dict(TOPICS, sensor_fov={"/other": {"azimuth": [-1, 1], "elevation": [-1, 1], "range": [0, 5]}}),
     ["sensor_fov//other"]),
    ("sensor_fov_without_range",
     dict(TOPICS, sensor_fov={"/cam/points": {"azimuth": [-1, 1], "elevation": [-1, 1]}}),
     ["sensor_fov//cam/points", "range"]),
    ("fixed_frame_leading_slash", dict(TOPICS, fixed_frame="/map"), ["fixed_frame"]),
    ("robot_body_size_negative",
     dict(TOPICS, robot_bodies=[{"name": "g", "frame": "tool0", "size": [0.1, -0.1, 0.1]}]),
     ["robot_bodies"]),
]


class CloudTrackerInvalidParamsTest(unittest.TestCase):
    def setUp(self):
        self.binary = find_node_binary("cloud_tracker")
        self.assertTrue(self.binary, "cloud_tracker binary not found")

    def test_valid_parameters_keep_running(self):
        proc = start_node_binary(self.binary, "valid_control", [], TOPICS)
        running, text = run_for(proc, 3.0)
        self.assertTrue(running, "exited with valid parameters (status %s): %s" % (
            proc.returncode, text[-2000:]))

    def test_invalid_parameters_exit(self):
        started = [(name, words, start_node_binary(self.binary, "bad_" + name, [], params))
                   for name, params, words in CASES]
        failures = startup_refusals(started)
        self.assertEqual(failures, [], "\n".join(failures))


if __name__ == "__main__":
    rospy.init_node("test_cloud_tracker_invalid_params")
    rostest.rosrun("workspace_proximity", "test_cloud_tracker_invalid_params", CloudTrackerInvalidParamsTest)
