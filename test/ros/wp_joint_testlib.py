"""Helpers of the joint rostests: a joint_states publisher thread, the swing arm's analytic
first contact and an independent check of what straight-line extrapolation would predict."""
import math
import threading

import rospy
from sensor_msgs.msg import JointState

OMEGA = 0.5          # rad/s of the swinging joints
ARM_HALF = (0.5, 0.05)   # the arm box's half extents in the plane (from 0 to 1 m along x)
OBJ_R, OBJ_HALF = 0.75, 0.1  # the object: centre at radius 0.75, a 0.2 m square, yawed radially


def contact_angle(phi):
    """Joint angle at which the arm (turning +z from below phi) first touches the object
    centred at radius OBJ_R, angle phi, yawed by phi: the object's corner (OBJ_R - h, -h) in its
    own radial/tangential axes reaches the arm's leading face y = 0.05 when
    (OBJ_R - h) sin a - h cos a = 0.05, a = phi - angle."""
    u, v = OBJ_R - OBJ_HALF, OBJ_HALF
    r = math.hypot(u, v)
    return phi - (math.atan2(v, u) + math.asin(ARM_HALF[1] / r))


def _rect(c, th, hx, hy):
    ca, sa = math.cos(th), math.sin(th)
    return [(c[0] + ca * x - sa * y, c[1] + sa * x + ca * y)
            for x, y in ((-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy))], th


def _separated(a, b):
    for _, th in (a, b):
        for ax in ((math.cos(th), math.sin(th)), (-math.sin(th), math.cos(th))):
            pa = [p[0] * ax[0] + p[1] * ax[1] for p in a[0]]
            pb = [p[0] * ax[0] + p[1] * ax[1] for p in b[0]]
            if max(pa) < min(pb) or max(pb) < min(pa):
                return True
    return False


def straight_line_contact(theta0, phi, horizon=4.0, steps=40000):
    """First contact (s) when the arm at angle theta0 is extrapolated with the constant twist
    of its box (the centre on a straight line, turning about it), by dense sampling with a
    separating-axis test; None when none within the horizon."""
    obj = _rect((OBJ_R * math.cos(phi), OBJ_R * math.sin(phi)), phi, OBJ_HALF, OBJ_HALF)
    c = (ARM_HALF[0] * math.cos(theta0), ARM_HALF[0] * math.sin(theta0))
    v = (-ARM_HALF[0] * OMEGA * math.sin(theta0), ARM_HALF[0] * OMEGA * math.cos(theta0))
    for i in range(steps + 1):
        t = horizon * i / steps
        arm = _rect((c[0] + v[0] * t, c[1] + v[1] * t), theta0 + OMEGA * t, *ARM_HALF)
        if not _separated(arm, obj):
            return t
    return None


class JointStatePublisher(object):
    """Publishes joint_states every `period` s, stamped now, positions from
    `positions(stamp)` -> {name: (position, velocity)}; velocities left empty when
    `with_velocity` is false. `stop` ends it; `last_stamp` is the last stamp sent."""

    def __init__(self, positions, with_velocity=True, period=0.02, first_pause=0.0):
        self.positions, self.with_velocity, self.period = positions, with_velocity, period
        self.first_pause = first_pause  # s of silence after the first message
        self.pub = rospy.Publisher("joint_states", JointState, queue_size=10)
        self.stop = threading.Event()
        self.last_stamp = None
        self.thread = None

    def wait_connected(self, timeout=10.0):
        deadline = rospy.Time.now() + rospy.Duration(timeout)
        while self.pub.get_num_connections() == 0 and rospy.Time.now() < deadline:
            rospy.sleep(0.05)
        return self.pub.get_num_connections() > 0

    def start(self):
        self.thread = threading.Thread(target=self._run)
        self.thread.daemon = True
        self.thread.start()

    def halt(self):
        self.stop.set()
        if self.thread is not None:
            self.thread.join(1.0)

    def _run(self):
        while not self.stop.is_set() and not rospy.is_shutdown():
            msg = JointState()
            msg.header.stamp = rospy.Time.now()
            for name, (q, v) in sorted(self.positions(msg.header.stamp).items()):
                msg.name.append(name)
                msg.position.append(q)
                if self.with_velocity:
                    msg.velocity.append(v)
            self.pub.publish(msg)
            first = self.last_stamp is None
            self.last_stamp = msg.header.stamp
            self.stop.wait(self.first_pause if first and self.first_pause > 0.0 else self.period)
