#!/usr/bin/env python3
"""trajectory_relay through its topics, with a fake joint_trajectory_controller.

The plan: joints a, b, c through four waypoints in 3 s, with velocities (a cubic per segment,
computed here independently of the relay). The test publishes speed_scale at 30 Hz and records
the fake arm's joint_states.

  * Pauses: scale 1, 0, 0.5, 0, 1: the arm ends at the final point, stands still while the
    scale is 0 (from one hold time plus a relay period and a scale period after the drop), and
    every joint state lies within joint_path_tolerance (0.01, the monitor's default; joint
    space, rad) of the planned path.
  * Silence and death: a new plan at scale 1; speed_scale falls silent: the arm stands still
    from ~scale_timeout + hold + a period on, and goes on when the scale returns; then the relay
    is killed: the arm stands still from ~chunk + T_s (the monitor's ~ssm/stopping_time
    default, 0.3 s) after the kill on, short of the plan's end.
  * Bad parameters: the relay binary, started once per bad setting, exits with an error naming
    the parameter (the running relay above is the positive control).
"""
import bisect
import subprocess
import sys
import threading
import time
import unittest

import rosnode
import rospy
import rostest
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

JOINTS = ['a', 'b', 'c']
TIMES = [0.0, 1.0, 2.0, 3.0]
WAYPOINTS = [[0.0, 0.0, 0.0], [0.6, 0.3, -0.2], [1.0, -0.2, 0.1], [1.2, 0.2, 0.4]]
PATH_TOLERANCE = 0.01     # ~joint_path_tolerance's default
CHUNK = 0.3               # the relay's ~chunk
PERIOD = 0.05             # the relay's period (20 Hz); also its hold time
SCALE_TIMEOUT = 0.1       # the relay's ~scale_timeout
STOPPING_TIME = 0.3       # T_s, the monitor's ~ssm/stopping_time default
STILL = 1e-6              # rad: "stands still"


def velocities():
    """Zero at the ends, central differences inside."""
    out = [[0.0] * 3]
    for k in range(1, len(TIMES) - 1):
        out.append([(WAYPOINTS[k + 1][j] - WAYPOINTS[k - 1][j]) / (TIMES[k + 1] - TIMES[k - 1])
                    for j in range(3)])
    out.append([0.0] * 3)
    return out


VELOCITIES = velocities()


def plan_at(s):
    """The planned positions at planned time s (cubic Hermite per segment)."""
    s = min(max(s, TIMES[0]), TIMES[-1])
    i = min(bisect.bisect_right(TIMES, s) - 1, len(TIMES) - 2)
    T = TIMES[i + 1] - TIMES[i]
    u = (s - TIMES[i]) / T
    h00, h10 = 2 * u ** 3 - 3 * u ** 2 + 1, u ** 3 - 2 * u ** 2 + u
    h01, h11 = -2 * u ** 3 + 3 * u ** 2, u ** 3 - u ** 2
    return [h00 * WAYPOINTS[i][j] + h10 * T * VELOCITIES[i][j] + h01 * WAYPOINTS[i + 1][j] +
            h11 * T * VELOCITIES[i + 1][j] for j in range(3)]


PATH = [plan_at(TIMES[-1] * k / 6000.0) for k in range(6001)]


def distance_to_path(q):
    return min(sum((q[j] - p[j]) ** 2 for j in range(3)) for p in PATH) ** 0.5


def plan_message(scale_time=1.0, backwards=False):
    """The plan, `scale_time` times slower; backwards: from the last waypoint to the first."""
    msg = JointTrajectory()
    msg.joint_names = JOINTS
    points = list(zip(WAYPOINTS, VELOCITIES))
    sign = 1.0
    if backwards:
        points.reverse()
        sign = -1.0
    for t, (q, v) in zip(TIMES, points):
        msg.points.append(JointTrajectoryPoint(
            positions=q, velocities=[sign * x / scale_time for x in v],
            time_from_start=rospy.Duration(t * scale_time)))
    return msg


class ScalePublisher(object):
    """speed_scale at 30 Hz: `value`, or nothing while `silent`."""

    def __init__(self):
        self.value, self.silent = 0.0, False
        self.pub = rospy.Publisher('speed_scale', Float64, queue_size=1, tcp_nodelay=True)
        self.thread = threading.Thread(target=self.run, daemon=True)
        self.thread.start()

    def run(self):
        rate = rospy.Rate(30.0)
        while not rospy.is_shutdown():
            if not self.silent:
                self.pub.publish(Float64(self.value))
            rate.sleep()


class Arm(object):
    def __init__(self):
        self.lock = threading.Lock()
        self.states = []  # (receipt time s, [positions])
        self.sub = rospy.Subscriber('joint_states', JointState, self.on_state, queue_size=100)

    def on_state(self, msg):
        with self.lock:
            self.states.append((rospy.Time.now().to_sec(), list(msg.position)))

    def between(self, t0, t1):
        with self.lock:
            return [q for t, q in self.states if t0 <= t <= t1]

    def latest(self):
        with self.lock:
            return self.states[-1][1] if self.states else None


def spread(states):
    return max(max(q[j] for q in states) - min(q[j] for q in states) for j in range(3))


