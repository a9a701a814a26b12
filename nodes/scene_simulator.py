#!/usr/bin/env python3
"""Simulated robot cell for the workspace_proximity demo.

Publishes, at ~rate Hz:
  * the arm (config/demo_arm.urdf), its revolute joints moving smoothly so that the arm sweeps
    around the cell, as a real robot driver does: sensor_msgs/JointState on joint_states
    (positions and their exact velocities; robot_state_publisher turns them into tf) and the
    static transform world -> <URDF root>; or, with ~robot_output: tf, every joint's transform
    on tf directly;
  * tracked_objects (workspace_proximity/TrackedBoxArray): three people walking through the
    cell on looping paths that come near the arm, and a forklift crossing it, each with the
    exact velocity of its path.

The arm follows the proximity monitor's speed scale (std_msgs/Float64 on speed_scale, speed and
separation monitoring) as a robot controller with a speed override would: its trajectory's
time advances at the scale (1: full speed, 0: standing still, and its joint velocities are
scaled alike), and silence on speed_scale for longer than ~speed_scale_timeout counts as 0,
so the loop from the tracked people through the monitor to the arm is closed.

Parameters (private):
  ~rate (30.0)            Hz
  ~frame ("world")        fixed frame of the tf root and of the tracked objects
  ~robot_description_param ("robot_description")  URDF to animate
  ~seed (0)               0: the deterministic scene; otherwise random phases for paths and joints
  ~objects (true)         publish tracked_objects
  ~robot (true)           publish the arm
  ~robot_output ("joint_states")  joint_states (+ robot_state_publisher) or tf; or base_only:
                          only the static transform of the arm's root, its joints driven by
                          another node (the demo: a planner through trajectory_relay and
                          fake_trajectory_controller.py)
  ~follow_speed_scale (false)     slow the arm down by speed_scale (the demo turns it on)
  ~speed_scale_timeout (0.1)      s without a speed_scale message after which the scale is 0
                                  (the demo: 3 periods of the monitor)
  ~trajectory_topic ("")  planned-trajectory episode: every ~plan_period s the arm leaves its
                          periodic motion for a planned move (reach out with the pan and elbow,
                          stop 1.5 s, return), announced 0.3 s ahead as a
                          trajectory_msgs/JointTrajectory on this topic, and executed exactly
                          (linear between its points); "" = no episode
  ~plan_period (15.0)     s between planned moves
Sets ~scene_start (s, ROS time) when the scene's clock starts: the paths' time t is counted from it.
"""

import math
import random
import sys
import threading
import xml.etree.ElementTree as ET

import rospy
import tf2_ros
from geometry_msgs.msg import TransformStamped
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

from workspace_proximity.msg import TrackedBox, TrackedBoxArray

# ---------------------------------------------------------------------------------------------
# Small rigid-transform helpers (quaternions as (x, y, z, w)).


def quat_from_rpy(roll, pitch, yaw):
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    return (sr * cp * cy - cr * sp * sy,
            cr * sp * cy + sr * cp * sy,
            cr * cp * sy - sr * sp * cy,
            cr * cp * cy + sr * sp * sy)


def quat_from_axis_angle(axis, angle):
    n = math.sqrt(sum(a * a for a in axis)) or 1.0
    s = math.sin(angle / 2) / n
    return (axis[0] * s, axis[1] * s, axis[2] * s, math.cos(angle / 2))


def quat_mul(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz)


def quat_rotate(q, v):
    qv = (v[0], v[1], v[2], 0.0)
    qc = (-q[0], -q[1], -q[2], q[3])
    r = quat_mul(quat_mul(q, qv), qc)
    return (r[0], r[1], r[2])


# ---------------------------------------------------------------------------------------------
# The arm: joints read from the URDF, animated by smooth periodic trajectories.


class Joint(object):
    def __init__(self, name, jtype, parent, child, xyz, rpy, axis, lower, upper):
        self.name, self.type, self.parent, self.child = name, jtype, parent, child
        self.xyz, self.rot = xyz, quat_from_rpy(*rpy)
        self.axis, self.lower, self.upper = axis, lower, upper


def _floats(text, default):
    return tuple(float(v) for v in text.split()) if text else default


