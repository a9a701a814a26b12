"""One person in each foreign tracker type, for the node's and the replay's tests of issue 24
(test/ros/test_foreign_inputs.py, test/replay/test_replay_foreign.py).

FAMILIES maps a name to (package, version folders, builder): make_fixtures.generate(folders)
and make_fixtures.load(root, package) give the genpy module `m` of the upstream definitions,
and builder(m, stamp, position, velocity) one message in frame "world" with one person, id
100 (name or uuid "100" where ids are text), at `position` (m) moving at `velocity` (m/s)
where the type carries a velocity, with zero covariances where it carries them.
"""
import geometry_msgs.msg as g


def header(msg, stamp, frame="world"):
    msg.header.stamp = stamp
    msg.header.frame_id = frame
    return msg


def people(m, s, p, v):
    msg = header(m.People(), s)
    msg.people.append(m.Person(name="100", position=g.Point(*p), velocity=g.Point(*v),
                               reliability=1.0))
    return msg


def position_measurements(m, s, p, v):
    msg = header(m.PositionMeasurementArray(), s)
    pm = header(m.PositionMeasurement(), s)
    pm.name, pm.object_id, pm.pos, pm.reliability = "legs", "100", g.Point(*p), 1.0
    msg.people.append(pm)
    return msg


def spencer(version):
    def build(m, s, p, v):
        msg = header(m.TrackedPersons(), s)
        t = m.TrackedPerson(track_id=100, is_occluded=False, detection_id=1)
        if version >= 2:
            t.is_matched = True
        if version == 3:
            t.detection_ids = [1]
        t.pose.pose.position = g.Point(*p)
        t.pose.pose.orientation.w = 1.0
        t.twist.twist.linear = g.Vector3(*v)
        msg.tracks.append(t)
        return msg
    return build


def bayes(version):
    def build(m, s, p, v):
        msg = header(m.PeopleTracker(), s)
        msg.uuids.append("100")
        msg.poses.append(g.Pose(position=g.Point(*p), orientation=g.Quaternion(0, 0, 0, 1)))
        if version == 2:
            msg.velocities.append(g.Vector3(*v))
        msg.distances.append(1.0)
        msg.angles.append(0.0)
        return msg
    return build


def leg_tracker(m, s, p, v):
    msg = header(m.PersonArray(), s)
    msg.people.append(m.Person(pose=g.Pose(position=g.Point(*p),
                                           orientation=g.Quaternion(0, 0, 0, 1)), id=100))
    return msg


def derived(covariance):
    def build(m, s, p, v):
        msg = header(m.ObjectWithCovarianceArray() if covariance else m.ObjectArray(), s)
        o = header(m.ObjectWithCovariance() if covariance else m.Object(), s)
        o.id = 100
        o.detection_level = 1       # OBJECT_TRACKED: its twist is valid
        o.object_classified = True
        o.classification = 4        # CLASSIFICATION_PEDESTRIAN
        pose = o.pose.pose if covariance else o.pose
        twist = o.twist.twist if covariance else o.twist
        pose.position = g.Point(*p)
        pose.orientation.w = 1.0
        twist.linear = g.Vector3(*v)
        o.shape.type = 1            # BOX
        o.shape.dimensions = [0.6, 0.6, 1.8]
        msg.objects.append(o)
        return msg
    return build


def trackedbox_v1(m, s, p, v):
    """This package's own TrackedBoxArray before the per-box errors (foreign_msgs/
    workspace_proximity/v1): what an old publisher or a recorded bag sends. The person's box
    as the TrackedBoxArray scene gives it (0.6 x 0.6 x 1.8 m, label person)."""
    msg = header(m.TrackedBoxArray(), s)
    b = m.TrackedBox(id="100", label="person")
    b.pose.position = g.Point(*p)
    b.pose.orientation.w = 1.0
    b.dimensions = g.Vector3(0.6, 0.6, 1.8)
    b.twist.linear = g.Vector3(*v)
    msg.boxes.append(b)
    return msg


def jsk_skeleton(m, s, p, v):
    """One body (human_ids [100]) of one bone "Neck->Pelvis" (a torso), vertical through the
    person's centre, 1.2 m long: with the test parameters' torso radius 0.3 m (the default
    label's size_x 0.6 m as its diameter) the capsule's tight box is the person's 0.6 x 0.6 x
    1.8 m box. The joints carry no velocity: the node differences them."""
    import std_msgs.msg
    msg = header(m.HumanSkeletonArray(), s)
    msg.human_ids.append(std_msgs.msg.Int32(100))
    skeleton = header(m.HumanSkeleton(), s)
    skeleton.bone_names.append("Neck->Pelvis")
    skeleton.bones.append(m.Segment(start_point=g.Point(p[0], p[1], p[2] + 0.6),
                                    end_point=g.Point(p[0], p[1], p[2] - 0.6)))
    msg.skeletons.append(skeleton)
    return msg


