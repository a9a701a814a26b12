"""Shared helpers for the proximity_monitor rostests (imported by the test_*.py scripts).

Scenes are made of Tracks: oriented boxes moving with piecewise-constant linear velocity.
A ScenePublisher publishes them as TrackedBoxArray at a fixed rate; every message carries the
pose the box has at the message's stamp, so whichever message the node extrapolates from, the
box is where the analytic model says it is at the prediction instant.
"""
import math
import os
import sys
import threading
import time

import rospy
from geometry_msgs.msg import Pose, TransformStamped, Twist, Vector3
from visualization_msgs.msg import MarkerArray

try:
    from workspace_proximity.msg import (ContactEvent, ContactEventArray, SafetyStatus,
                                         TrackedBox, TrackedBoxArray)
except ImportError:
    # A devel space configured for the first time exports an empty PYTHONPATH (its Python
    # directory did not exist yet when catkin cached the environment): look in the prefixes.
    for _prefix in os.environ.get("CMAKE_PREFIX_PATH", "").split(os.pathsep):
        _dir = os.path.join(_prefix, "lib", "python3", "dist-packages")
        if os.path.isdir(os.path.join(_dir, "workspace_proximity")) and _dir not in sys.path:
            sys.path.insert(0, _dir)
    sys.modules.pop("workspace_proximity", None)
    from workspace_proximity.msg import (ContactEvent, ContactEventArray, SafetyStatus,
                                         TrackedBox, TrackedBoxArray)

BEGIN = ContactEvent.BEGIN
ONGOING = ContactEvent.ONGOING
END = ContactEvent.END
STATE_NAMES = {BEGIN: "BEGIN", ONGOING: "ONGOING", END: "END"}
MARKER_NAMESPACES = {"bodies", "swept", "nearest", "ttc_text", "velocity", "ids", "status", "ssm"}

class WallPacer(object):
    """Paces a simulated clock's steps at about real time: call wait() after each step. A
    step that ran more than 0.1 s late restarts the pacing instead of rushing to catch up."""

    def __init__(self, step_s):
        self.step_s = step_s
        self.restart()

    def restart(self):
        self.next_wall = time.monotonic()

    def wait(self):
        self.next_wall += self.step_s
        delay = self.next_wall - time.monotonic()
        if delay > 0:
            time.sleep(delay)
        elif delay < -0.1:
            self.restart()


# Tolerances of the analytic checks.
TIME_TOL = 1e-3      # s, time_to_contact / time_to_separation
DIST_TOL = 1e-4      # m, distance and nearest points
SPEED_TOL = 1e-3     # m/s, closing speed
NORMAL_TOL = 1e-3    # per component


def quat_from_rpy(roll, pitch, yaw):
    """(x, y, z, w) of the rotation R = Rz(yaw) Ry(pitch) Rx(roll)."""
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    return (sr * cp * cy - cr * sp * sy,
            cr * sp * cy + sr * cp * sy,
            cr * cp * sy - sr * sp * cy,
            cr * cp * cy + sr * sp * sy)


def vsub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def vadd(a, b):
    return tuple(x + y for x, y in zip(a, b))


def vscale(a, s):
    return tuple(x * s for x in a)


def vdot(a, b):
    return sum(x * y for x, y in zip(a, b))


def vnorm(a):
    return math.sqrt(vdot(a, a))


def pt(p):
    """geometry_msgs Point/Vector3 -> tuple."""
    return (p.x, p.y, p.z)


def fmt_event(ev):
    return ("%s %s(%s)-%s(%s) ttc=%.6f tts=%.6f d=%.6f n=(%.4f,%.4f,%.4f) vc=%.4f lvl=%d" % (
        STATE_NAMES.get(ev.state, str(ev.state)), ev.id_a, ev.label_a, ev.id_b, ev.label_b,
        ev.time_to_contact, ev.time_to_separation, ev.distance, ev.normal.x, ev.normal.y,
        ev.normal.z, ev.closing_speed, ev.level))