def parse_urdf(xml_text):
    """Returns (root link name, [Joint]) with the joints in parent-before-child order."""
    robot = ET.fromstring(xml_text)
    joints = []
    for j in robot.findall('joint'):
        origin = j.find('origin')
        axis = j.find('axis')
        limit = j.find('limit')
        joints.append(Joint(
            j.get('name'), j.get('type'), j.find('parent').get('link'), j.find('child').get('link'),
            _floats(origin.get('xyz') if origin is not None else None, (0.0, 0.0, 0.0)),
            _floats(origin.get('rpy') if origin is not None else None, (0.0, 0.0, 0.0)),
            _floats(axis.get('xyz') if axis is not None else None, (1.0, 0.0, 0.0)),
            float(limit.get('lower', '-3.14')) if limit is not None else -math.pi,
            float(limit.get('upper', '3.14')) if limit is not None else math.pi))
    children = {j.child for j in joints}
    links = [l.get('name') for l in robot.findall('link')]
    roots = [l for l in links if l not in children]
    if len(roots) != 1:
        raise ValueError('URDF must have exactly one root link, found %s' % roots)
    ordered, known = [], {roots[0]}
    pending = list(joints)
    while pending:
        ready = [j for j in pending if j.parent in known]
        if not ready:
            raise ValueError('URDF joints do not form a tree')
        for j in ready:
            ordered.append(j)
            known.add(j.child)
            pending.remove(j)
    return roots[0], ordered


# Joint trajectories of the demo arm: q(t) = offset + amplitude * sin(2 pi t / period + phase).
# The pan sweeps the arm through most of the cell; lift and elbow raise and fold it.
ARM_MOTION = {
    'shoulder_pan': (0.0, 2.4, 20.0, 0.0),
    'shoulder_lift': (-0.45, 0.25, 7.0, 0.5),
    'elbow': (0.55, 0.35, 5.0, 1.0),
}


class ArmAnimator(object):
    def __init__(self, root, joints, seed_rng):
        self.root, self.joints = root, joints
        self.motion = {}
        for i, j in enumerate(joints):
            if j.type not in ('revolute', 'continuous', 'prismatic'):
                continue
            if j.name in ARM_MOTION:
                offset, amp, period, phase = ARM_MOTION[j.name]
            else:  # any other movable joint: a gentle swing inside its limits
                mid, half = 0.5 * (j.lower + j.upper), 0.5 * (j.upper - j.lower)
                offset, amp, period, phase = mid, 0.5 * half, 6.0 + 1.7 * i, 0.0
            if seed_rng is not None:
                phase += seed_rng.uniform(0.0, 2.0 * math.pi)
            self.motion[j.name] = (offset, amp, period, phase)

    def position(self, joint, t):
        offset, amp, period, phase = self.motion[joint.name]
        q = offset + amp * math.sin(2.0 * math.pi * t / period + phase)
        return min(max(q, joint.lower), joint.upper)

    def velocity(self, joint, t, speed=1.0):
        """Exact derivative of position() with respect to real time when the trajectory's time
        t advances at `speed` seconds per second (0 while held at a limit)."""
        offset, amp, period, phase = self.motion[joint.name]
        q = offset + amp * math.sin(2.0 * math.pi * t / period + phase)
        if q <= joint.lower or q >= joint.upper:
            return 0.0
        w = 2.0 * math.pi / period
        return speed * amp * w * math.cos(w * t + phase)

    def joint_state(self, stamp, t, speed=1.0, plan=None):
        msg = JointState()
        msg.header.stamp = stamp
        for j in self.joints:
            if j.name in self.motion:
                msg.name.append(j.name)
                planned = plan.at(j.name, t) if plan is not None else None
                if planned is not None:
                    msg.position.append(planned[0])
                    msg.velocity.append(speed * planned[1])
                    continue
                msg.position.append(self.position(j, t))
                msg.velocity.append(self.velocity(j, t, speed))
        return msg

    def transforms(self, t):
        """Yields (parent, child, translation, rotation) for every joint at time t."""
        for j in self.joints:
            trans, rot = j.xyz, j.rot
            if j.name in self.motion:
                q = self.position(j, t)
                if j.type == 'prismatic':
                    d = quat_rotate(j.rot, tuple(a * q for a in j.axis))
                    trans = (trans[0] + d[0], trans[1] + d[1], trans[2] + d[2])
                else:
                    rot = quat_mul(j.rot, quat_from_axis_angle(j.axis, q))
            yield j.parent, j.child, trans, rot


# The planned move of the demo's trajectory episode: (s after its start, pan offset rad, elbow
# rad). From where the periodic motion is, the pan turns 1.2 rad further and the elbow folds
# out, a stop, and back to where the periodic motion will be when the move ends.
PLAN_TIMES = (0.0, 1.5, 3.0, 4.5)
PLAN_LEAD = 0.3  # s: the plan is published this long before it starts


