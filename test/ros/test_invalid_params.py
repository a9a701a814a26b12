#!/usr/bin/env python3
"""Invalid configuration: for each bad setting, start the proximity_monitor binary under its
own node name with that private parameter and check it exits on its own (within 8 s) with a
non-zero status (not a signal) and stderr naming the parameter. Positive control: the same
start-up with valid parameters keeps running until interrupted.
"""
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402

from wp_node_testlib import (  # noqa: E402
    find_node_binary, run_for, start_node_binary, startup_refusals)

LABEL_OK = {"margin": 0.1, "warning_time": 1.0, "critical_time": 0.4,
            "warning_distance": 0.5, "critical_distance": 0.2}

# (case name, command-line private params, params set on the server, words one of which
#  the error must contain)
CASES = [
    ("rate_negative", ["_rate:=-1.0"], {}, ["rate"]),
    ("rate_too_high", ["_rate:=5000.0"], {}, ["rate"]),
    ("rate_not_a_number", ["_rate:=fast"], {}, ["rate"]),
    ("horizon_negative", ["_horizon:=-0.5"], {}, ["horizon"]),
    ("horizon_too_long", ["_horizon:=100.0"], {}, ["horizon"]),
    ("track_timeout_negative", ["_track_timeout:=-1.0"], {}, ["track_timeout"]),
    ("velocity_window_too_small", ["_velocity_window:=0.001"], {}, ["velocity_window"]),
    ("robot_margin_negative", ["_robot_margin:=-0.1"], {}, ["robot_margin"]),
    ("marker_lifetime_negative", ["_marker_lifetime:=-1.0"], {}, ["marker_lifetime"]),
    ("marker_rate_zero", ["_marker_rate:=0.0"], {}, ["marker_rate"]),
    ("label_margin_negative", [], {"labels": {"default": dict(LABEL_OK, margin=-0.1)}},
     ["labels", "margin"]),
    ("robot_body_size_negative", [],
     {"robot_bodies": [{"name": "g", "frame": "tool0", "size": [0.1, -0.1, 0.1]}]},
     ["robot_bodies", "size"]),
    ("ignore_pairs_bad_selector", [], {"ignore_pairs": [["colour:red", "*"]]},
     ["ignore_pairs"]),
    ("stale_after_over_track_timeout", ["_track_timeout:=0.5", "_stale_after:=0.6"], {},
     ["stale_after"]),
    ("source_timeout_zero", ["_source_timeout:=0.0"], {}, ["source_timeout"]),
    ("max_future_negative", ["_max_future:=-1.0"], {}, ["max_future"]),
    ("max_tracks_zero", ["_max_tracks:=0"], {}, ["max_tracks"]),
    ("safety_handoff_negative", ["_safety_handoff:=-0.0001"], {}, ["safety_handoff"]),
    ("safety_handoff_too_long", ["_safety_handoff:=0.5"], {}, ["safety_handoff"]),
    # tf2 refuses frame ids starting with '/' in every lookup: refused at start, named.
    ("fixed_frame_leading_slash", ["_fixed_frame:=/map"], {}, ["fixed_frame"]),
    ("robot_body_frame_leading_slash", [],
     {"robot_bodies": [{"name": "g", "frame": "/tool0", "size": [0.1, 0.1, 0.1]}]},
     ["robot_bodies[0]/frame"]),
    # The audit trail's file must be writable from the start (docs/node.md, "Audit trail").
    ("audit_log_cannot_be_opened", ["_audit_log:=/nonexistent_wp_dir/audit.csv"], {},
     ["~audit_log = '/nonexistent_wp_dir/audit.csv'"]),
]


class InvalidParamsTest(unittest.TestCase):
    def setUp(self):
        self.binary = find_node_binary()
        self.assertTrue(self.binary, "proximity_monitor binary not found")

    def test_valid_parameters_keep_running(self):
        proc = start_node_binary(self.binary, "valid_control", [], {})
        running, text = run_for(proc, 3.0)
        self.assertTrue(running, "the node exited with valid parameters (status %s): %s" % (
            proc.returncode, text[-2000:]))

    def test_unknown_keys_are_named_and_the_node_keeps_running(self):
        proc = start_node_binary(self.binary, "misspelled", ["_horizen:=3.0"],
                                 {"trak_timeout": 1.0})
        running, text = run_for(proc, 3.0)
        self.assertTrue(running, "an unknown key stopped the node: " + text[-2000:])
        self.assertIn("~horizen: unknown parameter, not used (did you mean ~horizon?)", text)
        self.assertIn("~trak_timeout: unknown parameter, not used (did you mean ~track_timeout?)",
                      text)

    def test_invalid_parameters_exit(self):
        started = [(name, words, start_node_binary(self.binary, "bad_" + name, args, params))
                   for name, args, params, words in CASES]
        failures = startup_refusals(started)
        self.assertEqual(failures, [], "\n".join(failures))


if __name__ == "__main__":
    rospy.init_node("test_invalid_params")
    rostest.rosrun("workspace_proximity", "test_invalid_params", InvalidParamsTest)