class Track(object):
    """A box with piecewise-constant linear velocity (no rotation over time).

    position is the centre at rospy.Time t0; set_velocity(t, v) changes the velocity from
    time t on while keeping the position continuous.
    """

    def __init__(self, box_id, label, position, size, velocity=(0.0, 0.0, 0.0),
                 quat=(0.0, 0.0, 0.0, 1.0), t0=None, yaw=None, yaw_rate=0.0):
        self.id = box_id
        self.label = label
        self.size = tuple(float(s) for s in size)
        self.quat = quat
        # With `yaw` given the box turns about the world z axis through its centre:
        # yaw(t) = yaw + yaw_rate * (t - t0), and `quat` is ignored.
        self.yaw = yaw
        self.yaw_rate = float(yaw_rate)
        self.active = True
        self._t0 = t0
        self._segments = [(0.0, tuple(float(p) for p in position),
                           tuple(float(v) for v in velocity))]

    @property
    def half(self):
        return tuple(0.5 * s for s in self.size)

    def set_t0(self, t0):
        self._t0 = t0

    def rel(self, stamp):
        return (stamp - self._t0).to_sec()

    def set_velocity(self, stamp, velocity):
        """From `stamp` on the box moves with `velocity`."""
        t = self.rel(stamp)
        pos, _ = self.state_rel(t)
        self._segments.append((t, pos, tuple(float(v) for v in velocity)))

    def state_rel(self, t):
        seg = self._segments[0]
        for s in self._segments:
            if s[0] <= t:
                seg = s
        t_start, p_start, v = seg
        return vadd(p_start, vscale(v, t - t_start)), v

    def state(self, stamp):
        """(centre, velocity) at the rospy.Time `stamp`."""
        return self.state_rel(self.rel(stamp))

    def yaw_at(self, stamp):
        return self.yaw + self.yaw_rate * self.rel(stamp)

    def switch_times(self):
        return [s[0] for s in self._segments[1:]]

    def to_msg(self, stamp):
        pos, vel = self.state(stamp)
        b = TrackedBox()
        b.id = self.id
        b.label = self.label
        b.pose = Pose()
        b.pose.position.x, b.pose.position.y, b.pose.position.z = pos
        quat = self.quat if self.yaw is None else quat_from_rpy(0.0, 0.0, self.yaw_at(stamp))
        (b.pose.orientation.x, b.pose.orientation.y, b.pose.orientation.z,
         b.pose.orientation.w) = quat
        b.dimensions = Vector3(*self.size)
        b.twist = Twist()
        b.twist.linear = Vector3(*vel)
        if self.yaw is not None:
            b.twist.angular = Vector3(0.0, 0.0, self.yaw_rate)
        return b


class ScenePublisher(object):
    """Publishes a list of Tracks as TrackedBoxArray at `rate` Hz from a background thread.

    Each message's stamp is now - latency, and each box's pose is its pose at that stamp.
    """

    def __init__(self, topic, tracks, frame_id="world", rate=20.0, latency=0.1):
        self.pub = rospy.Publisher(topic, TrackedBoxArray, queue_size=10)
        self.tracks = tracks
        self.frame_id = frame_id
        self.period = 1.0 / rate
        self.latency = rospy.Duration(latency)
        self.lock = threading.Lock()
        self.t0 = None
        self.last_stamp = {}  # track id -> stamp of the last message that carried it
        self.last_wall = {}   # track id -> rospy time at which that message was published
        self._stop = threading.Event()
        self._thread = None

    def wait_connected(self, timeout=10.0):
        """Waits until a subscriber (the node) is connected; returns whether one is."""
        deadline = rospy.Time.now() + rospy.Duration(timeout)
        while self.pub.get_num_connections() < 1 and rospy.Time.now() < deadline:
            rospy.sleep(0.02)
        return self.pub.get_num_connections() >= 1

    def start(self, t0=None):
        """Starts publishing with time origin t0; without t0, first waits for the node to
        connect, then takes now as t0."""
        if t0 is None:
            self.wait_connected()
        self.t0 = t0 if t0 is not None else rospy.Time.now()
        for tr in self.tracks:
            tr.set_t0(self.t0)
        self._thread = threading.Thread(target=self._run)
        self._thread.daemon = True
        self._thread.start()
        return self.t0

    def _run(self):
        while not self._stop.is_set() and not rospy.is_shutdown():
            self.publish_once()
            self._stop.wait(self.period)

    def publish_once(self):
        with self.lock:
            now = rospy.Time.now()
            stamp = now - self.latency
            msg = TrackedBoxArray()
            msg.header.stamp = stamp
            msg.header.frame_id = self.frame_id
            for tr in self.tracks:
                if tr.active:
                    msg.boxes.append(tr.to_msg(stamp))
                    self.last_stamp[tr.id] = stamp
                    self.last_wall[tr.id] = now
            self.pub.publish(msg)

    def set_velocity(self, track, stamp, velocity):
        with self.lock:
            track.set_velocity(stamp, velocity)

    def deactivate(self, track):
        with self.lock:
            track.active = False

    def stop(self):
        self._stop.set()
        if self._thread is not None:
            self._thread.join(2.0)


