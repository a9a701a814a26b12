#!/usr/bin/env python3
"""The Twist filter and the stop actions of speed and separation monitoring.

The test is the simulator: it publishes /clock in 10 ms steps at about real time (the node
runs on /use_sim_time at 20 Hz), the tracked person every 50 ms, and a velocity command
(linear (1.0, -0.5, 0), angular z 0.8) on cmd_vel_in every 20 ms. The robot is a static 1 m
cube ("post"). ~ssm/hold_time 0.2 s, max_increase_rate 5 / s. Simulated seconds from S:
   0 .. 2    nobody near (the person 5 m away): the scale rises from 0 to 1
   2 .. 3    the person stands 0.1 m from the post: stop (scale 0)
   3 .. 4.5  away again: the scale rises to 1
 4.5 .. 5.5  at 0.1 m again: the second stop
 5.5 .. 7    away: the scale rises to 1
then the clock jumps back 10 s and stands still there for 0.6 s of wall time (the node cannot
cycle: the scale is 10 s old), then runs on for 1.5 s.

Checks:
- cmd_vel_out: every command is the input times one speed_scale of the cycles published in
  the 0.15 s before it (each component), and the input itself once the scale has been 1 for a
  while; while the clock stands still after the jump back, every command is zero (stale);
- stop actions: exactly one empty trajectory_msgs/JointTrajectory on /arm_controller/command
  and one "stop" on /trajectory_execution_event per transition of the scale into 0 (at
  start-up, at each of the two stops, and after the reset of the jump back, when nothing is
  known again): 4 of each, each within 0.1 s of the cycle that stopped, nothing more;
- speed_scale (Float64) carries safety_status.speed_scale and speed_override (Int64)
  round(100 x speed_scale), cycle by cycle.
"""
import math
import os
import sys
import threading
import time
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402
import tf2_ros  # noqa: E402
from geometry_msgs.msg import TransformStamped, Twist  # noqa: E402
from rosgraph_msgs.msg import Clock  # noqa: E402
from std_msgs.msg import String  # noqa: E402
from trajectory_msgs.msg import JointTrajectory  # noqa: E402

from wp_node_testlib import (SsmCollector, Track, TrackedBoxArray, WallPacer,  # noqa: E402
                             aligned)

STEP_NS = 10 * 1000 * 1000
START_NS = 100 * 10**9
FAR = (5.0, 0.0, 0.9)
NEAR = (0.5 + 0.1 + 0.25, 0.0, 0.9)   # 0.1 m from the post's face
# (from, to, where) in simulated seconds from the start
PHASES = [(0.0, 2.0, FAR), (2.0, 3.0, NEAR), (3.0, 4.5, FAR), (4.5, 5.5, NEAR), (5.5, 7.0, FAR)]
JUMP_BACK_NS = 10 * 10**9
COMMAND = (1.0, -0.5, 0.8)   # linear x, linear y, angular z