class PlannedMove(object):
    """One planned move of the pan and elbow joints from time `t_start` (s of the scene)."""

    def __init__(self, arm, t_start):
        self.t_start = t_start
        self.points = {}
        for j in arm.joints:
            if j.name not in ('shoulder_pan', 'elbow') or j.name not in arm.motion:
                continue
            first = arm.position(j, t_start)
            last = arm.position(j, t_start + PLAN_TIMES[-1])
            if j.name == 'shoulder_pan':
                far = first + (1.2 if first < 0.0 else -1.2)
            else:
                far = 0.2
            far = min(max(far, j.lower), j.upper)
            self.points[j.name] = (first, far, far, last)

    @property
    def end(self):
        return self.t_start + PLAN_TIMES[-1]

    def at(self, name, t):
        """(position, velocity) of joint `name` at scene time t while the move runs, else None."""
        if name not in self.points or not (self.t_start <= t <= self.end):
            return None
        q, s = self.points[name], t - self.t_start
        for k in range(1, len(PLAN_TIMES)):
            if s <= PLAN_TIMES[k]:
                v = (q[k] - q[k - 1]) / (PLAN_TIMES[k] - PLAN_TIMES[k - 1])
                return q[k - 1] + v * (s - PLAN_TIMES[k - 1]), v
        return q[-1], 0.0

    def message(self, stamp):
        msg = JointTrajectory()
        msg.header.stamp = stamp
        msg.joint_names = sorted(self.points)
        for k, t in enumerate(PLAN_TIMES):
            msg.points.append(JointTrajectoryPoint(
                positions=[self.points[n][k] for n in msg.joint_names],
                time_from_start=rospy.Duration(t)))
        return msg

# ---------------------------------------------------------------------------------------------
# Tracked objects. Each path returns (x, y, yaw, vx, vy, yaw_rate) at time t.


class PingPong(object):
    """Back and forth along a line through `centre` in direction `heading`, sinusoidal."""

    def __init__(self, centre, heading, half_length, period, phase=0.0):
        self.c, self.h, self.a, self.w, self.p = centre, heading, half_length, 2 * math.pi / period, phase

    def __call__(self, t):
        s = self.a * math.sin(self.w * t + self.p)
        v = self.a * self.w * math.cos(self.w * t + self.p)
        ch, sh = math.cos(self.h), math.sin(self.h)
        return (self.c[0] + s * ch, self.c[1] + s * sh, self.h, v * ch, v * sh, 0.0)


class Ellipse(object):
    """Round an axis-aligned ellipse, facing the direction of travel."""

    def __init__(self, centre, a, b, period, phase=0.0):
        self.c, self.a, self.b, self.w, self.p = centre, a, b, 2 * math.pi / period, phase

    def __call__(self, t):
        th = self.w * t + self.p
        c, s = math.cos(th), math.sin(th)
        vx, vy = -self.a * self.w * s, self.b * self.w * c
        ax, ay = -self.a * self.w ** 2 * c, -self.b * self.w ** 2 * s
        yaw_rate = (vx * ay - vy * ax) / (vx * vx + vy * vy)
        return (self.c[0] + self.a * c, self.c[1] + self.b * s, math.atan2(vy, vx), vx, vy, yaw_rate)


class Visit(object):
    """Walks from A to B with a smooth (cosine) speed profile, waits, walks back, waits."""

    def __init__(self, a, b, move, wait_b, wait_a, phase=0.0):
        self.a, self.b = a, b
        self.move, self.wait_b, self.wait_a, self.phase = move, wait_b, wait_a, phase
        self.period = 2 * move + wait_b + wait_a
        self.heading = math.atan2(b[1] - a[1], b[0] - a[0])

    def __call__(self, t):
        u = (t + self.phase) % self.period
        m = self.move
        if u < m:                      # A -> B
            s, ds, yaw = 0.5 - 0.5 * math.cos(math.pi * u / m), 0.5 * math.pi / m * math.sin(math.pi * u / m), self.heading
        elif u < m + self.wait_b:      # waiting at B
            s, ds, yaw = 1.0, 0.0, self.heading
        elif u < 2 * m + self.wait_b:  # B -> A
            k = u - m - self.wait_b
            s, ds = 0.5 + 0.5 * math.cos(math.pi * k / m), -0.5 * math.pi / m * math.sin(math.pi * k / m)
            yaw = self.heading + math.pi
        else:                          # waiting at A
            s, ds, yaw = 0.0, 0.0, self.heading + math.pi
        dx, dy = self.b[0] - self.a[0], self.b[1] - self.a[1]
        return (self.a[0] + s * dx, self.a[1] + s * dy, yaw, ds * dx, ds * dy, 0.0)


