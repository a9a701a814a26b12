#!/usr/bin/env python3
"""Simulated sensors for the workspace_proximity demo and the scene rostests (issue 23).

Ray-casts the scene that the scene simulator (or a test) publishes as true boxes, together with
the robot's links, into what a mounted depth camera and a floor laser scanner would return:

  * ~camera_topic (sensor_msgs/PointCloud2): an organized cloud, ~width x ~height, float32 x, y,
    z in the camera's optical frame (z forward, x right, y down), NaN where a ray has no return
    (nothing within ~range_max, or a random dropout); Gaussian noise along each ray;
  * ~scan_topic (sensor_msgs/LaserScan): ~beams beams over ~scan_fov in a horizontal plane at
    the scanner's height, inf where nothing is within ~scan_range_max;
  * tf_static: ~frame -> <camera_frame> (x forward, z up, from ~camera_position looking at
    ~camera_target), <camera_frame> -> <camera_frame>_optical, ~frame -> <scan_frame>.

What is seen: the floor (z = 0, camera only), every box of ~objects_topic
(workspace_proximity/TrackedBoxArray in ~frame; moved along its twist to the frame's stamp) and
the robot's links: the collision shapes (box, cylinder, sphere) of the URDF in
~robot_description_param, posed from tf. A frame is stamped with the robot's newest pose on tf
(the stamp the links were rendered at), so the robot's points are where the self-filter expects
them; without any robot pose on tf yet, nothing is published.

Vectorized with numpy: the camera's rays are computed once (it does not move); each shape is
cast only against the pixels inside its projected bounding sphere.

Parameters (private), lengths in m, angles in rad:
  ~rate (15.0)                   Hz of both sensors
  ~frame ("world")               fixed frame
  ~objects_topic ("tracked_objects")  the true boxes to render
  ~robot_description_param ("robot_description")  "" for no robot
  ~seed (1)                      random generator seed (noise and dropout)
  ~camera (true)                 publish the depth camera
  ~camera_topic ("sim_camera_points": one name without "/", so that it can key cloud_tracker's
                                 ~sensor_fov in a YAML file), ~camera_frame ("sim_camera_link")
  ~camera_position ([3.6, 2.4, 2.4]), ~camera_target ([0.0, 0.0, 0.6])
  ~width (320), ~height (240)    pixels (640 x 480 works, at a lower rate; see docs/perception.md)
  ~hfov (1.0123)                 horizontal field of view (58 deg); vertical from the aspect
  ~range_min (0.3), ~range_max (6.0)
  ~range_noise (0.005)           standard deviation of the noise along each ray
  ~dropout (0.02)                probability that a pixel returns NaN
  ~scanner (true)                publish the floor laser scanner
  ~scan_topic ("sim_scan"), ~scan_frame ("sim_scan_link")
  ~scan_position ([3.6, -1.0, 0.2]), ~scan_yaw (3.14159)
  ~beams (1000), ~scan_fov (4.712)  beams spread over the field of view, centred ahead
  ~scan_range_min (0.05), ~scan_range_max (10.0), ~scan_noise (0.01), ~scan_dropout (0.0)
Topics out, besides the sensors': ~true_boxes (visualization_msgs/MarkerArray): the rendered
boxes, dimmed, for comparison with what the front end makes of them (only when someone listens).
Topics in: ~objects_topic, tf; ~pause_camera and ~pause_scanner (std_msgs/Bool: true silences
that sensor, for the fail-safe tests).
"""

import math
import sys
import threading
import time
import xml.etree.ElementTree as ET

import numpy as np
import rospy
import tf2_ros
from geometry_msgs.msg import TransformStamped
from sensor_msgs.msg import LaserScan, PointCloud2, PointField
from std_msgs.msg import Bool
from visualization_msgs.msg import Marker, MarkerArray

from workspace_proximity.msg import TrackedBoxArray


# ---------------------------------------------------------------------------------------------
# Rotations.


def rot_from_quat(x, y, z, w):
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def rot_from_rpy(r, p, y):
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