def connected_collector(tc, **kwargs):
    """A Collector (Collector's arguments) once the node publishes contacts; the test `tc`
    fails if it never does."""
    col = Collector(**kwargs)
    tc.assertTrue(col.wait_for_node(), "proximity_monitor published no contacts")
    return col


def run_scene(collector, tracks, seconds, skip, latency=0.05, topic="tracked_objects"):
    """Publishes `tracks` for `seconds` from t0 (when the node is connected) and returns
    (t0, the contact arrays stamped from t0 + skip on)."""
    scene = ScenePublisher(topic, tracks, latency=latency)
    t0 = scene.start()
    rospy.sleep(seconds)
    scene.stop()
    return t0, collector.contact_msgs(since=t0 + rospy.Duration(skip))


class NodeLabels(dict):
    """Label -> {margin, warning_time, critical_time, warning_distance, critical_distance}
    as the node under test was given them; a label it has no entry for reads as "default",
    as the node treats it."""

    def __missing__(self, label):
        return self["default"]


def node_labels(node="/proximity_monitor"):
    """The node's label settings from the parameter server (so a test's expectations follow
    its .test file); "robot" holds ~robot_thresholds with ~robot_margin as its margin."""
    labels = NodeLabels(rospy.get_param(node + "/labels"))
    robot = dict(rospy.get_param(node + "/robot_thresholds"))
    robot["margin"] = rospy.get_param(node + "/robot_margin", 0.0)
    labels["robot"] = robot
    return labels


class Collector(object):
    """Records every ContactEventArray and MarkerArray the node publishes."""

    def __init__(self, contacts_topic="contacts", markers_topic="markers"):
        self.lock = threading.Lock()
        self.contacts = []   # (receipt rospy.Time, ContactEventArray)
        self.markers = []    # (receipt rospy.Time, MarkerArray)
        self.sub_c = rospy.Subscriber(contacts_topic, ContactEventArray, self._on_contacts,
                                      queue_size=200)
        self.sub_m = rospy.Subscriber(markers_topic, MarkerArray, self._on_markers,
                                      queue_size=200)

    def _on_contacts(self, msg):
        with self.lock:
            self.contacts.append((rospy.Time.now(), msg))

    def _on_markers(self, msg):
        with self.lock:
            self.markers.append((rospy.Time.now(), msg))

    def contact_msgs(self, since=None):
        with self.lock:
            return [m for t, m in self.contacts if since is None or m.header.stamp >= since]

    def marker_msgs(self, since=None):
        with self.lock:
            return [m for t, m in self.markers if since is None or t >= since]

    def wait_for_node(self, timeout=20.0):
        """Waits until the node has published at least two contact arrays."""
        deadline = rospy.Time.now() + rospy.Duration(timeout)
        while rospy.Time.now() < deadline and not rospy.is_shutdown():
            with self.lock:
                if len(self.contacts) >= 2:
                    return True
            rospy.sleep(0.05)
        return False

    def wait_until(self, predicate, timeout):
        """Waits until predicate(contact_msgs) is true; returns whether it became true."""
        deadline = rospy.Time.now() + rospy.Duration(timeout)
        while rospy.Time.now() < deadline and not rospy.is_shutdown():
            if predicate(self.contact_msgs()):
                return True
            rospy.sleep(0.05)
        return predicate(self.contact_msgs())


class TfBroadcaster(object):
    """parent -> child re-stamped with rospy.Time.now() every `period` s in a thread, at the
    translation `position(stamp)` (x, y, z) with no rotation, unless `paused` is set; `stop`
    ends it. `last_stamp` is the stamp of the last transform sent."""

    def __init__(self, parent, child, position, period=0.02):
        self.parent, self.child, self.position, self.period = parent, child, position, period
        import tf2_ros
        self.br = tf2_ros.TransformBroadcaster()
        self.paused = threading.Event()
        self.stop = threading.Event()
        self.last_stamp = None
        self.thread = threading.Thread(target=self.run)
        self.thread.daemon = True
        self.thread.start()

    def run(self):
        while not self.stop.is_set() and not rospy.is_shutdown():
            if not self.paused.is_set():
                t = TransformStamped()
                t.header.stamp = rospy.Time.now()
                t.header.frame_id = self.parent
                t.child_frame_id = self.child
                (t.transform.translation.x, t.transform.translation.y,
                 t.transform.translation.z) = self.position(t.header.stamp)
                t.transform.rotation.w = 1.0
                self.br.sendTransform(t)
                self.last_stamp = t.header.stamp
            self.stop.wait(self.period)


