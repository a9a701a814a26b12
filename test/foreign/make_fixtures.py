#!/usr/bin/env python3
"""Writes test/foreign/fixtures/: messages of every stored foreign type serialized by ROS's own
Python serializer (genpy, from Debian, generating classes from foreign_msgs/ as a package's
build would), and what each holds. test_foreign_decoder reads them back: an oracle for the
decoder that shares no code with it or with the test's hand-written serializer.

Run with /usr/bin/python3 (genpy and genmsg come from Debian); rerun after changing foreign_msgs/.
Each fixture: <name>.bin (the bytes) and <name>.txt: "type <type> <md5>", then one line per
track: "track <px> <py> <pz> <velocity axes> <vx> <vy> <vz>".
"""

import importlib
import os
import shutil
import sys
import tempfile

import genpy
import genpy.generate_initpy
import genpy.generator

HERE = os.path.dirname(os.path.abspath(__file__))
FOREIGN = os.path.join(HERE, '..', '..', 'foreign_msgs')
OUT = os.path.join(HERE, 'fixtures')
STANDARD = ['std_msgs', 'geometry_msgs', 'sensor_msgs', 'shape_msgs']


def generate(version_dirs):
    """Python classes for every foreign package (plus shape_msgs, which Debian ships without
    Python) in a temporary folder; `version_dirs` maps a package to its version folder."""
    root = tempfile.mkdtemp()
    path = {p: ['/usr/share/%s/msg' % p] for p in STANDARD}
    packages = [p for p in os.listdir(FOREIGN) if os.path.isdir(os.path.join(FOREIGN, p))]
    for p in packages:
        path[p] = [os.path.join(FOREIGN, p)]
        if p in version_dirs:
            path[p].insert(0, os.path.join(FOREIGN, p, version_dirs[p]))
    for p in packages + ['shape_msgs']:
        names = set()
        for d in path[p]:
            names |= {f for f in os.listdir(d) if f.endswith('.msg')}
        files = [next(os.path.join(d, n) for d in path[p] if os.path.exists(os.path.join(d, n)))
                 for n in sorted(names)]
        if not files:
            continue  # workspace_proximity: only its v1 folder is stored (msg/ has the current)
        out = os.path.join(root, p, 'msg')
        genpy.generator.MsgGenerator().generate_messages(p, files, out, path)
        genpy.generate_initpy.write_modules(out)
        open(os.path.join(root, p, '__init__.py'), 'w').close()
    return root


def load(root, package):
    for name in list(sys.modules):
        if name.split('.')[0] in os.listdir(FOREIGN) + ['shape_msgs']:
            del sys.modules[name]
    sys.path.insert(0, root)
    try:
        return importlib.import_module(package + '.msg')
    finally:
        sys.path.remove(root)


def stamped(msg, secs, frame):
    msg.header.stamp = genpy.Time(secs, 500)
    msg.header.frame_id = frame
    return msg


def point(cls, x, y, z):
    return cls(x, y, z)


def spencer(m, g, version):
    msg = stamped(m.TrackedPersons(), 10, 'map')
    rows = []
    for i, (p, v) in enumerate([((1.5, -2.25, 0.5), (0.25, 0.5, 0.0)),
                                ((3.0, 4.0, 0.0), (-1.0, 0.0, 0.125))]):
        t = m.TrackedPerson(track_id=100 + i, is_occluded=False, detection_id=7)
        if version >= 2:
            t.is_matched = True
        if version == 3:
            t.detection_ids = [1, 2, 3]
        t.age = genpy.Duration(2, 0)
        t.pose.pose.position = g.Point(*p)
        t.pose.pose.orientation.w = 1.0
        t.pose.covariance = [0.01 * (k % 7 == 0) for k in range(36)]
        t.twist.twist.linear = g.Vector3(*v)
        t.twist.covariance = [0.02 * (k % 7 == 0) for k in range(36)]
        msg.tracks.append(t)
        rows.append((p, 7, v))
    return msg, rows


def people(m, g):
    msg = stamped(m.People(), 11, 'odom')
    rows = []
    for i, (p, v) in enumerate([((1.0, 2.0, 0.0), (0.5, 0.0, 0.0)),
                                ((-1.0, 0.5, 0.0), (0.0, -0.3, 0.0))]):
        msg.people.append(m.Person(name='p%d' % i, position=g.Point(*p), velocity=g.Point(*v),
                                   reliability=0.9, tagnames=['a'], tags=['b']))
        rows.append((p, 7, v))
    return msg, rows


