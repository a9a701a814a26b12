#!/usr/bin/env python3
"""The monitor from simulated sensors, beside a monitor on the true boxes (sensors_monitor.test:
the depth camera alone; sensors_scanner_only.test: the floor scanner alone; ~sensor names it).

Scene: the demo arm swinging at full speed (scene_simulator, joint_states through
robot_state_publisher); sensor_simulator renders the true boxes this test publishes on
/true_objects; cloud_tracker publishes its tracks on /perceived_objects; /perceived/
proximity_monitor hears those, /truth/proximity_monitor the true boxes (same configuration,
config/proximity_monitor.yaml).

1. The arm alone: 30 frames of perceived_objects without a track, and the perceived monitor's
   scale 1 throughout (the arm's own points never make a track, so never an event).
2. A person walks at the arm (0.8 m/s from (2.6, 0.8) towards its base, stopping 0.94 m from
   it), in the sensor's view and on its side of the arm. The perceived monitor's scale drops
   below 1 no later than the true-box monitor's plus the front end's delay D:
     D = one sensor period (1 / 15 s) + the front end's measured latency (the largest
         receipt time - stamp of perceived_objects during the run: rendering, transport,
         cloud_tracker) + one monitor period (1 / 30 s: the two monitors cycle unaligned).
3. The person leaves at T: every perceived_objects array stamped from T + 0.05 s on has no
   track on them ("free within one frame" of cloud_tracker: the simulator stamps a frame with
   the robot's newest tf stamp, never later than its rendering, and hears of the departure
   well within 0.05 s). What the monitor does after that is its track rules (docs/node.md).
4. The sensor silenced: the perceived monitor DEGRADED with a scale of 0, the sensor named in
   its reason (cloud_tracker's perception_status, and perceived_objects silent for
   source_timeout, capped at track_timeout); the true-box monitor is not.
"""
import os
import sys
import threading
import time
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import rospy  # noqa: E402
import rostest  # noqa: E402
from std_msgs.msg import Bool, Float64  # noqa: E402

from wp_node_testlib import SafetyStatus, TrackedBox, TrackedBoxArray  # noqa: E402
from workspace_proximity.msg import PerceptionStatus  # noqa: E402  (on the path: wp_node_testlib)

PERSON = (0.5, 0.5, 1.8)
RATE = 15.0          # Hz, sensor_simulator's default
MONITOR_RATE = 30.0  # Hz, config/proximity_monitor.yaml
START, STOP, SPEED = (2.6, 0.8), (0.9, 0.277), 0.8


class Scales(object):
    """speed_scale and safety_status of one monitor, with rospy receipt times."""

    def __init__(self, ns):
        self.lock = threading.Lock()
        self.scales = []   # (receipt s, scale)
        self.status = []   # (receipt s, SafetyStatus)
        rospy.Subscriber(ns + "/speed_scale", Float64, self.on_scale, queue_size=100)
        rospy.Subscriber(ns + "/safety_status", SafetyStatus, self.on_status, queue_size=100)

    def on_scale(self, msg):
        with self.lock:
            self.scales.append((rospy.Time.now().to_sec(), msg.data))

    def on_status(self, msg):
        with self.lock:
            self.status.append((rospy.Time.now().to_sec(), msg))

    def since(self, t):
        with self.lock:
            return [s for s in self.scales if s[0] >= t]

    def statuses(self, t):
        with self.lock:
            return [s for s in self.status if s[0] >= t]

    def wait(self, predicate, t, timeout):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            for r, v in self.since(t):
                if predicate(v):
                    return r
            time.sleep(0.02)
        return None


class Perceived(object):
    """perceived_objects: (receipt s, stamp s, [(x, y)]) per array."""

    def __init__(self):
        self.lock = threading.Lock()
        self.arrays = []
        rospy.Subscriber("/perceived_objects", TrackedBoxArray, self.on_array, queue_size=100)

    def on_array(self, msg):
        now = rospy.Time.now().to_sec()
        with self.lock:
            self.arrays.append((now, msg.header.stamp.to_sec(),
                                [(b.pose.position.x, b.pose.position.y) for b in msg.boxes]))

    def since(self, t):
        with self.lock:
            return [a for a in self.arrays if a[0] >= t]