def broadcast_robot_frames(base_xyz, links):
    """Static tf of a robot: world -> base_link at `base_xyz` (not turned), and base_link ->
    each link of `links`, a list of (frame, xyz, rpy). Returns the broadcaster (keep it alive)."""
    return broadcast_static([("world", "base_link", base_xyz, (0.0, 0.0, 0.0))] +
                            [("base_link", frame, xyz, rpy) for frame, xyz, rpy in links])


def broadcast_static(transforms):
    """transforms: list of (parent, child, xyz, rpy). Returns the broadcaster (keep it alive)."""
    import tf2_ros
    br = tf2_ros.StaticTransformBroadcaster()
    msgs = []
    for parent, child, xyz, rpy in transforms:
        t = TransformStamped()
        t.header.stamp = rospy.Time.now()
        t.header.frame_id = parent
        t.child_frame_id = child
        t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = xyz
        q = quat_from_rpy(*rpy)
        (t.transform.rotation.x, t.transform.rotation.y, t.transform.rotation.z,
         t.transform.rotation.w) = q
        msgs.append(t)
    br.sendTransform(msgs)
    # Wait (up to 10 s) for a tf listener (the node's) to connect, so the transforms are known
    # to the node before the scene starts.
    deadline = rospy.Time.now() + rospy.Duration(10.0)
    while br.pub_tf.get_num_connections() < 1 and rospy.Time.now() < deadline:
        rospy.sleep(0.02)
    return br


def aabb_prediction(ca, ha, va, cb, hb, vb, horizon):
    """Exact prediction for two axis-aligned boxes translating at constant velocity.

    ca/cb centres, ha/hb half extents, va/vb velocities (world, at the prediction instant).
    Returns None when they do not touch within [0, horizon], else a dict with ttc, tts,
    distance, normal (None when touching), closing_speed (None when touching), axis (the
    single separating axis for a face-face configuration, else None).
    """
    lo, hi = -math.inf, math.inf
    for k in range(3):
        d = cb[k] - ca[k]
        w = vb[k] - va[k]
        s = ha[k] + hb[k]
        if w == 0.0:
            if abs(d) > s:
                lo, hi = math.inf, -math.inf
            continue
        t1, t2 = (-s - d) / w, (s - d) / w
        lo, hi = max(lo, min(t1, t2)), min(hi, max(t1, t2))
    lo, hi = max(lo, 0.0), min(hi, horizon)
    gaps = []
    for k in range(3):
        d = cb[k] - ca[k]
        g = abs(d) - (ha[k] + hb[k])
        gaps.append(math.copysign(g, d) if g > 0 else 0.0)
    dist = vnorm(gaps)
    res = {"distance": dist, "normal": None, "closing_speed": None, "axis": None}
    if dist > 0:
        n = vscale(gaps, 1.0 / dist)
        res["normal"] = n
        res["closing_speed"] = -vdot(vsub(vb, va), n)
        nonzero = [k for k in range(3) if gaps[k] != 0.0]
        if len(nonzero) == 1:
            res["axis"] = nonzero[0]
    if not lo <= hi:
        return None
    res["ttc"] = lo
    res["tts"] = hi
    return res


def check_face_contact(tc, ev, exp, ca, ha, cb, hb, what="", check_points=True):
    """Compares an event with aabb_prediction() output `exp` for boxes a, b (as in the event's
    id order). Nearest points are checked along the separating axis exactly and across it
    loosely (inside both boxes' extents), since a face-face pair has no unique nearest points."""
    ctx = "%s: %s vs expected %r" % (what, fmt_event(ev), exp)
    tc.assertAlmostEqual(ev.time_to_contact, exp["ttc"], delta=TIME_TOL, msg="ttc " + ctx)
    tc.assertAlmostEqual(ev.time_to_separation, exp["tts"], delta=TIME_TOL, msg="tts " + ctx)
    tc.assertAlmostEqual(ev.distance, exp["distance"], delta=DIST_TOL, msg="distance " + ctx)
    if exp["normal"] is not None:
        for k in range(3):
            tc.assertAlmostEqual(pt(ev.normal)[k], exp["normal"][k], delta=NORMAL_TOL,
                                 msg="normal " + ctx)
        tc.assertAlmostEqual(ev.closing_speed, exp["closing_speed"], delta=SPEED_TOL,
                             msg="closing_speed " + ctx)
    if exp["axis"] is not None and check_points:
        k = exp["axis"]
        sgn = 1.0 if cb[k] > ca[k] else -1.0
        pa, pb = pt(ev.point_a), pt(ev.point_b)
        tc.assertAlmostEqual(pa[k], ca[k] + sgn * ha[k], delta=DIST_TOL, msg="point_a " + ctx)
        tc.assertAlmostEqual(pb[k], cb[k] - sgn * hb[k], delta=DIST_TOL, msg="point_b " + ctx)
        for j in range(3):
            if j == k:
                continue
            for p, name in ((pa, "point_a"), (pb, "point_b")):
                for c, h in ((ca, ha), (cb, hb)):
                    tc.assertLessEqual(abs(p[j] - c[j]), h[j] + DIST_TOL,
                                       msg="%s outside the face overlap on axis %d %s" % (
                                           name, j, ctx))