def position_measurements(m, g):
    msg = stamped(m.PositionMeasurementArray(), 12, 'laser')
    rows = []
    for i, p in enumerate([(2.0, 1.0, 0.0), (3.0, -1.0, 0.0)]):
        pm = stamped(m.PositionMeasurement(), 12, 'laser')
        pm.name = 'leg_detector'
        pm.object_id = 'Person%d' % i
        pm.pos = g.Point(*p)
        pm.reliability = 0.5
        pm.covariance = [0.1, 0, 0, 0, 0.1, 0, 0, 0, 0.1]
        msg.people.append(pm)
        rows.append((p, 0, (0.0, 0.0, 0.0)))
    msg.cooccurrence = [0.5]
    return msg, rows


def bayes(m, g, version):
    msg = stamped(m.PeopleTracker(), 13, 'map')
    rows = []
    for i, (p, v) in enumerate([((1.0, 1.0, 0.0), (0.1, 0.2, 0.0)),
                                ((2.0, -2.0, 0.0), (-0.3, 0.0, 0.0))]):
        msg.uuids.append('uuid-%d' % i)
        msg.poses.append(g.Pose(position=g.Point(*p), orientation=g.Quaternion(0, 0, 0, 1)))
        if version == 2:
            msg.velocities.append(g.Vector3(*v))
        msg.distances.append(1.0)
        msg.angles.append(0.1)
        rows.append((p, 7 if version == 2 else 0, v if version == 2 else (0.0, 0.0, 0.0)))
    return msg, rows


def leg_tracker(m, g):
    msg = stamped(m.PersonArray(), 14, 'odom')
    rows = []
    for i, p in enumerate([(1.0, -1.0, 0.0), (0.5, 0.5, 0.0)]):
        msg.people.append(m.Person(pose=g.Pose(position=g.Point(*p),
                                               orientation=g.Quaternion(0, 0, 0, 1)), id=40 + i))
        rows.append((p, 0, (0.0, 0.0, 0.0)))
    return msg, rows


def derived(m, g, covariance):
    msg = stamped(m.ObjectWithCovarianceArray() if covariance else m.ObjectArray(), 15, 'base')
    rows = []
    for i, (p, v, level) in enumerate([((4.0, 1.0, 0.9), (-1.0, 0.5, 0.0), 1),
                                       ((6.0, -2.0, 0.9), (3.0, 0.5, 0.0), 0)]):
        o = stamped(m.ObjectWithCovariance() if covariance else m.Object(), 15, 'base')
        o.id = 20 + i
        o.detection_level = level
        o.object_classified = True
        o.classification = 4
        if covariance:
            o.pose.pose.position = g.Point(*p)
            o.pose.pose.orientation.w = 1.0
            o.pose.covariance = [0.1 * (k % 7 == 0) for k in range(36)]
            o.twist.twist.linear = g.Vector3(*v)
            o.twist.covariance = [0.2 * (k % 7 == 0) for k in range(36)]
            o.shape.covariance = [0.01]
        else:
            o.pose.position = g.Point(*p)
            o.pose.orientation.w = 1.0
            o.twist.linear = g.Vector3(*v)
        o.polygon.points = [g.Point32(1, 2, 3)]
        o.shape.type = 1
        o.shape.dimensions = [1.0, 2.0, 3.0]
        msg.objects.append(o)
        rows.append((p, 7 if level == 1 else 0, v if level == 1 else (0.0, 0.0, 0.0)))
    return msg, rows


def obstacles(m, g):
    msg = stamped(m.Obstacles(), 16, 'map')
    msg.segments.append(m.SegmentObstacle(first_point=g.Point(0, 0, 0),
                                          last_point=g.Point(1, 0, 0)))
    # Tracks in wire order: the segment's midpoint, then the circles; no velocity is read
    # (obstacle_detector's 0 means "not measured" as well: src/rules/foreign_tracks.cpp).
    rows = [((0.5, 0.0, 0.0), 0, (0.0, 0.0, 0.0))]
    for p, v in [((2.0, 3.0, 0.0), (0.4, 0.0, 0.0)), ((-2.0, 1.0, 0.0), (0.0, 0.0, 0.0))]:
        msg.circles.append(m.CircleObstacle(center=g.Point(*p), velocity=g.Vector3(*v),
                                            radius=0.5, true_radius=0.3))
        rows.append((p, 0, (0.0, 0.0, 0.0)))
    return msg, rows