class Health(object):
    """cloud_tracker's perception_status, with rospy receipt times."""

    def __init__(self):
        self.lock = threading.Lock()
        self.msgs = []
        rospy.Subscriber("/perception_status", PerceptionStatus, self.on_status, queue_size=100)

    def on_status(self, msg):
        with self.lock:
            self.msgs.append((rospy.Time.now().to_sec(), msg))

    def last(self):
        with self.lock:
            return self.msgs[-1][1] if self.msgs else None

    def wait(self, predicate, t, timeout):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            with self.lock:
                hit = next((m for r, m in self.msgs if r >= t and predicate(m)), None)
            if hit is not None:
                return hit
            time.sleep(0.05)
        return None


class Walker(object):
    """The true boxes on /true_objects at 30 Hz: one person walking START -> STOP at SPEED from
    `start` (rospy s), then standing; none before `start` or after `gone`."""

    def __init__(self):
        self.start, self.gone = None, None
        self.pub = rospy.Publisher("/true_objects", TrackedBoxArray, queue_size=5)
        self.timer = rospy.Timer(rospy.Duration(1.0 / 30.0), self.tick)

    def where(self, t):
        dx, dy = STOP[0] - START[0], STOP[1] - START[1]
        length = (dx * dx + dy * dy) ** 0.5
        s = min(max(0.0, (t - self.start) * SPEED), length)
        moving = 0.0 < (t - self.start) * SPEED < length
        return (START[0] + dx * s / length, START[1] + dy * s / length,
                SPEED * dx / length if moving else 0.0, SPEED * dy / length if moving else 0.0)

    def tick(self, _):
        now = rospy.Time.now()
        msg = TrackedBoxArray()
        msg.header.stamp, msg.header.frame_id = now, "world"
        t = now.to_sec()
        if self.start is not None and t >= self.start and (self.gone is None or t < self.gone):
            x, y, vx, vy = self.where(t)
            b = TrackedBox()
            b.id, b.label = "walker", "person"
            b.pose.position.x, b.pose.position.y, b.pose.position.z = x, y, 0.5 * PERSON[2]
            b.pose.orientation.w = 1.0
            b.dimensions.x, b.dimensions.y, b.dimensions.z = PERSON
            b.twist.linear.x, b.twist.linear.y = vx, vy
            msg.boxes.append(b)
        try:
            self.pub.publish(msg)
        except rospy.ROSException:
            pass  # shutting down


def near(xy, person_xy):
    return abs(xy[0] - person_xy[0]) <= 0.6 and abs(xy[1] - person_xy[1]) <= 0.6


