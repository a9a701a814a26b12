#!/usr/bin/env python3
"""A stand-in for ros_control's joint_trajectory_controller (not in Debian), for the tests and
the demo: executes trajectory_msgs/JointTrajectory commands as that controller does, and
publishes the joints it drives on joint_states, as a robot driver does.

Command semantics (those of joint_trajectory_controller):
  * A new trajectory replaces the one being executed from its start, header.stamp (0 = now):
    until then the old one goes on; from then, the old one's state (position, velocity,
    acceleration) at that instant is joined to the new one's first point still in the future.
    Points already in the past are dropped; a trajectory with none left is ignored.
  * Between points: linear with positions only, cubic with velocities, quintic with
    velocities and accelerations.
  * At the end it holds the last point (velocity 0).
  * An empty trajectory (no points) stops: it holds the current position.
  * Joints the command does not name hold where they are.

Topics: ~command (in, trajectory_msgs/JointTrajectory), joint_states (out,
sensor_msgs/JointState, with positions and velocities).

Parameters (private):
  ~joints ([])             names of the joints driven (required)
  ~initial_positions ([])  their starting positions (default all 0)
  ~rate (100.0)            Hz of joint_states
"""

import bisect
import sys
import threading

import rospy
from sensor_msgs.msg import JointState
from trajectory_msgs.msg import JointTrajectory


def hermite(mode, t0, t1, a, b, t):
    """One joint on a segment from state a = (q, v, acc) at t0 to b at t1, at time t:
    (position, velocity). mode: 'linear', 'cubic' or 'quintic'."""
    T = t1 - t0
    x = min(max(t - t0, 0.0), T)
    h = b[0] - a[0]
    if mode == 'linear':
        return a[0] + h * x / T, h / T
    v0, v1 = a[1], b[1]
    if mode == 'cubic':
        c2 = (3 * h - (2 * v0 + v1) * T) / T ** 2
        c3 = (-2 * h + (v0 + v1) * T) / T ** 3
        return (a[0] + v0 * x + c2 * x ** 2 + c3 * x ** 3,
                v0 + 2 * c2 * x + 3 * c3 * x ** 2)
    a0, a1 = a[2], b[2]
    c3 = (20 * h - (8 * v1 + 12 * v0) * T - (3 * a0 - a1) * T ** 2) / (2 * T ** 3)
    c4 = (-30 * h + (14 * v1 + 16 * v0) * T + (3 * a0 - 2 * a1) * T ** 2) / (2 * T ** 4)
    c5 = (12 * h - 6 * (v1 + v0) * T + (a1 - a0) * T ** 2) / (2 * T ** 5)
    return (a[0] + v0 * x + 0.5 * a0 * x ** 2 + c3 * x ** 3 + c4 * x ** 4 + c5 * x ** 5,
            v0 + a0 * x + 3 * c3 * x ** 2 + 4 * c4 * x ** 3 + 5 * c5 * x ** 4)


class Trajectory(object):
    """Absolute times (s) and, per point, per joint (q, v, acc); the first point is where it
    starts. `before`: the trajectory in force until times[0] (None: hold the first point)."""

    def __init__(self, times, states, mode, before=None):
        self.times, self.states, self.mode, self.before = times, states, mode, before

    @staticmethod
    def hold(state):
        return Trajectory([0.0], [[(q, 0.0, 0.0) for q, _v, _a in state]], 'linear')

    def sample(self, t):
        """Per joint (q, v, acc) at time t."""
        if t < self.times[0] and self.before is not None:
            return self.before.sample(t)
        if t <= self.times[0]:
            return list(self.states[0]) if len(self.times) > 1 else \
                [(q, 0.0, 0.0) for q, _v, _a in self.states[0]]
        if t >= self.times[-1]:
            return [(q, 0.0, 0.0) for q, _v, _a in self.states[-1]]
        i = bisect.bisect_right(self.times, t) - 1
        out = []
        for j in range(len(self.states[0])):
            q, v = hermite(self.mode, self.times[i], self.times[i + 1],
                           self.states[i][j], self.states[i + 1][j], t)
            out.append((q, v, 0.0))
        # Acceleration by a central difference (only to join the next command smoothly).
        eps = 1e-4
        if self.mode != 'linear' and self.times[i] + eps < t < self.times[i + 1] - eps:
            for j in range(len(out)):
                _, vp = hermite(self.mode, self.times[i], self.times[i + 1],
                                self.states[i][j], self.states[i + 1][j], t + eps)
                _, vm = hermite(self.mode, self.times[i], self.times[i + 1],
                                self.states[i][j], self.states[i + 1][j], t - eps)
                out[j] = (out[j][0], out[j][1], (vp - vm) / (2 * eps))
        return out