def detections(m, g):
    import sensor_msgs.msg as s
    msg = stamped(m.Detection3DArray(), 17, 'camera')
    rows = []
    for p in [(1.0, 2.0, 3.0), (-1.0, -2.0, 0.5)]:
        d = stamped(m.Detection3D(), 17, 'camera')
        d.results.append(m.ObjectHypothesisWithPose(id=5, score=0.9))
        d.bbox.center.position = g.Point(*p)
        d.bbox.center.orientation.w = 1.0
        d.bbox.size = g.Vector3(0.5, 0.5, 1.7)
        d.source_cloud.fields = [s.PointField(name='x', offset=0, datatype=7, count=1)]
        d.source_cloud.data = b'\x01\x02\x03\x04'
        msg.detections.append(d)
        rows.append((p, 0, (0.0, 0.0, 0.0)))
    return msg, rows


def jsk(m, g, version):
    msg = stamped(m.BoundingBoxArray(), 18, 'base')
    rows = []
    for i, p in enumerate([(0.0, 1.0, 0.8), (2.0, 2.0, 0.8)]):
        b = stamped(m.BoundingBox(), 18, 'base')
        b.pose.position = g.Point(*p)
        b.pose.orientation.w = 1.0
        b.dimensions = g.Vector3(0.6, 0.6, 1.8)
        if version == 2:
            b.value = 0.5
            b.label = 3 + i
        msg.boxes.append(b)
        rows.append((p, 0, (0.0, 0.0, 0.0)))
    return msg, rows


# name, package, version folders, builder
CASES = [
    ('spencer_v1', 'spencer_tracking_msgs', {'spencer_tracking_msgs': 'v1'},
     lambda m, g: spencer(m, g, 1)),
    ('spencer_v2', 'spencer_tracking_msgs', {}, lambda m, g: spencer(m, g, 2)),
    ('spencer_v3', 'spencer_tracking_msgs', {'spencer_tracking_msgs': 'v3'},
     lambda m, g: spencer(m, g, 3)),
    ('pedsim_v1', 'pedsim_msgs', {'pedsim_msgs': 'v1'}, lambda m, g: spencer(m, g, 1)),
    ('people', 'people_msgs', {}, people),
    ('position_measurements', 'people_msgs', {}, position_measurements),
    ('bayes_v1', 'bayes_people_tracker', {'bayes_people_tracker': 'v1'},
     lambda m, g: bayes(m, g, 1)),
    ('bayes_v2', 'bayes_people_tracker', {}, lambda m, g: bayes(m, g, 2)),
    ('leg_tracker', 'leg_tracker', {}, leg_tracker),
    ('derived_objects', 'derived_object_msgs', {}, lambda m, g: derived(m, g, False)),
    ('derived_objects_covariance', 'derived_object_msgs', {}, lambda m, g: derived(m, g, True)),
    ('obstacles', 'obstacle_detector', {}, obstacles),
    ('detections3d', 'vision_msgs', {}, detections),
    ('jsk_v1', 'jsk_recognition_msgs', {'jsk_recognition_msgs': 'v1'}, lambda m, g: jsk(m, g, 1)),
    ('jsk_v2', 'jsk_recognition_msgs', {}, lambda m, g: jsk(m, g, 2)),
]


def main():
    import geometry_msgs.msg as g
    os.makedirs(OUT, exist_ok=True)
    for name, package, versions, build in CASES:
        root = generate(versions)
        try:
            msg, rows = build(load(root, package), g)
        finally:
            shutil.rmtree(root)
        buff = __import__('io').BytesIO()
        msg.serialize(buff)
        with open(os.path.join(OUT, name + '.bin'), 'wb') as f:
            f.write(buff.getvalue())
        with open(os.path.join(OUT, name + '.txt'), 'w') as f:
            f.write('type %s %s\n' % (msg._type, msg._md5sum))
            for p, axes, v in rows:
                f.write('track %r %r %r %d %r %r %r\n' % (p + (axes,) + v))
        print(name, msg._type, msg._md5sum, len(buff.getvalue()), 'bytes')


if __name__ == '__main__':
    main()