class SensorsMonitor(unittest.TestCase):
    def test_scene(self):
        sensor = rospy.get_param("~sensor", "camera")
        pause = rospy.Publisher("/sensor_simulator/pause_" + sensor, Bool, queue_size=1, latch=True)
        perceived, truth = Scales("/perceived"), Scales("/truth")
        tracks = Perceived()
        health = Health()
        walker = Walker()

        # Both monitors up and at full speed (the perceived one once cloud_tracker publishes).
        t0 = rospy.Time.now().to_sec()
        for name, m in (("perceived", perceived), ("truth", truth)):
            self.assertIsNotNone(m.wait(lambda v: v >= 1.0, t0, 40.0),
                                 "the %s monitor never reached scale 1: last %s, status %s"
                                 % (name, m.since(t0)[-1:], [s.reason for _, s in m.statuses(t0)[-1:]]))

        # 1. The arm alone.
        t1 = rospy.Time.now().to_sec()
        deadline = time.monotonic() + 30.0
        while len(tracks.since(t1)) < 30 and time.monotonic() < deadline:
            time.sleep(0.05)
        arrays = tracks.since(t1)
        self.assertGreaterEqual(len(arrays), 30)
        with_tracks = [a for a in arrays if a[2]]
        self.assertFalse(with_tracks, "the arm alone made tracks in %d of %d arrays, e.g. %s"
                         % (len(with_tracks), len(arrays), with_tracks[:1]))
        low = [s for s in perceived.since(t1) if s[0] <= arrays[-1][0] and s[1] < 1.0]
        self.assertFalse(low, "the perceived monitor's scale fell below 1 with the arm alone: %s" % low[:3])

        # 2. A person walks at the arm.
        start = rospy.Time.now().to_sec() + 0.2
        walker.start = start
        t_truth = truth.wait(lambda v: v < 1.0, start, 15.0)
        t_perc = perceived.wait(lambda v: v < 1.0, start, 15.0)
        self.assertIsNotNone(t_truth, "the true-box monitor never slowed the arm down")
        self.assertIsNotNone(t_perc, "the perceived monitor never slowed the arm down")
        lag = max(r - s for r, s, _ in tracks.since(t1))
        delay = 1.0 / RATE + lag + 1.0 / MONITOR_RATE
        self.assertLessEqual(t_perc, t_truth + delay,
                             "perceived first below 1 at %.3f s, true boxes at %.3f s: later than D = "
                             "%.3f s (front end latency %.3f s)" % (t_perc - start, t_truth - start, delay, lag))
        rospy.loginfo("sensors_monitor (%s): scale below 1 at %.3f s (true boxes) and %.3f s (perceived); "
                      "D = %.3f s (front end latency %.3f s)", sensor, t_truth - start, t_perc - start, delay, lag)
        while rospy.Time.now().to_sec() < start + 3.0:
            time.sleep(0.05)
        seen = [a for a in tracks.since(start + 2.5) if any(near(xy, STOP) for xy in a[2])]
        self.assertTrue(seen, "no track on the standing person at %s" % (STOP,))

        # 3. The person leaves.
        gone = rospy.Time.now().to_sec()
        walker.gone = gone
        deadline = time.monotonic() + 20.0
        while time.monotonic() < deadline and len([a for a in tracks.since(gone) if a[1] >= gone + 0.05]) < 10:
            time.sleep(0.05)
        after = [a for a in tracks.since(gone) if a[1] >= gone + 0.05]
        self.assertGreaterEqual(len(after), 10)
        late = [a[1] - gone for a in after if any(near(xy, STOP) for xy in a[2])]
        self.assertFalse(late, "arrays stamped %s s after the person left still have a track on them" % late)

        # 4. The sensor silenced.
        t4 = rospy.Time.now().to_sec()
        pause.publish(Bool(data=True))
        self.assertIsNotNone(perceived.wait(lambda v: v == 0.0, t4, 5.0),
                             "a silent %s did not stop the arm: %s" % (sensor, perceived.since(t4)[-1:]))
        time.sleep(0.5)
        st = perceived.statuses(t4)[-1][1]
        self.assertEqual(st.status, SafetyStatus.DEGRADED, st.reason)
        self.assertEqual(st.speed_scale, 0.0)
        # perceived_objects falls silent first (source_timeout capped at track_timeout, 0.5 s:
        # the reason the monitor's one line gives); the front end's perception_status, which the
        # monitor also reads, names the sensor after cloud_tracker's source_timeout (1 s).
        topic = "sim_camera_points" if sensor == "camera" else "sim_scan"
        named = health.wait(lambda m: m.degraded and any(topic in r for r in m.reasons), t4, 5.0)
        self.assertIsNotNone(named, "perception_status never named the silent %s: %s" % (sensor, health.last()))
        self.assertEqual(perceived.statuses(t4)[-1][1].speed_scale, 0.0)
        self.assertTrue(truth.since(t4) and truth.since(t4)[-1][1] > 0.0,
                        "the true-box monitor should not stop for the sensor")
        pause.publish(Bool(data=False))


if __name__ == "__main__":
    rospy.init_node("test_sensors_monitor")
    rostest.rosrun("workspace_proximity", "sensors_monitor", SensorsMonitor)