def quat_from_rot(m):
    """(x, y, z, w) of a rotation matrix (Shepperd's method)."""
    t = np.trace(m)
    if t > 0:
        s = 2.0 * math.sqrt(t + 1.0)
        return ((m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s, 0.25 * s)
    i = int(np.argmax(np.diag(m)))
    j, k = (i + 1) % 3, (i + 2) % 3
    s = 2.0 * math.sqrt(1.0 + m[i, i] - m[j, j] - m[k, k])
    q = [0.0, 0.0, 0.0, 0.0]
    q[i] = 0.25 * s
    q[j] = (m[j, i] + m[i, j]) / s
    q[k] = (m[k, i] + m[i, k]) / s
    q[3] = (m[k, j] - m[j, k]) / s
    return tuple(q)


def look_at(position, target):
    """Rotation of a body frame (x forward, z up) at `position` looking at `target`."""
    x = np.asarray(target, float) - np.asarray(position, float)
    x /= np.linalg.norm(x)
    y = np.cross([0.0, 0.0, 1.0], x)
    if np.linalg.norm(y) < 1e-6:
        y = np.array([0.0, 1.0, 0.0])
    y /= np.linalg.norm(y)
    return np.column_stack([x, y, np.cross(x, y)])


# The optical frame (z forward, x right, y down) in the body frame (x forward, z up).
OPTICAL_IN_BODY = np.array([[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])


# ---------------------------------------------------------------------------------------------
# Shapes and ray casting. A shape: (kind, half sizes, rotation R, centre c) in the fixed frame;
# kinds: 'box' (half extents), 'cylinder' (radius, half length, axis local z), 'sphere' (radius).


def cast(kind, half, rot, centre, origin, dirs):
    """Distance along each unit ray (origin + t dirs, dirs (N, 3)) to its first entry into the
    shape, inf where it misses (or starts inside)."""
    o = rot.T @ (np.asarray(origin, float) - centre)   # the origin in the shape's frame
    d = dirs @ rot                                      # (R^T d) for every row
    inf = np.full(d.shape[0], np.inf)
    with np.errstate(divide='ignore', invalid='ignore'):
        if kind == 'box':
            # Slabs, axis by axis on flat columns (faster than (N, 3) reductions); a ray
            # parallel to a slab gets a tiny component instead of 0 (no 0 * inf).
            tnear = np.full(d.shape[0], -np.inf)
            tfar = np.full(d.shape[0], np.inf)
            for i in range(3):
                di = d[:, i]
                di = np.where(np.abs(di) < 1e-12, 1e-12, di)
                t1 = (-half[i] - o[i]) / di
                t2 = (half[i] - o[i]) / di
                np.maximum(tnear, np.minimum(t1, t2), out=tnear)
                np.minimum(tfar, np.maximum(t1, t2), out=tfar)
            return np.where((tnear <= tfar) & (tnear > 0.0), tnear, inf)
        if kind == 'sphere':
            b = d @ o
            c = o @ o - half[0] * half[0]
            disc = b * b - c
            t = -b - np.sqrt(disc)
            return np.where((disc >= 0.0) & (t > 0.0), t, inf)
        # Cylinder: the side, then the two caps.
        r, hl = half[0], half[1]
        a = d[:, 0] ** 2 + d[:, 1] ** 2
        b = d[:, 0] * o[0] + d[:, 1] * o[1]
        c = o[0] ** 2 + o[1] ** 2 - r * r
        disc = b * b - a * c
        ts = (-b - np.sqrt(disc)) / a
        zs = o[2] + ts * d[:, 2]
        best = np.where((disc >= 0.0) & (a > 0.0) & (ts > 0.0) & (np.abs(zs) <= hl), ts, inf)
        for cap in (-hl, hl):
            tc = (cap - o[2]) / d[:, 2]
            xc, yc = o[0] + tc * d[:, 0], o[1] + tc * d[:, 1]
            ok = (tc > 0.0) & (xc * xc + yc * yc <= r * r)
            best = np.where(ok & (tc < best), tc, best)
        return best


def parse_collisions(xml_text):
    """[(link, kind, half sizes, rotation in link, offset in link)] from a URDF's collisions."""
    shapes = []
    for link in ET.fromstring(xml_text).findall('link'):
        for col in link.findall('collision'):
            origin = col.find('origin')
            xyz = [float(v) for v in origin.get('xyz', '0 0 0').split()] if origin is not None else [0.0] * 3
            rpy = [float(v) for v in origin.get('rpy', '0 0 0').split()] if origin is not None else [0.0] * 3
            geom = col.find('geometry')
            if geom is None:
                continue
            box, cyl, sph = geom.find('box'), geom.find('cylinder'), geom.find('sphere')
            if box is not None:
                shape = ('box', 0.5 * np.array([float(v) for v in box.get('size').split()]))
            elif cyl is not None:
                shape = ('cylinder', np.array([float(cyl.get('radius')), 0.5 * float(cyl.get('length'))]))
            elif sph is not None:
                shape = ('sphere', np.array([float(sph.get('radius'))]))
            else:
                rospy.logwarn('sensor_simulator: link %s: a collision shape other than box, cylinder '
                              'or sphere is not rendered', link.get('name'))
                continue
            shapes.append((link.get('name'), shape[0], shape[1], rot_from_rpy(*rpy), np.array(xyz)))
    return shapes


# ---------------------------------------------------------------------------------------------


class Camera(object):
    """A pinhole depth camera fixed in the cell: its unit rays are computed once."""

    def __init__(self, position, rot_body, width, height, hfov, range_min, range_max):
        self.position = np.asarray(position, float)
        self.rot_optical = rot_body @ OPTICAL_IN_BODY      # optical frame in the fixed frame
        self.width, self.height = width, height
        self.fx = 0.5 * width / math.tan(0.5 * hfov)
        self.cx, self.cy = 0.5 * (width - 1), 0.5 * (height - 1)
        u, v = np.meshgrid(np.arange(width, dtype=float), np.arange(height, dtype=float))
        rays = np.stack([(u - self.cx) / self.fx, (v - self.cy) / self.fx, np.ones_like(u)], axis=-1)
        norm = np.linalg.norm(rays, axis=-1, keepdims=True)
        self.rays_optical = (rays / norm)                 # (H, W, 3), unit, optical frame
        self.rays_world = self.rays_optical @ self.rot_optical.T
        self.range_min, self.range_max = range_min, range_max
        # The floor (z = 0) does not move: its distances are computed once.
        dz = self.rays_world[..., 2]
        with np.errstate(divide='ignore'):
            tf = -self.position[2] / dz
        self.floor = np.where((dz < 0.0) & (tf > 0.0), tf, np.inf)

    def pixel_window(self, kind, half, rot, centre):
        """(v0, v1, u0, u1): the pixels whose rays may meet the shape: those inside the
        projection of its bounding box (the whole image when that reaches behind the camera)."""
        if kind == 'box':
            ext = half
        elif kind == 'cylinder':
            ext = np.array([half[0], half[0], half[1]])
        else:
            ext = np.array([half[0], half[0], half[0]])
        corners = (np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]) * ext) @ rot.T
        c = (corners + (centre - self.position)) @ self.rot_optical     # optical frame, (8, 3)
        if np.any(c[:, 2] <= 1e-3):
            return 0, self.height, 0, self.width
        us = self.fx * c[:, 0] / c[:, 2] + self.cx
        vs = self.fx * c[:, 1] / c[:, 2] + self.cy
        u0, u1 = max(0, int(math.floor(us.min()))), min(self.width, int(math.ceil(us.max())) + 1)
        v0, v1 = max(0, int(math.floor(vs.min()))), min(self.height, int(math.ceil(vs.max())) + 1)
        return v0, v1, u0, u1

    def render(self, shapes):
        depth = self.floor.copy()
        for kind, half, rot, centre in shapes:
            v0, v1, u0, u1 = self.pixel_window(kind, half, rot, centre)
            if v0 >= v1 or u0 >= u1:
                continue
            window = self.rays_world[v0:v1, u0:u1].reshape(-1, 3)
            t = cast(kind, half, rot, centre, self.position, window).reshape(v1 - v0, u1 - u0)
            np.minimum(depth[v0:v1, u0:u1], t, out=depth[v0:v1, u0:u1])
        return depth


