#!/usr/bin/env python3
"""Writes test/foreign/fixtures/walk_<name>.{bin,txt}: a sequence of detection messages of two
people walking past each other, serialized by genpy (ROS's own Python serializer) from the
stored definitions (make_fixtures.py's generator), for test_foreign_detections.

Scene (every 0.1 s from 20.0 s, 30 frames, frame 'camera' = the fixed frame):
  A from (-3.0, 0.5, 0.9) at (1.0, 0.0, 0.0) m/s, B from (3.0, -0.5, 0.9) at (-0.8, 0.2, 0.0).
The detections' order alternates every frame, and vision_msgs' results[0].id is overloaded as a
user's "track id" that swaps between the two people every frame (it must not be trusted).

<name>.bin: for each frame a little-endian uint32 length, then the serialized message.
<name>.txt: "type <type> <md5>", then per frame "frame <secs> <nsecs> <count>" and one line per
person "truth <name> <px> <py> <pz> <vx> <vy> <vz>" (where it is at the frame's stamp).

Run with /usr/bin/python3; rerun after changing foreign_msgs/ or this scene.
"""

import io
import os
import shutil
import struct

import genpy

import make_fixtures as mf

PEOPLE = [('A', (-3.0, 0.5, 0.9), (1.0, 0.0, 0.0)), ('B', (3.0, -0.5, 0.9), (-0.8, 0.2, 0.0))]
FRAMES = 30
PERIOD = 0.1


def at(p0, v, t):
    return tuple(p + vi * t for p, vi in zip(p0, v))


def stamp(msg, k):
    msg.header.stamp = genpy.Time(20, k * 100000000)
    msg.header.frame_id = 'camera'
    return msg


def detections3d(m, g, k, order):
    msg = stamp(m.Detection3DArray(), k)
    for i in order:
        name, p0, v = PEOPLE[i]
        d = stamp(m.Detection3D(), k)
        # A user's overloaded id: swaps between the people every frame.
        d.results.append(m.ObjectHypothesisWithPose(id=(i + k) % 2 + 1, score=0.9))
        d.bbox.center.position = g.Point(*at(p0, v, k * PERIOD))
        d.bbox.center.orientation.w = 1.0
        d.bbox.size = g.Vector3(0.5, 0.5, 1.7)
        msg.detections.append(d)
    return msg


def jsk(m, g, k, order):
    msg = stamp(m.BoundingBoxArray(), k)
    for i in order:
        name, p0, v = PEOPLE[i]
        b = stamp(m.BoundingBox(), k)
        b.pose.position = g.Point(*at(p0, v, k * PERIOD))
        b.pose.orientation.w = 1.0
        b.dimensions = g.Vector3(0.6, 0.6, 0.0)  # no height: the label's default applies
        b.value = 0.5
        b.label = (i + k) % 2
        msg.boxes.append(b)
    return msg


def markers(m, g, k, order):
    # Per person a CYLINDER (a detection) with an rviz id that swaps, then a TEXT_VIEW_FACING
    # label and an ARROW (not detections); a DELETE of another marker at the end.
    msg = m.MarkerArray()
    for i in order:
        name, p0, v = PEOPLE[i]
        for kind in (m.Marker.CYLINDER, m.Marker.TEXT_VIEW_FACING, m.Marker.ARROW):
            mk = stamp(m.Marker(), k)
            mk.ns = 'people'
            mk.id = (i + k) % 2 + 10 * kind
            mk.type = kind
            mk.action = m.Marker.ADD
            mk.pose.position = g.Point(*at(p0, v, k * PERIOD))
            mk.pose.orientation.w = 1.0
            mk.scale = g.Vector3(0.5, 0.5, 1.7)
            mk.color.a = 1.0
            if kind == m.Marker.TEXT_VIEW_FACING:
                mk.text = name
            if kind == m.Marker.ARROW:
                mk.points = [g.Point(0, 0, 0), g.Point(1, 0, 0)]
            msg.markers.append(mk)
    gone = stamp(m.Marker(), k)
    gone.action = m.Marker.DELETE
    gone.type = m.Marker.CUBE
    gone.pose.orientation.w = 1.0
    msg.markers.append(gone)
    return msg


def poses(m, g, k, order):
    msg = stamp(g.PoseArray(), k)
    for i in order:
        name, p0, v = PEOPLE[i]
        msg.poses.append(g.Pose(position=g.Point(*at(p0, v, k * PERIOD)),
                                orientation=g.Quaternion(0, 0, 0, 1)))
    return msg


# name, package (None: Debian's own Python), builder
CASES = [('walk_detections3d', 'vision_msgs', detections3d),
         ('walk_jsk', 'jsk_recognition_msgs', jsk),
         ('walk_markers', None, markers),
         ('walk_poses', None, poses)]


def main():
    import geometry_msgs.msg as g
    for name, package, build in CASES:
        root = mf.generate({})
        try:
            if package is None:
                import visualization_msgs.msg as m
            else:
                m = mf.load(root, package)
            data = io.BytesIO()
            lines = []
            for k in range(FRAMES):
                order = [0, 1] if k % 2 == 0 else [1, 0]
                msg = build(m, g, k, order)
                nsecs = k * 100000000
                buff = io.BytesIO()
                msg.serialize(buff)
                data.write(struct.pack('<I', len(buff.getvalue())))
                data.write(buff.getvalue())
                if k == 0:
                    lines.append('type %s %s' % (msg._type, msg._md5sum))
                lines.append('frame 20 %d %d' % (nsecs, len(order)))
                for pname, p0, v in PEOPLE:
                    lines.append('truth %s %r %r %r %r %r %r' % ((pname,) + at(p0, v, k * PERIOD) + v))
        finally:
            shutil.rmtree(root)
        with open(os.path.join(mf.OUT, name + '.bin'), 'wb') as f:
            f.write(data.getvalue())
        with open(os.path.join(mf.OUT, name + '.txt'), 'w') as f:
            f.write('\n'.join(lines) + '\n')
        print(name, len(data.getvalue()), 'bytes')


if __name__ == '__main__':
    main()