class FakeController(object):
    def __init__(self, joints, initial):
        self.joints = joints
        self.index = {n: i for i, n in enumerate(joints)}
        self.lock = threading.Lock()
        self.traj = Trajectory.hold([(q, 0.0, 0.0) for q in initial])
        self.sub = rospy.Subscriber('~command', JointTrajectory, self.on_command, queue_size=10,
                                    tcp_nodelay=True)

    def on_command(self, msg):
        now = rospy.Time.now().to_sec()
        names = list(msg.joint_names)
        unknown = [n for n in names if n not in self.index]
        if unknown or len(set(names)) != len(names):
            rospy.logwarn('fake_trajectory_controller: command ignored: joints %s unknown or '
                          'repeated (driving %s)', unknown or names, self.joints)
            return
        with self.lock:
            if not msg.points:
                self.traj = Trajectory.hold(self.traj.sample(now))
                return
            start = msg.header.stamp.to_sec() if not msg.header.stamp.is_zero() else now
            splice = max(now, start)
            keep = [p for p in msg.points if start + p.time_from_start.to_sec() > splice]
            if not keep:
                rospy.logwarn('fake_trajectory_controller: command ignored: all its points are '
                              'in the past')
                return
            has_v = all(len(p.velocities) == len(names) for p in msg.points)
            has_a = has_v and all(len(p.accelerations) == len(names) for p in msg.points)
            mode = 'quintic' if has_a else ('cubic' if has_v else 'linear')
            first = self.traj.sample(splice)
            times, states = [splice], [first]
            for p in keep:
                state = [(q, 0.0, 0.0) for q, _v, _a in first]  # unnamed joints hold
                for k, n in enumerate(names):
                    j = self.index[n]
                    state[j] = (p.positions[k], p.velocities[k] if has_v else 0.0,
                                p.accelerations[k] if has_a else 0.0)
                times.append(start + p.time_from_start.to_sec())
                states.append(state)
            # Joints that the command does not name hold their position at the splice.
            for j in range(len(self.joints)):
                if self.joints[j] not in names:
                    states[0][j] = (first[j][0], 0.0, 0.0)
            before = self.traj if start > now else None
            if before is not None:
                before.before = None  # keep the chain one deep
            self.traj = Trajectory(times, states, mode, before)

    def state(self, t):
        with self.lock:
            return self.traj.sample(t)


def main():
    rospy.init_node('arm_controller')
    joints = rospy.get_param('~joints', [])
    if not isinstance(joints, list) or not joints or not all(isinstance(n, str) for n in joints):
        rospy.logfatal('fake_trajectory_controller: ~joints must be a non-empty list of joint names')
        return 1
    initial = rospy.get_param('~initial_positions', [0.0] * len(joints))
    if not isinstance(initial, list) or len(initial) != len(joints):
        rospy.logfatal('fake_trajectory_controller: ~initial_positions must have one value per joint')
        return 1
    rate_hz = float(rospy.get_param('~rate', 100.0))
    if not (1.0 <= rate_hz <= 1000.0):
        rospy.logfatal('fake_trajectory_controller: ~rate must be in [1, 1000] Hz')
        return 1
    ctrl = FakeController(joints, [float(q) for q in initial])
    pub = rospy.Publisher('joint_states', JointState, queue_size=10)
    rospy.loginfo('fake_trajectory_controller: driving %s; commands on %s', joints,
                  rospy.resolve_name('~command'))
    rate = rospy.Rate(rate_hz)
    while not rospy.is_shutdown():
        now = rospy.Time.now()
        state = ctrl.state(now.to_sec())
        msg = JointState()
        msg.header.stamp = now
        msg.name = list(joints)
        msg.position = [s[0] for s in state]
        msg.velocity = [s[1] for s in state]
        pub.publish(msg)
        try:
            rate.sleep()
        except rospy.ROSInterruptException:
            break
    return 0


if __name__ == '__main__':
    try:
        sys.exit(main())
    except rospy.ROSInterruptException:
        pass