def expected_level(ttc, dist, thr, margin_t=3e-3, margin_d=3e-3):
    """Level from thresholds {warning_time, critical_time, warning_distance,
    critical_distance}; None when too close to a threshold to decide."""
    for key in ("critical_time", "warning_time"):
        if abs(ttc - thr[key]) < margin_t:
            return None
    for key in ("critical_distance", "warning_distance"):
        if abs(dist - thr[key]) < margin_d:
            return None
    if ttc <= thr["critical_time"] or dist <= thr["critical_distance"]:
        return ContactEvent.CRITICAL
    if ttc <= thr["warning_time"] or dist <= thr["warning_distance"]:
        return ContactEvent.WARNING
    return ContactEvent.NOTICE


def events_for(msg, id_a, id_b):
    return [e for e in msg.events if e.id_a == id_a and e.id_b == id_b]


def checked_arrays(tc, msgs, t0, until):
    """The arrays of `msgs` stamped up to `until` s after t0, each first checked by
    check_array_basics (the first one past `until` is checked too, then the walk stops)."""
    for m in msgs:
        check_array_basics(tc, m)
        if (m.header.stamp - t0).to_sec() > until:
            return
        yield m


def check_array_basics(tc, msg, frame_id="world"):
    """Contract every ContactEventArray must satisfy."""
    tc.assertEqual(msg.header.frame_id, frame_id)
    tc.assertGreater(msg.header.stamp.to_sec(), 0.0)
    tc.assertIn(msg.status, (ContactEventArray.OK, ContactEventArray.DEGRADED))
    if msg.status == ContactEventArray.DEGRADED:
        tc.assertTrue(msg.status_details, "DEGRADED without status_details")
    else:
        tc.assertEqual(list(msg.status_details), [], "OK with status_details")
    seen = set()
    prev = -math.inf
    for ev in msg.events:
        tc.assertLess(ev.id_a, ev.id_b, "id_a < id_b violated: " + fmt_event(ev))
        pair = (ev.id_a, ev.id_b)
        tc.assertNotIn(pair, seen, "pair reported twice in one array: " + fmt_event(ev))
        seen.add(pair)
        tc.assertIn(ev.state, (BEGIN, ONGOING, END))
        if ev.state == END:
            tc.assertTrue(math.isinf(ev.time_to_contact) and ev.time_to_contact > 0,
                          "END must have ttc=+inf: " + fmt_event(ev))
            tc.assertEqual(ev.time_to_separation, 0.0, "END must have tts=0: " + fmt_event(ev))
        else:
            tc.assertGreaterEqual(ev.time_to_contact, 0.0, fmt_event(ev))
            tc.assertGreaterEqual(ev.time_to_separation, ev.time_to_contact, fmt_event(ev))
            tc.assertGreaterEqual(ev.distance, 0.0, fmt_event(ev))
            n = vnorm(pt(ev.normal))
            tc.assertAlmostEqual(n, 1.0, delta=1e-6, msg="normal not unit: " + fmt_event(ev))
        tc.assertGreaterEqual(ev.time_to_contact, prev,
                              "events not sorted by time_to_contact: %s" % [
                                  fmt_event(e) for e in msg.events])
        prev = ev.time_to_contact


def degraded_about(msg, word):
    """True when the array is DEGRADED and one of its status_details contains `word`."""
    return (msg.status == ContactEventArray.DEGRADED and
            any(word in d for d in msg.status_details))


def state_sequence(msgs, id_a, id_b):
    """One character per contacts message: '.' no event for the pair, else B/O/E."""
    out = []
    for m in msgs:
        evs = events_for(m, id_a, id_b)
        out.append("BOE"[evs[0].state] if evs else ".")
    return "".join(out)


