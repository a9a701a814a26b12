#!/usr/bin/env python3
"""The demo arm's planner: a work cycle of planned moves, as a motion planner would send them.

From where the arm is (joint_states), a planned trajectory_msgs/JointTrajectory (positions and
velocities: a cubic per segment) through a via pose to the next pose of the cycle, published on
~trajectory_topic (header stamp: now). The next move is planned once the arm has arrived
(every joint within ~arrival_tolerance of the target) and dwelt ~dwell s. The planner never
looks at the speed scale: trajectory_relay pauses and resumes the planned moves, so the arm
takes longer when people come near, and arrives all the same.

Parameters (private):
  ~trajectory_topic ("/planned_trajectory")
  ~move_time (8.0)           s of a planned move (at full speed)
  ~dwell (1.0)               s at each pose
  ~arrival_tolerance (0.002) rad
"""

import sys
import threading

import rospy
from sensor_msgs.msg import JointState
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

JOINTS = ['shoulder_pan', 'shoulder_lift', 'elbow']
# The cycle's poses (rad) and the via pose between them: the pan sweeps across the cell, past
# the aisle where people walk.
POSES = [[-2.0, -0.45, 0.55], [2.0, -0.3, 0.3]]
VIA = [0.0, -0.7, 0.9]


class Planner(object):
    def __init__(self):
        self.topic = rospy.get_param('~trajectory_topic', '/planned_trajectory')
        self.move_time = float(rospy.get_param('~move_time', 8.0))
        self.dwell = float(rospy.get_param('~dwell', 1.0))
        self.tolerance = float(rospy.get_param('~arrival_tolerance', 0.002))
        if not (0.5 <= self.move_time <= 600.0 and 0.0 <= self.dwell <= 600.0 and
                0.0 < self.tolerance <= 1.0):
            raise ValueError('~move_time must be in [0.5, 600] s, ~dwell in [0, 600] s and '
                             '~arrival_tolerance in (0, 1] rad')
        self.lock = threading.Lock()
        self.position = None
        self.pub = rospy.Publisher(self.topic, JointTrajectory, queue_size=1, latch=True)
        self.sub = rospy.Subscriber('joint_states', JointState, self.on_state, queue_size=10)

    def on_state(self, msg):
        if not all(n in msg.name for n in JOINTS):
            return
        with self.lock:
            self.position = [msg.position[msg.name.index(n)] for n in JOINTS]

    def current(self):
        with self.lock:
            return None if self.position is None else list(self.position)

    def plan(self, start, target):
        """start -> VIA -> target in move_time s, at rest at both ends."""
        half = 0.5 * self.move_time
        via_velocity = [(t - s) / self.move_time for s, t in zip(start, target)]
        msg = JointTrajectory()
        msg.header.stamp = rospy.Time.now()
        msg.joint_names = JOINTS
        for t, q, v in ((0.0, start, [0.0] * 3), (half, VIA, via_velocity),
                        (self.move_time, target, [0.0] * 3)):
            msg.points.append(JointTrajectoryPoint(positions=list(q), velocities=list(v),
                                                   time_from_start=rospy.Duration(t)))
        return msg

    def run(self):
        while not rospy.is_shutdown() and self.current() is None:
            rospy.sleep(0.1)
        # The first move goes to the pose farther from where the arm is.
        q = self.current()
        k = max(range(len(POSES)), key=lambda i: max(abs(a - b) for a, b in zip(q, POSES[i])))
        while not rospy.is_shutdown():
            target = POSES[k % len(POSES)]
            start = self.current()
            self.pub.publish(self.plan(start, target))
            rospy.loginfo('demo_planner: move %d to %s', k + 1, target)
            while not rospy.is_shutdown():
                q = self.current()
                if max(abs(a - b) for a, b in zip(q, target)) <= self.tolerance:
                    break
                rospy.sleep(0.05)
            rospy.sleep(self.dwell)
            k += 1


def main():
    rospy.init_node('demo_planner')
    try:
        planner = Planner()
    except ValueError as e:
        rospy.logfatal('demo_planner: %s', e)
        return 1
    planner.run()
    return 0


if __name__ == '__main__':
    try:
        sys.exit(main())
    except rospy.ROSInterruptException:
        pass