FAMILIES = {
    "people": ("people_msgs", {}, people),
    "position_measurements": ("people_msgs", {}, position_measurements),
    "spencer_v1": ("spencer_tracking_msgs", {"spencer_tracking_msgs": "v1"}, spencer(1)),
    "spencer_v2": ("spencer_tracking_msgs", {}, spencer(2)),
    "spencer_v3": ("spencer_tracking_msgs", {"spencer_tracking_msgs": "v3"}, spencer(3)),
    "pedsim_v1": ("pedsim_msgs", {"pedsim_msgs": "v1"}, spencer(1)),
    "pedsim_v2": ("pedsim_msgs", {}, spencer(2)),
    "bayes_v1": ("bayes_people_tracker", {"bayes_people_tracker": "v1"}, bayes(1)),
    "bayes_v2": ("bayes_people_tracker", {}, bayes(2)),
    "leg_tracker": ("leg_tracker", {}, leg_tracker),
    "derived_objects": ("derived_object_msgs", {}, derived(False)),
    "derived_objects_covariance": ("derived_object_msgs", {}, derived(True)),
    "trackedbox_v1": ("workspace_proximity", {"workspace_proximity": "v1"}, trackedbox_v1),
    "jsk_skeleton": ("jsk_recognition_msgs", {}, jsk_skeleton),
}


# Detections (no ids): through the multi-object tracker. Debian ships visualization_msgs and
# geometry_msgs with Python: their package is given as "debian:<package>".
def detections3d(m, s, p, v):
    msg = header(m.Detection3DArray(), s)
    d = header(m.Detection3D(), s)
    d.results.append(m.ObjectHypothesisWithPose(id=7, score=0.9))  # a class id: never an id
    d.bbox.center.position = g.Point(*p)
    d.bbox.center.orientation.w = 1.0
    d.bbox.size = g.Vector3(0.6, 0.6, 1.8)
    msg.detections.append(d)
    return msg


def jsk(version):
    def build(m, s, p, v):
        msg = header(m.BoundingBoxArray(), s)
        b = header(m.BoundingBox(), s)
        b.pose.position = g.Point(*p)
        b.pose.orientation.w = 1.0
        b.dimensions = g.Vector3(0.6, 0.6, 1.8)
        if version == 2:
            b.value, b.label = 0.9, 1
        msg.boxes.append(b)
        return msg
    return build


def markers(m, s, p, v):
    msg = m.MarkerArray()
    mk = header(m.Marker(), s)
    mk.ns, mk.id, mk.type, mk.action = "people", 1, m.Marker.CYLINDER, m.Marker.ADD
    mk.pose.position = g.Point(*p)
    mk.pose.orientation.w = 1.0
    mk.scale = g.Vector3(0.6, 0.6, 1.8)
    mk.color.a = 1.0
    msg.markers.append(mk)
    return msg


def poses(m, s, p, v):
    msg = header(m.PoseArray(), s)
    msg.poses.append(g.Pose(position=g.Point(*p), orientation=g.Quaternion(0, 0, 0, 1)))
    return msg


def obstacles(m, s, p, v):
    """obstacle_detector: the person as a circle (true_radius 0.3: 0.6 m across; radius 0.55
    with obstacle_detector's default 0.25 margin; its velocity field set, never read: the
    monitor's tracker measures it) and a static wall segment 30 m behind the post, beyond the
    reach of both its and the person's growth within the 5 s horizon (at most 2 m/s + their
    speed each), so the scene's only pair stays the person's and the post's."""
    msg = header(m.Obstacles(), s)
    msg.segments.append(m.SegmentObstacle(first_point=g.Point(-30.0, -1.0, 0.0),
                                          last_point=g.Point(-30.0, 1.0, 0.0)))
    msg.circles.append(m.CircleObstacle(center=g.Point(p[0], p[1], 0.0), velocity=g.Vector3(*v),
                                        radius=0.55, true_radius=0.3))
    return msg


DETECTION_FAMILIES = {
    "detections3d": ("vision_msgs", {}, detections3d),
    "jsk_v1": ("jsk_recognition_msgs", {"jsk_recognition_msgs": "v1"}, jsk(1)),
    "jsk_v2": ("jsk_recognition_msgs", {}, jsk(2)),
    "markers": ("debian:visualization_msgs", {}, markers),
    "poses": ("debian:geometry_msgs", {}, poses),
    "obstacles": ("obstacle_detector", {}, obstacles),
}


def load_module(make_fixtures, root, package):
    """The module of `package`'s messages: generated into `root`, or Debian's."""
    if package.startswith("debian:"):
        import importlib
        return importlib.import_module(package.split(":", 1)[1] + ".msg")
    return make_fixtures.load(root, package)