PERSON_SIZE = (0.5, 0.5, 1.8)
FORKLIFT_SIZE = (2.4, 1.2, 2.0)


def make_objects(rng):
    """[(id, label, size, path)]; rng None gives the deterministic scene."""
    def ph(period):
        return rng.uniform(0.0, period) if rng is not None else 0.0
    return [
        # Walks along the aisle in front of the arm, passing 1.6 m from its base.
        ('person_1', 'person', PERSON_SIZE,
         PingPong(centre=(0.0, 1.6), heading=0.0, half_length=4.0, period=22.0, phase=ph(2 * math.pi))),
        # Walks round the cell.
        ('person_2', 'person', PERSON_SIZE,
         Ellipse(centre=(0.3, -0.1), a=2.7, b=2.0, period=15.0, phase=ph(2 * math.pi) + 1.0)),
        # Walks up to a bench beside the arm, works there for a while, and leaves.
        ('person_3', 'person', PERSON_SIZE,
         Visit(a=(-4.5, 3.2), b=(-1.15, 1.0), move=5.0, wait_b=4.0, wait_a=3.0, phase=ph(17.0) + 2.0)),
        # Drives through the cell along y = -2.3 and back.
        ('forklift_1', 'forklift', FORKLIFT_SIZE,
         PingPong(centre=(0.0, -2.3), heading=0.0, half_length=9.0, period=30.0, phase=ph(2 * math.pi) + 0.52)),
    ]


# ---------------------------------------------------------------------------------------------


class SpeedScale(object):
    """The latest speed_scale, or 0 once it has been silent for longer than `timeout` s (a
    monitor that stopped cycling must stop the robot, not leave it at its last speed)."""

    def __init__(self, timeout):
        self.timeout = timeout
        self.lock = threading.Lock()
        self.value = 0.0
        self.received = None
        self.sub = rospy.Subscriber('speed_scale', Float64, self.on_scale, queue_size=1,
                                    tcp_nodelay=True)

    def on_scale(self, msg):
        with self.lock:
            self.value = min(1.0, max(0.0, msg.data))
            self.received = rospy.Time.now()

    def now(self):
        with self.lock:
            if self.received is None or (rospy.Time.now() - self.received).to_sec() > self.timeout:
                return 0.0
            return self.value