class StaticBody(object):
    """An axis-aligned body at rest (e.g. a robot body under static tf), for the checks."""

    def __init__(self, body_id, label, centre, half):
        self.id = body_id
        self.label = label
        self.centre = tuple(centre)
        self.half = tuple(half)

    def state(self, stamp):
        return self.centre, (0.0, 0.0, 0.0)


class PlanarTransformed(object):
    """World-frame view of a Track published in a frame that is translated by `xyz` and
    yawed by a multiple of 90 degrees (`quarter_turns`) relative to world."""

    def __init__(self, track, xyz, quarter_turns):
        self.track = track
        self.id = track.id
        self.label = track.label
        self.xyz = xyz
        self.turns = quarter_turns % 4
        h = track.half
        self.half = (h[1], h[0], h[2]) if self.turns % 2 else h

    def _rot(self, v):
        x, y, z = v
        for _ in range(self.turns):
            x, y = -y, x
        return (x, y, z)

    def state(self, stamp):
        c, v = self.track.state(stamp)
        return vadd(self.xyz, self._rot(c)), self._rot(v)


def check_scene_events(tc, msg, bodies, horizon, ambiguity=5e-3, thresholds=None,
                       check_points=True):
    """Checks one ContactEventArray against the exact prediction for a scene of axis-aligned,
    translating bodies (Track or StaticBody, with .id, .label, .half, .state(stamp)).

    Every non-END event must be an expected pair with analytic numbers, and every expected
    pair must be reported unless it is within `ambiguity` s of the horizon or of separating.
    Robot-robot pairs are not expected. With `thresholds` (label -> {warning_time, ...},
    "robot" for robot bodies) the level is checked too: the stricter of the two labels'.
    Returns the number of events checked."""
    T = msg.header.stamp
    by_id = dict((b.id, b) for b in bodies)
    expected, optional = {}, set()
    ids = sorted(by_id)
    for i, ia in enumerate(ids):
        for ib in ids[i + 1:]:
            a, b = by_id[ia], by_id[ib]
            if a.label == "robot" and b.label == "robot":
                continue
            ca, va = a.state(T)
            cb, vb = b.state(T)
            exp = aabb_prediction(ca, a.half, va, cb, b.half, vb, horizon + ambiguity)
            if exp is None:
                continue
            if exp["ttc"] > horizon - ambiguity or exp["tts"] < ambiguity:
                optional.add((ia, ib))
                if exp["ttc"] > horizon:
                    continue
            exp["tts"] = min(exp["tts"], horizon)
            expected[(ia, ib)] = (exp, ca, a.half, cb, b.half)
    got = dict(((e.id_a, e.id_b), e) for e in msg.events if e.state != END)
    where = "T=%.4f" % T.to_sec()
    for pair in got:
        tc.assertIn(pair, expected, "%s unexpected event %s" % (where, fmt_event(got[pair])))
    for pair in expected:
        if pair not in optional:
            tc.assertIn(pair, got, "%s missing event for pair %s (expected %r); got %s" % (
                where, pair, expected[pair][0], [fmt_event(e) for e in msg.events]))
    for pair, ev in got.items():
        exp, ca, ha, cb, hb = expected[pair]
        tc.assertEqual((ev.label_a, ev.label_b), (by_id[pair[0]].label, by_id[pair[1]].label),
                       fmt_event(ev))
        check_face_contact(tc, ev, exp, ca, ha, cb, hb, where, check_points)
        if thresholds is not None:
            levels = [expected_level(exp["ttc"], exp["distance"], thresholds[by_id[i].label])
                      for i in pair]
            if None not in levels:
                tc.assertEqual(ev.level, max(levels), "%s level of %s" % (where, fmt_event(ev)))
    return len(got)


# ---------------------------------------------------------------------------------------------
# /diagnostics and general sanity of event numbers (reliability tests)

DIAG_NAME = "proximity_monitor: proximity monitor"  # "<node name>: <task>" (diagnostic_updater)


def diag_values(status):
    """key -> value (str) of a DiagnosticStatus; a repeated key keeps its values in a list
    under key + "[]" as well (e.g. "degraded")."""
    out = {}
    for kv in status.values:
        out.setdefault(kv.key + "[]", []).append(kv.value)
        out[kv.key] = kv.value
    return out


