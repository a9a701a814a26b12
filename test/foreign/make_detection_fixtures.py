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


def detections3d(m, g, k, order):
    msg = mf.stamped(m.Detection3DArray(), 20, 'camera')
    for i in order:
        name, p0, v = PEOPLE[i]
        d = mf.stamped(m.Detection3D(), 20, 'camera')
        # A user's overloaded id: swaps between the people every frame.
        d.results.append(m.ObjectHypothesisWithPose(id=(i + k) % 2 + 1, score=0.9))
        d.bbox.center.position = g.Point(*at(p0, v, k * PERIOD))
        d.bbox.center.orientation.w = 1.0
        d.bbox.size = g.Vector3(0.5, 0.5, 1.7)
        msg.detections.append(d)
    return msg


def jsk(m, g, k, order):
    msg = mf.stamped(m.BoundingBoxArray(), 20, 'camera')
    for i in order:
        name, p0, v = PEOPLE[i]
        b = mf.stamped(m.BoundingBox(), 20, 'camera')
        b.pose.position = g.Point(*at(p0, v, k * PERIOD))
        b.pose.orientation.w = 1.0
        b.dimensions = g.Vector3(0.6, 0.6, 0.0)  # no height: the label's default applies
        b.value = 0.5
        b.label = (i + k) % 2
        msg.boxes.append(b)
    return msg


CASES = [('walk_detections3d', 'vision_msgs', detections3d),
         ('walk_jsk', 'jsk_recognition_msgs', jsk)]


def main():
    import geometry_msgs.msg as g
    for name, package, build in CASES:
        root = mf.generate({})
        try:
            m = mf.load(root, package)
            data = io.BytesIO()
            lines = []
            for k in range(FRAMES):
                order = [0, 1] if k % 2 == 0 else [1, 0]
                msg = build(m, g, k, order)
                nsecs = k * 100000000
                msg.header.stamp = genpy.Time(20, nsecs)
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