def main():
    rospy.init_node('scene_simulator')
    rate_hz = float(rospy.get_param('~rate', 30.0))
    if not (0.1 <= rate_hz <= 1000.0):
        rospy.logfatal('~rate must be in [0.1, 1000] Hz, got %g', rate_hz)
        return 1
    frame = rospy.get_param('~frame', 'world')
    seed = int(rospy.get_param('~seed', 0))
    rng = random.Random(seed) if seed != 0 else None
    publish_robot = bool(rospy.get_param('~robot', True))
    publish_objects = bool(rospy.get_param('~objects', True))
    robot_output = rospy.get_param('~robot_output', 'joint_states')
    follow = bool(rospy.get_param('~follow_speed_scale', False))
    scale_timeout = float(rospy.get_param('~speed_scale_timeout', 0.1))
    trajectory_topic = rospy.get_param('~trajectory_topic', '')
    plan_period = float(rospy.get_param('~plan_period', 15.0))
    if robot_output not in ('joint_states', 'tf', 'base_only'):
        rospy.logfatal("~robot_output must be 'joint_states', 'tf' or 'base_only', got %r",
                       robot_output)
        return 1

    arm = None
    if publish_robot:
        desc_param = rospy.get_param('~robot_description_param', 'robot_description')
        xml_text = None
        while not rospy.is_shutdown() and xml_text is None:
            try:
                xml_text = rospy.get_param(desc_param)
            except KeyError:
                rospy.logwarn_throttle(5.0, 'scene_simulator: waiting for parameter %s'
                                       % rospy.resolve_name(desc_param))
                rospy.sleep(0.5)
        if xml_text is None:
            return 0
        try:
            root, joints = parse_urdf(xml_text)
        except (ET.ParseError, ValueError, AttributeError) as e:
            rospy.logfatal('scene_simulator: cannot read the URDF in %s: %s', desc_param, e)
            return 1
        arm = ArmAnimator(root, joints, rng)

    objects = make_objects(rng) if publish_objects else []
    broadcaster = tf2_ros.TransformBroadcaster()
    pub = rospy.Publisher('tracked_objects', TrackedBoxArray, queue_size=10)
    joints_pub = None
    if arm is not None and robot_output in ('joint_states', 'base_only'):
        if robot_output == 'joint_states':
            joints_pub = rospy.Publisher('joint_states', JointState, queue_size=10)
        # The arm stands still in the cell: its base is a static transform, the rest comes from
        # robot_state_publisher.
        static_broadcaster = tf2_ros.StaticTransformBroadcaster()
        static_broadcaster.sendTransform(
            make_tf(rospy.Time.now(), frame, arm.root, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)))
    rospy.loginfo('scene_simulator: %d Hz, frame %s, %s, %d tracked objects%s%s', rate_hz, frame,
                  ('arm rooted at %s with %d joints' % (arm.root, len(arm.joints))) if arm else 'no arm',
                  len(objects), (', seed %d' % seed) if seed else '',
                  (', the arm follows %s' % rospy.resolve_name('speed_scale')) if (arm and follow) else '')

    if robot_output == 'base_only':
        arm = None  # its joints are another node's
    speed_scale = SpeedScale(scale_timeout) if (arm is not None and follow) else None
    plan_pub, plan = None, None
    if joints_pub is not None and trajectory_topic and plan_period > PLAN_TIMES[-1] + PLAN_LEAD:
        plan_pub = rospy.Publisher(trajectory_topic, JointTrajectory, queue_size=2)

    start = rospy.Time.now()
    # The scene's clock starts here: tools (tools/demo_ssm_share.py) align their windows to it.
    rospy.set_param('~scene_start', start.to_sec())
    rate = rospy.Rate(rate_hz)
    arm_t = 0.0      # the arm's trajectory time: advances at the speed scale
    last = start
    while not rospy.is_shutdown():
        now = rospy.Time.now()
        t = (now - start).to_sec()
        speed = speed_scale.now() if speed_scale is not None else 1.0
        arm_t += max(0.0, (now - last).to_sec()) * speed
        last = now

        if plan_pub is not None:
            # Announce the next move PLAN_LEAD s (of the arm's time) ahead; the arm executes it
            # in its own time, so at full speed exactly as announced, and behind the plan while
            # the speed scale slows it (the monitor then drops the plan as not followed, as it
            # would for a real controller that scales a trajectory).
            n = math.floor((arm_t + PLAN_LEAD) / plan_period)
            t_next = n * plan_period
            if n >= 1 and (plan is None or plan.t_start < t_next):
                plan = PlannedMove(arm, t_next)
                plan_pub.publish(plan.message(now + rospy.Duration(max(0.0, t_next - arm_t))))
                rospy.loginfo('scene_simulator: planned move at t = %.1f s', t_next)

        if joints_pub is not None:
            joints_pub.publish(arm.joint_state(now, arm_t, speed, plan))
        elif arm is not None:
            tfs = [make_tf(now, frame, arm.root, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0))]
            for parent, child, trans, rot in arm.transforms(arm_t):
                tfs.append(make_tf(now, parent, child, trans, rot))
            broadcaster.sendTransform(tfs)

        if objects:
            msg = TrackedBoxArray()
            msg.header.stamp = now
            msg.header.frame_id = frame
            for oid, label, size, path in objects:
                x, y, yaw, vx, vy, wz = path(t)
                box = TrackedBox()
                box.id, box.label = oid, label
                box.pose.position.x, box.pose.position.y, box.pose.position.z = x, y, 0.5 * size[2]
                q = quat_from_rpy(0.0, 0.0, yaw)
                (box.pose.orientation.x, box.pose.orientation.y,
                 box.pose.orientation.z, box.pose.orientation.w) = q
                box.dimensions.x, box.dimensions.y, box.dimensions.z = size
                box.twist.linear.x, box.twist.linear.y = vx, vy
                box.twist.angular.z = wz
                msg.boxes.append(box)
            pub.publish(msg)

        try:
            rate.sleep()
        except rospy.ROSInterruptException:
            break
    return 0


def make_tf(stamp, parent, child, trans, rot):
    t = TransformStamped()
    t.header.stamp = stamp
    t.header.frame_id = parent
    t.child_frame_id = child
    t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = trans
    t.transform.rotation.x, t.transform.rotation.y, t.transform.rotation.z, t.transform.rotation.w = rot
    return t


if __name__ == '__main__':
    try:
        sys.exit(main())
    except rospy.ROSInterruptException:
        pass