class DiagnosticsCollector(object):
    """Records the node's status from /diagnostics, with the wall-clock (monotonic) time of
    receipt, so it also works under simulated time."""

    def __init__(self, name=DIAG_NAME):
        import time
        from diagnostic_msgs.msg import DiagnosticArray
        self._time = time
        self.name = name
        self.lock = threading.Lock()
        self.statuses = []  # (monotonic receipt, header stamp rospy.Time, DiagnosticStatus)
        self.sub = rospy.Subscriber("/diagnostics", DiagnosticArray, self._on_diag,
                                    queue_size=100)

    def _on_diag(self, msg):
        now = self._time.monotonic()
        with self.lock:
            for st in msg.status:
                if st.name == self.name:
                    self.statuses.append((now, msg.header.stamp, st))

    def since(self, wall):
        """Statuses received at or after the monotonic time `wall`."""
        with self.lock:
            return [(s, st) for t, s, st in self.statuses if t >= wall]

    def latest(self):
        with self.lock:
            return self.statuses[-1][2] if self.statuses else None

    def wait_for(self, predicate, timeout, since=None):
        """Waits (wall clock) for a status received after `since` (monotonic) with
        predicate(status, values) true; returns it, or None."""
        deadline = self._time.monotonic() + timeout
        while True:
            for _, st in self.since(since if since is not None else 0.0):
                if predicate(st, diag_values(st)):
                    return st
            if self._time.monotonic() > deadline or rospy.is_shutdown():
                return None
            self._time.sleep(0.05)


def check_event_numbers(tc, msg, horizon, what=""):
    """No NaN anywhere, and times within [0, horizon] (END: +inf / 0) in every event."""
    eps = 1e-6
    for ev in msg.events:
        ctx = "%s T=%.4f %s" % (what, msg.header.stamp.to_sec(), fmt_event(ev))
        numbers = [ev.time_to_contact, ev.time_to_separation, ev.distance, ev.closing_speed]
        numbers += list(pt(ev.point_a)) + list(pt(ev.point_b)) + list(pt(ev.normal))
        tc.assertFalse(any(math.isnan(x) for x in numbers), "NaN in " + ctx)
        if ev.state == END:
            tc.assertEqual(ev.time_to_contact, math.inf, "END ttc " + ctx)
            tc.assertEqual(ev.time_to_separation, 0.0, "END tts " + ctx)
            continue
        tc.assertTrue(0.0 <= ev.time_to_contact <= horizon + eps, "ttc out of [0, H]: " + ctx)
        tc.assertTrue(ev.time_to_contact <= ev.time_to_separation <= horizon + eps,
                      "tts out of [ttc, H]: " + ctx)
        tc.assertTrue(0.0 <= ev.distance < 1e6 and math.isfinite(ev.closing_speed),
                      "distance / closing speed: " + ctx)


def find_node_binary(node="proximity_monitor"):
    """The path of this package's executable `node`, None if it is not built."""
    from roslib.packages import find_node
    found = find_node("workspace_proximity", node)
    return found[0] if found else None


def start_node_binary(binary, name, args, params):
    """Starts `binary` as node `name` (without robot_description) with the command-line private
    parameters `args` ("_key:=value") after setting `params` under /name on the server; the
    Popen, stdout and stderr piped."""
    import subprocess
    for key, value in params.items():
        rospy.set_param("/%s/%s" % (name, key), value)
    cmd = [binary, "__name:=" + name, "_use_robot_description:=false"] + list(args)
    return subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            env=dict(os.environ))


def run_for(proc, seconds):
    """Lets the node run for `seconds`, then stops it (SIGINT, killed if not gone in 10 s).
    Returns (was still running, stdout + stderr)."""
    import signal
    import subprocess
    time.sleep(seconds)
    running = proc.poll() is None
    if running:
        proc.send_signal(signal.SIGINT)
    try:
        out, err = proc.communicate(timeout=10)
    except subprocess.TimeoutExpired:
        proc.kill()
        out, err = proc.communicate()
    return running, out.decode(errors="replace") + err.decode(errors="replace")


# ---------------------------------------------------------------------------------------------
# Speed and separation monitoring (ISO/TS 15066): the formula written out, and the outputs.

SSM_DEFAULTS = {"reaction_time": 0.1, "stopping_time": 0.3, "intrusion_distance": 0.1,
                "sensor_uncertainty": 0.1, "robot_uncertainty": 0.02, "robot_max_speed": 1.0}


def ssm_required(v_h, v_r, p=SSM_DEFAULTS):
    """S_p(v_r) = v_h (T_r + T_s) + v_r T_r + v_r T_s / 2 + C + Z_d + Z_r, m."""
    return (v_h * (p["reaction_time"] + p["stopping_time"]) + v_r * p["reaction_time"] +
            v_r * p["stopping_time"] / 2.0 + p["intrusion_distance"] + p["sensor_uncertainty"] +
            p["robot_uncertainty"])