class SensorSimulator(object):
    def __init__(self):
        p = lambda name, default: rospy.get_param('~' + name, default)  # noqa: E731
        self.frame = p('frame', 'world')
        self.rate = float(p('rate', 15.0))
        self.rng = np.random.default_rng(int(p('seed', 1)))
        self.lock = threading.Lock()
        self.objects = None
        self.paused = {'camera': False, 'scanner': False}

        self.links = []
        desc_param = p('robot_description_param', 'robot_description')
        if desc_param:
            xml_text = None
            while not rospy.is_shutdown() and xml_text is None:
                try:
                    xml_text = rospy.get_param(desc_param)
                except KeyError:
                    rospy.logwarn_throttle(5.0, 'sensor_simulator: waiting for parameter %s'
                                           % rospy.resolve_name(desc_param))
                    rospy.sleep(0.2)
            if xml_text is not None:
                self.links = parse_collisions(xml_text)
        self.tf_buffer = tf2_ros.Buffer(rospy.Duration(10.0))
        self.tf_listener = tf2_ros.TransformListener(self.tf_buffer)

        statics = []
        self.camera = None
        if p('camera', True):
            position = [float(v) for v in p('camera_position', [3.6, 2.4, 2.4])]
            target = [float(v) for v in p('camera_target', [0.0, 0.0, 0.6])]
            width, height = int(p('width', 320)), int(p('height', 240))
            if not (8 <= width <= 4096 and 8 <= height <= 4096):
                raise ValueError('~width and ~height must be 8 to 4096 pixels')
            body = look_at(position, target)
            self.camera = Camera(position, body, width, height, float(p('hfov', math.radians(58.0))),
                                 float(p('range_min', 0.3)), float(p('range_max', 6.0)))
            self.range_noise, self.dropout = float(p('range_noise', 0.005)), float(p('dropout', 0.02))
            self.camera_frame = p('camera_frame', 'sim_camera_link')
            self.optical_frame = self.camera_frame + '_optical'
            statics.append(make_tf(self.frame, self.camera_frame, position, quat_from_rot(body)))
            statics.append(make_tf(self.camera_frame, self.optical_frame, (0.0, 0.0, 0.0),
                                   quat_from_rot(OPTICAL_IN_BODY)))
            self.cloud_pub = rospy.Publisher(p('camera_topic', 'sim_camera_points'), PointCloud2,
                                             queue_size=2)
            self.cloud = PointCloud2()
            self.cloud.header.frame_id = self.optical_frame
            self.cloud.height, self.cloud.width = height, width
            self.cloud.fields = [PointField(name=n, offset=4 * i, datatype=PointField.FLOAT32, count=1)
                                 for i, n in enumerate('xyz')]
            self.cloud.is_bigendian = False
            self.cloud.point_step = 12
            self.cloud.row_step = 12 * width
            self.cloud.is_dense = False
            rospy.Subscriber('~pause_camera', Bool, lambda m: self.pause('camera', m.data), queue_size=1)
        self.scanner = None
        if p('scanner', True):
            position = np.array([float(v) for v in p('scan_position', [3.6, -1.0, 0.2])])
            yaw = float(p('scan_yaw', math.pi))
            beams, fov = int(p('beams', 1000)), float(p('scan_fov', 1.5 * math.pi))
            if not (2 <= beams <= 100000) or not (0.0 < fov <= 2.0 * math.pi):
                raise ValueError('~beams must be 2 to 100000 and ~scan_fov in (0, 2 pi]')
            self.scan = LaserScan()
            self.scan.header.frame_id = p('scan_frame', 'sim_scan_link')
            self.scan.angle_min, self.scan.angle_increment = -0.5 * fov, fov / (beams - 1)
            self.scan.angle_max = self.scan.angle_min + (beams - 1) * self.scan.angle_increment
            self.scan.scan_time = 1.0 / self.rate
            self.scan.range_min = float(p('scan_range_min', 0.05))
            self.scan.range_max = float(p('scan_range_max', 10.0))
            self.scan_noise, self.scan_dropout = float(p('scan_noise', 0.01)), float(p('scan_dropout', 0.0))
            angles = yaw + self.scan.angle_min + self.scan.angle_increment * np.arange(beams)
            self.scanner = (position, np.column_stack([np.cos(angles), np.sin(angles), np.zeros(beams)]))
            statics.append(make_tf(self.frame, self.scan.header.frame_id, position,
                                   (0.0, 0.0, math.sin(0.5 * yaw), math.cos(0.5 * yaw))))
            self.scan_pub = rospy.Publisher(p('scan_topic', 'sim_scan'), LaserScan, queue_size=2)
            rospy.Subscriber('~pause_scanner', Bool, lambda m: self.pause('scanner', m.data), queue_size=1)
        if statics:
            self.static_broadcaster = tf2_ros.StaticTransformBroadcaster()
            self.static_broadcaster.sendTransform(statics)
        rospy.Subscriber(p('objects_topic', 'tracked_objects'), TrackedBoxArray, self.on_objects,
                         queue_size=1, tcp_nodelay=True)
        self.truth_pub = rospy.Publisher('~true_boxes', MarkerArray, queue_size=2)
        self.frames, self.busy = 0, 0.0

    def pause(self, which, value):
        self.paused[which] = bool(value)
        rospy.loginfo('sensor_simulator: %s %s', which, 'silenced' if value else 'resumed')

    def on_objects(self, msg):
        if msg.header.frame_id and msg.header.frame_id.lstrip('/') != self.frame:
            rospy.logwarn_throttle(5.0, 'sensor_simulator: objects in %s, not %s: not rendered'
                                   % (msg.header.frame_id, self.frame))
            return
        with self.lock:
            self.objects = msg

    def scene(self):
        """(stamp, shapes): the robot's links at their newest pose on tf, and the boxes moved to
        that stamp; None while the robot has no pose."""
        shapes, stamp = [], rospy.Time(0)
        poses = {}
        for link, kind, half, rot, offset in self.links:
            if link not in poses:
                try:
                    t = self.tf_buffer.lookup_transform(self.frame, link, rospy.Time(0))
                except tf2_ros.TransformException:
                    return None
                q, v = t.transform.rotation, t.transform.translation
                poses[link] = (rot_from_quat(q.x, q.y, q.z, q.w), np.array([v.x, v.y, v.z]))
                stamp = max(stamp, t.header.stamp)
            r, c = poses[link]
            shapes.append((kind, half, r @ rot, r @ offset + c))
        if stamp == rospy.Time(0):
            stamp = rospy.Time.now()
        with self.lock:
            objects = self.objects
        if objects is not None:
            for box in objects.boxes:
                dt = (stamp - (objects.header.stamp if objects.header.stamp != rospy.Time(0) else stamp)).to_sec()
                q, pos, v = box.pose.orientation, box.pose.position, box.twist.linear
                if q.x == 0.0 and q.y == 0.0 and q.z == 0.0 and q.w == 0.0:
                    q.w = 1.0
                half = 0.5 * np.array([box.dimensions.x, box.dimensions.y, box.dimensions.z])
                if not np.all(half > 0.0):
                    continue
                shapes.append(('box', half, rot_from_quat(q.x, q.y, q.z, q.w),
                               np.array([pos.x + v.x * dt, pos.y + v.y * dt, pos.z + v.z * dt])))
        return stamp, shapes

    def step(self):
        start = time.perf_counter()
        scene = self.scene()
        if scene is None:
            rospy.logwarn_throttle(5.0, 'sensor_simulator: the robot has no pose on tf yet: nothing published')
            return
        stamp, shapes = scene
        if self.camera is not None and not self.paused['camera']:
            cam = self.camera
            t = cam.render(shapes)
            n = t.shape[0] * t.shape[1]
            t = t + self.range_noise * self.rng.standard_normal(t.shape)
            bad = (t > cam.range_max) | (t < cam.range_min) | (self.rng.random(t.shape) < self.dropout)
            t[bad] = np.nan
            xyz = (cam.rays_optical * t[..., None]).astype(np.float32)
            self.cloud.header.stamp = stamp
            self.cloud.data = xyz.tobytes()
            assert len(self.cloud.data) == 12 * n
            self.cloud_pub.publish(self.cloud)
        if self.scanner is not None and not self.paused['scanner']:
            origin, dirs = self.scanner
            best = np.full(dirs.shape[0], np.inf)
            for kind, half, rot, centre in shapes:
                np.minimum(best, cast(kind, half, rot, centre, origin, dirs), out=best)
            best = best + self.scan_noise * self.rng.standard_normal(best.shape)
            best[(best > self.scan.range_max) | (self.rng.random(best.shape) < self.scan_dropout)] = np.inf
            best[best < self.scan.range_min] = np.nan
            self.scan.header.stamp = stamp
            self.scan.ranges = best.astype(np.float32).tolist()
            self.scan_pub.publish(self.scan)
        if self.truth_pub.get_num_connections() > 0:
            self.publish_truth(stamp, shapes[len(self.links):])
        self.frames += 1
        self.busy += time.perf_counter() - start
        if self.frames % int(max(1, 10 * self.rate)) == 0:
            rospy.loginfo('sensor_simulator: %d frames, %.1f ms each on average (%.0f Hz possible)',
                          self.frames, 1e3 * self.busy / self.frames, self.frames / max(self.busy, 1e-9))

    def publish_truth(self, stamp, boxes):
        out = MarkerArray()
        clear = Marker()
        clear.action = Marker.DELETEALL
        out.markers.append(clear)
        for i, (_, half, rot, centre) in enumerate(boxes):
            m = Marker()
            m.header.frame_id, m.header.stamp = self.frame, stamp
            m.ns, m.id, m.type, m.action = 'true boxes', i, Marker.CUBE, Marker.ADD
            m.pose.position.x, m.pose.position.y, m.pose.position.z = (float(v) for v in centre)
            (m.pose.orientation.x, m.pose.orientation.y, m.pose.orientation.z,
             m.pose.orientation.w) = (float(v) for v in quat_from_rot(rot))
            m.scale.x, m.scale.y, m.scale.z = (float(2.0 * v) for v in half)
            m.color.r, m.color.g, m.color.b, m.color.a = 0.6, 0.7, 0.9, 0.15
            out.markers.append(m)
        self.truth_pub.publish(out)

    def spin(self):
        rate = rospy.Rate(self.rate)
        while not rospy.is_shutdown():
            self.step()
            try:
                rate.sleep()
            except rospy.ROSInterruptException:
                break


def make_tf(parent, child, trans, rot):
    t = TransformStamped()
    t.header.stamp = rospy.Time.now()
    t.header.frame_id = parent
    t.child_frame_id = child
    t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = (float(v) for v in trans)
    (t.transform.rotation.x, t.transform.rotation.y, t.transform.rotation.z,
     t.transform.rotation.w) = (float(v) for v in rot)
    return t


def main():
    rospy.init_node('sensor_simulator')
    try:
        sim = SensorSimulator()
    except (ValueError, ET.ParseError, AttributeError, TypeError) as e:
        rospy.logfatal('sensor_simulator: %s', e)
        return 1
    sim.spin()
    return 0


if __name__ == '__main__':
    try:
        sys.exit(main())
    except rospy.ROSInterruptException:
        pass