def to_time(ns):
    return rospy.Time(ns // 10**9, ns % 10**9)


class Recorder(object):
    """Messages with the simulated clock the test had published when they arrived."""

    def __init__(self, sim):
        self.sim = sim
        self.lock = threading.Lock()
        self.twists, self.trajectories, self.events = [], [], []
        self.subs = [rospy.Subscriber("cmd_vel_out", Twist, self._on(self.twists), queue_size=500),
                     rospy.Subscriber("/arm_controller/command", JointTrajectory,
                                      self._on(self.trajectories), queue_size=50),
                     rospy.Subscriber("/trajectory_execution_event", String,
                                      self._on(self.events), queue_size=50)]

    def _on(self, into):
        def callback(msg):
            with self.lock:
                into.append((self.sim.clock_ns, self.sim.frozen, msg))
        return callback


class Simulator(object):
    def __init__(self):
        self.clock_pub = rospy.Publisher("/clock", Clock, queue_size=20)
        self.box_pub = rospy.Publisher("tracked_objects", TrackedBoxArray, queue_size=20)
        self.cmd_pub = rospy.Publisher("cmd_vel_in", Twist, queue_size=20)
        self.static = tf2_ros.StaticTransformBroadcaster()
        self.clock_ns = 0
        self.frozen = False

    def publish_static(self):
        t = TransformStamped()
        t.header.frame_id = "world"
        t.child_frame_id = "base_link"
        t.transform.rotation.w = 1.0
        self.static.sendTransform(t)

    def step(self, ns, k, where):
        self.clock_ns = ns
        self.clock_pub.publish(Clock(clock=to_time(ns)))
        if where is not None and k % 5 == 0:
            stamp = to_time(ns) - rospy.Duration(0.02)
            msg = TrackedBoxArray()
            msg.header.stamp = stamp
            msg.header.frame_id = "world"
            msg.boxes = [Track("p1", "person", where, (0.5, 0.5, 1.8), t0=stamp).to_msg(stamp)]
            self.box_pub.publish(msg)
        if k % 2 == 0:
            cmd = Twist()
            cmd.linear.x, cmd.linear.y, cmd.angular.z = COMMAND
            self.cmd_pub.publish(cmd)

    def run(self, start_ns, steps, where_at, k0=0):
        pacer = WallPacer(STEP_NS * 1e-9)
        for k in range(steps):
            if rospy.is_shutdown():
                return
            ns = start_ns + k * STEP_NS
            self.step(ns, k0 + k, where_at(ns))
            pacer.wait()


def where_at(ns):
    s = (ns - START_NS) * 1e-9
    for lo, hi, where in PHASES:
        if lo <= s < hi:
            return where
    return FAR


class SsmActionsTest(unittest.TestCase):
    def test_twist_filter_and_stop_actions(self):
        sim = Simulator()
        ssm = SsmCollector()
        rec = Recorder(sim)
        deadline = time.monotonic() + 15.0
        while time.monotonic() < deadline and not (
                ssm.connected() and all(s.get_num_connections() >= 1 for s in rec.subs) and
                sim.clock_pub.get_num_connections() >= 1 and
                sim.box_pub.get_num_connections() >= 1 and
                sim.cmd_pub.get_num_connections() >= 1):
            time.sleep(0.05)
        sim.publish_static()
        time.sleep(1.0)  # the node's tf listener; the node has not cycled yet (no clock)
        self.assertEqual(ssm.statuses(), [], "the node cycled before the clock started")

        run_steps = 700
        sim.run(START_NS, run_steps, where_at)
        end_ns = START_NS + run_steps * STEP_NS
        # The clock jumps back and stands still: the node cannot cycle, its scale is stale.
        back_ns = end_ns - JUMP_BACK_NS
        sim.frozen = True
        freeze_wall = time.monotonic()
        while time.monotonic() < freeze_wall + 0.6:
            sim.step(back_ns, 0, FAR)  # the same instant again: time stands still
            time.sleep(0.02)
        sim.frozen = False
        sim.run(back_ns + STEP_NS, 150, lambda ns: FAR, k0=1)
        time.sleep(0.3)

        statuses = ssm.statuses()
        with rec.lock:
            twists, trajectories, events = list(rec.twists), list(rec.trajectories), list(rec.events)

        # Transitions of the scale into 0, in the order published.
        stops = []
        prev = None
        for m in statuses:
            if m.speed_scale == 0.0 and (prev is None or prev.speed_scale > 0.0):
                stops.append(m.header.stamp)
            prev = m
        self.assertEqual(len(stops), 4, "transitions into a stop: %r" % [s.to_sec() for s in stops])
        self.assertEqual(len(trajectories), 4, "JointTrajectory messages: %d" % len(trajectories))
        self.assertEqual(len(events), 4, "stop events: %d" % len(events))
        for (clock_ns, _, traj), (_, _, word), stop in zip(trajectories, events, stops):
            self.assertEqual(list(traj.joint_names), [])
            self.assertEqual(list(traj.points), [])
            self.assertEqual(word.data, "stop")
            self.assertLess(abs(clock_ns * 1e-9 - stop.to_sec()), 0.1,
                            "stop action at %.3f for the stop at %.3f" % (clock_ns * 1e-9, stop.to_sec()))

        # The Twist filter.
        by_stamp = [(m.header.stamp.to_nsec(), m.speed_scale) for m in statuses]
        scaled = full = stale = 0
        for clock_ns, frozen, out in twists:
            got = (out.linear.x, out.linear.y, out.angular.z)
            self.assertEqual((out.linear.z, out.angular.x, out.angular.y), (0.0, 0.0, 0.0))
            ratio = got[0] / COMMAND[0]
            for g, c in zip(got, COMMAND):
                self.assertAlmostEqual(g, c * ratio, delta=1e-12, msg="not one scale for all: %r" % (got,))
            if frozen:
                continue  # checked below
            recent = [s for t, s in by_stamp if clock_ns - 150 * 10**6 <= t <= clock_ns + STEP_NS]
            if clock_ns > back_ns + STEP_NS and clock_ns < back_ns + 3 * 10**8:
                recent.append(0.0)  # right after the jump: stale until the first new cycle
            self.assertTrue(any(abs(ratio - s) < 1e-12 for s in recent),
                            "clock %.3f: command scaled by %.6f, recent scales %r" % (
                                clock_ns * 1e-9, ratio, recent))
            scaled += 0.0 < ratio < 1.0
            if clock_ns < end_ns and where_at(clock_ns) is FAR and recent and min(recent) == 1.0:
                self.assertEqual(got, COMMAND)
                full += 1
        frozen_twists = [out for clock_ns, frozen, out in twists if frozen]
        self.assertGreater(len(frozen_twists), 15, "too few commands while the clock stood still")
        # The first one or two may have been handled before the node saw the jump.
        for out in frozen_twists[3:]:
            self.assertEqual((out.linear.x, out.linear.y, out.angular.z), (0.0, 0.0, 0.0),
                             "a command passed while the scale was stale")
            stale += 1
        self.assertGreater(scaled, 5, "too few commands checked at a partial scale")
        self.assertGreater(full, 50, "too few commands checked at full speed")
        self.assertGreater(stale, 10)

        # The Float64 and Int64 outputs, cycle by cycle (moved here from ssm_approach, whose
        # verdicts are checked by test_scene_ssm without ROS).
        status, scale, override = ssm.sequences()
        self.assertIsNotNone(aligned([m.speed_scale for m in status], scale, lambda a, b: a == b),
                             "speed_scale does not carry safety_status.speed_scale")
        # round() half away from zero (the scale is never negative)
        self.assertIsNotNone(aligned(scale, override, lambda s, o: o == math.floor(100.0 * s + 0.5)),
                             "speed_override is not round(100 x speed_scale)")
        self.assertIn(0, override)
        self.assertIn(100, override)
        self.assertTrue(any(0 < o < 100 for o in override))


if __name__ == "__main__":
    rospy.init_node("test_ssm_actions")
    rostest.rosrun("workspace_proximity", "test_ssm_actions", SsmActionsTest)