# Bad settings: (private parameter, value, word the error must hold).
BAD_PARAMS = [('rate', '0.5', '~rate'), ('rate', 'fast', '~rate'), ('chunk', '0.01', '~chunk'),
              ('scale_timeout', '0', '~scale_timeout'), ('max_points', '1', '~max_points'),
              ('command_topic', 'planned_trajectory', '~command_topic'),
              ('trajectory_topic', "'bad name'", '~trajectory_topic'),
              ('max_joints', '1000', '~max_points x ~max_joints')]


class TestTrajectoryRelay(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_trajectory_relay')
        cls.scale = ScalePublisher()
        cls.arm = Arm()
        cls.plan_pub = rospy.Publisher('planned_trajectory', JointTrajectory, queue_size=1,
                                       latch=True)
        deadline = time.time() + 20.0
        while time.time() < deadline and (cls.arm.latest() is None or
                                          cls.plan_pub.get_num_connections() == 0):
            time.sleep(0.1)
        assert cls.arm.latest() is not None, 'no joint_states from the fake controller'
        assert cls.plan_pub.get_num_connections() > 0, 'the relay does not subscribe the plan'

    def now(self):
        return rospy.Time.now().to_sec()

    def test_1_pauses_end_at_the_final_point_on_the_path(self):
        self.scale.value = 1.0
        time.sleep(0.3)
        start = self.now()
        self.plan_pub.publish(plan_message())
        schedule = [(0.8, 1.0), (1.0, 0.0), (1.0, 0.5), (0.7, 0.0), (4.0, 1.0)]
        zero_windows = []
        for duration, value in schedule:
            t0 = self.now()
            self.scale.value = value
            time.sleep(duration)
            if value == 0.0:
                zero_windows.append((t0, self.now()))
        end = self.now()
        final = self.arm.latest()
        for j in range(3):
            self.assertAlmostEqual(final[j], WAYPOINTS[-1][j], delta=1e-3,
                                   msg='joint %s ends at %.4f, the plan at %.4f'
                                   % (JOINTS[j], final[j], WAYPOINTS[-1][j]))
        for t0, t1 in zero_windows:
            still = self.arm.between(t0 + PERIOD + PERIOD + 1.0 / 30 + 0.05, t1)
            self.assertGreater(len(still), 20)
            self.assertLess(spread(still), STILL, 'the arm moved while the scale was 0')
            # ... and it had stopped part-way, not at an end.
            self.assertGreater(distance_to_point(still[0], WAYPOINTS[-1]), 0.05)
        states = self.arm.between(start, end)
        self.assertGreater(len(states), 300)
        worst = max(distance_to_path(q) for q in states[::2])
        rospy.loginfo('test_trajectory_relay: largest distance from the planned path %.5f', worst)
        self.assertLessEqual(worst, PATH_TOLERANCE)

    def test_2_silence_holds_and_a_killed_relay_stops_the_arm(self):
        self.scale.value = 1.0
        self.scale.silent = False
        # The plan backwards (from where the last test ended) and 4 times slower (12 s).
        self.plan_pub.publish(plan_message(scale_time=4.0, backwards=True))
        time.sleep(1.0)
        moving = self.arm.between(self.now() - 0.3, self.now())
        self.assertGreater(spread(moving), 0.01, 'the arm does not move at scale 1')
        t_silent = self.now()
        self.scale.silent = True
        time.sleep(1.0)
        still = self.arm.between(t_silent + SCALE_TIMEOUT + 2 * PERIOD + 0.05, self.now())
        self.assertGreater(len(still), 20)
        self.assertLess(spread(still), STILL, 'the arm moved with speed_scale silent')
        self.scale.silent = False
        time.sleep(1.0)
        moving = self.arm.between(self.now() - 0.3, self.now())
        self.assertGreater(spread(moving), 0.01, 'the arm did not resume')
        t_kill = self.now()
        _, failed = rosnode.kill_nodes(['/trajectory_relay'])
        self.assertFalse(failed)
        time.sleep(2.0)
        still = self.arm.between(t_kill + CHUNK + STOPPING_TIME, self.now())
        self.assertGreater(len(still), 50)
        self.assertLess(spread(still), STILL, 'the arm went on after the relay was killed')
        self.assertGreater(distance_to_point(still[-1], WAYPOINTS[0]), 0.05)

    def test_3_bad_parameters_stop_the_relay_naming_them(self):
        from roslib.packages import find_node
        binary = find_node('workspace_proximity', 'trajectory_relay')[0]
        failures = []
        for k, (name, value, word) in enumerate(BAD_PARAMS):
            proc = subprocess.Popen([binary, '__name:=bad_relay_%d' % k, '_%s:=%s' % (name, value)],
                                    stdout=subprocess.PIPE, stderr=subprocess.PIPE)
            try:
                out, err = proc.communicate(timeout=8)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.communicate()
                failures.append('%s=%s: still running' % (name, value))
                continue
            text = (out + err).decode(errors='replace')
            if proc.returncode <= 0 or word not in text or 'invalid parameter' not in text:
                failures.append('%s=%s: status %d, %r' % (name, value, proc.returncode, text[-300:]))
        self.assertEqual(failures, [], '\n'.join(failures))


def distance_to_point(q, p):
    return sum((q[j] - p[j]) ** 2 for j in range(3)) ** 0.5


if __name__ == '__main__':
    rostest.rosrun('workspace_proximity', 'trajectory_relay_pause_resume', TestTrajectoryRelay, sys.argv)