def ssm_scale(d, v_h, p=SSM_DEFAULTS):
    """min(1, v_allowed / v_max) with v_allowed the largest v_r >= 0 with S_p(v_r) <= d."""
    spare = d - ssm_required(v_h, 0.0, p)
    per_speed = p["reaction_time"] + p["stopping_time"] / 2.0
    return min(1.0, max(0.0, spare / per_speed / p["robot_max_speed"]))


class SsmCollector(object):
    """Records safety_status, speed_scale and speed_override in order of receipt."""

    def __init__(self):
        from std_msgs.msg import Float64, Int64
        self.lock = threading.Lock()
        self.status = []     # SafetyStatus
        self.scale = []      # float
        self.override = []   # int
        self.subs = [
            rospy.Subscriber("safety_status", SafetyStatus, self._on_status, queue_size=500),
            rospy.Subscriber("speed_scale", Float64, self._on_scale, queue_size=500),
            rospy.Subscriber("speed_override", Int64, self._on_override, queue_size=500)]

    def _on_status(self, msg):
        with self.lock:
            self.status.append(msg)

    def _on_scale(self, msg):
        with self.lock:
            self.scale.append(msg.data)

    def _on_override(self, msg):
        with self.lock:
            self.override.append(msg.data)

    def connected(self):
        return all(s.get_num_connections() >= 1 for s in self.subs)

    def statuses(self, since=None):
        with self.lock:
            return [m for m in self.status if since is None or m.header.stamp >= since]

    def sequences(self):
        with self.lock:
            return list(self.status), list(self.scale), list(self.override)


def aligned(a, b, same, max_shift=5, min_overlap=20):
    """The shift k (|k| <= max_shift) for which same(a[i], b[i + k]) holds for every i of the
    overlap (at least min_overlap long), or None. Topics published together every cycle are
    received in order, but their first messages may differ by a cycle or two."""
    for k in sorted(range(-max_shift, max_shift + 1), key=abs):
        pairs = [(a[i], b[i + k]) for i in range(len(a)) if 0 <= i + k < len(b)]
        if len(pairs) >= min_overlap and all(same(x, y) for x, y in pairs):
            return k
    return None


def startup_refusals(started, timeout=8.0):
    """For nodes started with bad parameters: `started` holds (name, words, proc) for each
    case; every proc must exit within `timeout` s with a non-zero status (not by a signal), and
    its stderr must contain one of `words` (the parameter it names). Returns the failures as
    lines (empty: every case refused as it should)."""
    import subprocess
    failures = []
    for name, words, proc in started:
        try:
            _, err = proc.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            proc.kill()
            _, err = proc.communicate()
            failures.append("%s: still running after %g s" % (name, timeout))
            continue
        err = err.decode(errors="replace")
        if proc.returncode == 0:
            failures.append("%s: exit status 0" % name)
        elif proc.returncode < 0:
            failures.append("%s: killed by signal %d: %s" % (name, -proc.returncode, err[-500:]))
        if not any(w in err for w in words):
            failures.append("%s: stderr names none of %r: %r" % (name, words, err[-500:]))
    return failures


class ContactStatusRecorder(object):
    """Records the contacts and safety_status a monitor under namespace `ns` publishes."""

    def __init__(self, ns, queue_size=500):
        self.lock = threading.Lock()
        self.contacts, self.status = [], []
        self.subs = [rospy.Subscriber(ns + "/contacts", ContactEventArray, self._into(self.contacts),
                                      queue_size=queue_size),
                     rospy.Subscriber(ns + "/safety_status", SafetyStatus, self._into(self.status),
                                      queue_size=queue_size)]

    def _into(self, where):
        def cb(msg):
            with self.lock:
                where.append(msg)
        return cb

    def posed(self):
        """The monitor has published contacts and the last ones name no robot body without a
        pose (its tf listener has the robot's transforms)."""
        with self.lock:
            return bool(self.contacts) and not any("robot body" in d
                                                   for d in self.contacts[-1].status_details)

    def since(self, t):
        """Contacts and statuses stamped at or after t."""
        with self.lock:
            return ([m for m in self.contacts if m.header.stamp >= t],
                    [m for m in self.status if m.header.stamp >= t])

    def between(self, t0, t1):
        """Contacts and statuses stamped in [t0, t1]."""
        with self.lock:
            return ([m for m in self.contacts if t0 <= m.header.stamp <= t1],
                    [m for m in self.status if t0 <= m.header.stamp <= t1])
