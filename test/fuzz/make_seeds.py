#!/usr/bin/env python3
"""Writes the hand-made seed inputs of test/fuzz/corpus/<harness>/.

Each seed is a small, meaningful program in the byte format the harness reads (see
fuzz_input.hpp and the harnesses), so fuzzing starts from scenes that already reach the
interesting code (contacts, END events, rebuilds, accepted boxes) instead of from nothing.
Run it again after changing a harness's input format:  python3 test/fuzz/make_seeds.py
"""

import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


class Program:
    def __init__(self):
        self.data = bytearray()

    def byte(self, b):
        self.data.append(b & 0xFF)
        return self

    def u16(self, v):
        self.data += struct.pack("<H", v & 0xFFFF)
        return self

    def u32(self, v):
        self.data += struct.pack("<I", v & 0xFFFFFFFF)
        return self

    # Input::number(): grid values k / 8 in [-16, 16), or entries of the special table.
    def grid(self, v):
        k = int(round(v * 8))
        assert -128 <= k <= 127 and k / 8 == v, v
        return self.byte(100).byte(k & 0xFF)

    def special(self, index):
        return self.byte(0).byte(index)

    def vector(self, x, y, z):
        return self.grid(x).grid(y).grid(z)

    # Input::dimension(): (n + 1) / 16 for n in [0, 255].
    def dimension(self, v):
        n = int(round(v * 16)) - 1
        assert 0 <= n <= 255 and (n + 1) / 16 == v, v
        return self.byte(0).byte(n)

    # Input::margin(): n / 512.
    def margin(self, v):
        n = int(round(v * 512))
        assert 0 <= n <= 255, v
        return self.byte(0).byte(n)

    def text(self, s):
        b = s.encode()
        self.byte(len(b))
        self.data += b
        return self

    def identity(self):
        return self.byte(0)

    def axis_angle(self, axis, angle):
        self.byte(1).vector(*axis)
        return self.grid(angle)

    def write(self, harness, name):
        folder = os.path.join(HERE, "corpus", harness)
        os.makedirs(folder, exist_ok=True)
        with open(os.path.join(folder, name), "wb") as f:
            f.write(bytes(self.data))


# ---- fuzz_world ----------------------------------------------------------------------------
ADD, REMOVE, SET_MOTION, SET_SHAPE, SET_RULES, ADVANCE, PREDICT = 0, 3, 4, 5, 6, 7, 8
BOX, SPHERE, CYLINDER, CAPSULE = 0, 1, 2, 3
LABELS = {"person": 0, "forklift": 1, "robot": 2, "pallet": 3}


def world_config(p, allow_all=True, small=False, rebuild_always=False):
    b = 0 if small else 0xFF & ~0xC0  # capacities 1 or 256
    if rebuild_always:
        b |= 1 << 6
    p.byte(b)
    return p.byte(4 if allow_all else 0)


def add(p, shape, dims, position, velocity=None, angular=None, label="person", robot=False,
        margin=0.0, orientation=None):
    # naming byte: low 4 bits non-zero (an id), bit 4 clear (no suffix), (n >> 5) % 5 picks the
    # label and bit 7 the group: search the byte that says all of that.
    naming = next(n for n in range(256)
                  if n & 31 == 1 and (n >> 5) % 5 == LABELS[label] and bool(n & 0x80) == robot)
    p.byte(ADD).byte(naming)
    shape_body(p, shape, dims)
    p.margin(margin)
    motion(p, position, velocity, angular, orientation)


def shape_body(p, shape, dims):
    # dims: box (hx, hy, hz); sphere (r,); cylinder/capsule (r, length)
    p.byte(shape)
    half = dims if shape == BOX else (0.5, 0.5, 0.5)
    for v in half:
        p.dimension(v)
    p.dimension(dims[0] if shape != BOX else 0.5)
    if shape in (CYLINDER, CAPSULE):
        p.byte(255).dimension(dims[1])
    else:
        p.byte(0)  # length 0


def motion(p, position, velocity, angular, orientation):
    p.vector(*position)
    if orientation is None:
        p.identity()
    else:
        p.axis_angle(*orientation)
    kind = (1 if velocity else 0) | (2 if angular else 0)
    p.byte(kind)
    if velocity:
        p.vector(*velocity)
    if angular:
        p.vector(*angular)


def predict(p, horizon):
    n = int(round(horizon * 32))
    assert 0 <= n <= 255
    return p.byte(PREDICT).byte(1).byte(n)


def advance(p, dt):
    k = int(round(dt * 64))
    return p.byte(ADVANCE).byte(1).byte(k & 0xFF)


def world_seeds():
    # Two boxes head-on: BEGIN, then ONGOING as they advance, END after one is removed.
    p = Program()
    world_config(p)
    add(p, BOX, (0.5, 0.5, 0.5), (-3, 0, 0), velocity=(1, 0, 0))
    add(p, BOX, (0.25, 0.5, 1), (3, 0, 0), velocity=(-1, 0, 0), label="forklift")
    predict(p, 4)
    advance(p, 0.5)
    predict(p, 4)
    p.byte(REMOVE).byte(1)
    predict(p, 4)
    predict(p, 4)
    p.write("fuzz_world", "head_on_boxes")

    # Every shape type, rotating, with margins; shape change and rules in between.
    p = Program()
    world_config(p, allow_all=False, small=True)
    add(p, SPHERE, (0.5,), (0, 0, 0), velocity=(0.5, 0, 0), margin=0.1)
    add(p, CYLINDER, (0.25, 1.5), (1.5, 0.25, 0), angular=(0, 0, 2), orientation=((1, 0, 0), 1.5))
    add(p, CAPSULE, (0.25, 1), (0, 1.5, 0), velocity=(0, -0.5, 0), label="robot", robot=True)
    add(p, BOX, (1, 0.125, 0.125), (-1.5, 0, 0.25), angular=(1, 1, 0), label="robot", robot=True)
    predict(p, 2)
    p.byte(SET_SHAPE).byte(0)
    shape_body(p, SPHERE, (1,))
    p.margin(0.25)
    predict(p, 2)
    p.byte(SET_RULES).byte(1 | (1 << 1)).byte(0x21).byte(0)  # allowAll + deny robot-object
    predict(p, 2)
    advance(p, 0.25)
    predict(p, 1)
    p.write("fuzz_world", "all_shapes_rules")

    # Touching and overlapping bodies at rest, horizon 0, then removal of all of them.
    p = Program()
    world_config(p, rebuild_always=True)
    add(p, BOX, (0.5, 0.5, 0.5), (0, 0, 0))
    add(p, BOX, (0.5, 0.5, 0.5), (1, 0, 0))
    add(p, SPHERE, (0.5,), (0.5, 0.5, 0))
    predict(p, 0)
    p.byte(SET_MOTION).byte(2)
    motion(p, (4, 4, 4), (-1, -1, -1), None, None)
    predict(p, 3)
    for i in range(3):
        p.byte(REMOVE).byte(i)
    predict(p, 3)
    predict(p, 3)
    p.write("fuzz_world", "touching_then_removed")


# ---- fuzz_sweep_and_prune ----------------------------------------------------------------------
def sap_box(p, lower, width):
    for lo, w in zip(lower, width):
        p.u16(int(lo * 64))
        if lo == 0:
            p.byte(0)  # the sign flag read for a zero: +0
        p.byte(255 if w else 0)
        if w:
            p.u16(int(w * 64))


def sap_seeds():
    CREATE, MOVE, DESTROY, JITTER, UPDATE = 0, 2, 3, 4, 5
    for name, rebuild in (("grid_incremental", 0x50), ("grid_rebuild", 0x10)):
        p = Program()
        p.byte(0).byte(rebuild | 0x0F)  # exact mode; capacities 256, rebuild factor
        for _ in range(8):
            p.grid(0)
        for i in range(6):
            p.byte(CREATE)
            sap_box(p, (i, i % 2, 0), (1.5, 1, 1 if i % 3 else 0))
            p.u32(100 + i)
        p.byte(UPDATE)
        p.byte(MOVE).byte(0)
        sap_box(p, (2, 0, 0), (1, 1, 1))
        p.byte(JITTER).byte(1)
        p.data += bytes([4, 0xFC, 0] * 6)
        p.byte(UPDATE)
        p.byte(DESTROY).byte(1)
        p.byte(CREATE)
        sap_box(p, (1, 0, 0), (0, 0, 0))
        p.u32(7)
        p.byte(UPDATE)
        p.write("fuzz_sweep_and_prune", name)

    # Wide mode: anchors far apart in magnitude, boxes a few ulps apart.
    p = Program()
    p.byte(1).byte(0x03)
    for index in (2, 9, 21, 29, 33, 41, 0, 1):  # 1, 1e-9, 1e150, denormal, 1e-300, pi, 0, -0
        p.special(index)
    for i in range(6):
        p.byte(CREATE)
        for axis in range(3):
            p.byte(i).byte(0).byte(30).byte(i + 1).byte((i + axis) % 3)
        p.u32(i)
    p.byte(UPDATE)
    p.write("fuzz_sweep_and_prune", "wide_ulps")

    # A crowd (64 proxies from a few bytes) under a tracker's noise: rebuilds that radix-sort
    # and sweep in slabs; coasting's long runs, whose ends are the next arrays built in
    # slices (radix sorts in steps, a sweep planned in slabs and its slab lists in a slice of
    # their own) and swapped in.
    CROWD, NOISY = 0xE7, 0xF7
    p = Program()
    p.byte(0).byte(0x0F)  # exact mode; capacities 256; coasting's lead of 8
    for _ in range(8):
        p.grid(0)
    p.byte(CROWD).byte(48).byte(0x3B).u16(0x1234)  # 64 boxes, width 1/2, far cluster 15 widths
    p.byte(UPDATE)
    p.byte(NOISY).byte(35).byte(0x05).u16(0x51C3)  # 36 updates, +-1/64, every third drifting
    p.write("fuzz_sweep_and_prune", "crowd_slabs")


# ---- fuzz_messages -------------------------------------------------------------------------
def box_msg(p, position, dims, linear=None, angular=None, label_index=0, tf=None):
    p.byte(1 | (label_index << 3))   # naming: id text follows
    p.text("track1")
    for v in position:
        p.byte(0).grid(v)            # coordinate(): flag 0 -> number()
    p.byte(0).identity()             # exact unit quaternion
    for v in dims:
        p.byte(0).dimension(v)       # flag 0 -> dimension()
    p.byte((1 if linear else 0) | (2 if angular else 0))
    for vec in (linear, angular):
        if vec:
            for v in vec:
                p.byte(0).grid(v)
    # transform of the box's frame, margin, latency
    p.vector(*(tf or (0, 0, 0))).identity()
    p.byte(25)
    p.u16(1)


def message_seeds():
    p = Program()
    p.byte(1)  # two boxes
    box_msg(p, (1, 2, 0.875), (0.5, 0.625, 1.75), linear=(1.25, 0, 0))
    box_msg(p, (3, 2, 0.875), (1, 1, 1), linear=(-1, 0, 0), angular=(0, 0, 0.25), label_index=1,
            tf=(0.5, 0, 0))
    p.byte(64)  # horizon
    p.write("fuzz_messages", "two_boxes")

    # Limits: dimension 1000 and speed 100 exactly (accepted), via nearLimit().
    p = Program()
    p.byte(0)
    p.byte(1).text("big")
    for _ in range(3):
        p.byte(1).byte(1).byte(0)    # nearLimit: 1e5 exactly
    p.byte(0).identity()
    for _ in range(3):
        p.byte(1).byte(0).byte(0)    # nearLimit: 1000 exactly
    p.byte(1)
    p.byte(1).byte(2).byte(0)        # linear x = 100
    p.byte(0).grid(0).byte(0).grid(0)
    p.vector(0, 0, 0).identity().byte(255).u16(8)
    p.byte(255)
    p.write("fuzz_messages", "at_the_limits")

    # Parameters: labels, pair rules and robot bodies.
    p = Program()
    p.byte(0xFF)
    p.grid(2).margin(0.0625)
    p.byte(1)                          # one label
    p.margin(0.125).grid(1).grid(0.5).grid(0.5).grid(0.25).byte(0).text("person")
    p.byte(2)                          # two rules
    p.byte(1).byte(3).byte(1)          # ignore group:robot - label:person
    p.byte(0).byte(4).byte(0)          # check * - id:arm
    p.byte(1)                          # one robot body
    p.text("arm").byte(1).byte(2).dimension(0.125).dimension(1).vector(0, 0, 1)
    p.write("fuzz_messages", "params")


# fuzz_foreign: byte 0 is the index of the type's version in the catalogue (kVersions of
# src/rules/foreign_types.cpp, in its order), the rest one serialized message: the genpy
# fixtures of test/foreign/fixtures/ (the walk_* files: their first frame).
def foreign_seeds():
    import re
    root = os.path.dirname(os.path.dirname(HERE))
    with open(os.path.join(root, "src", "rules", "foreign_types.cpp")) as f:
        table = f.read().split("kVersions[] = {", 1)[1].split("};", 1)[0]
    versions = re.findall(r'known\("([^"]+)",\s*"[^"]+",\s*"([0-9a-f]{32})"', table)
    fixtures = os.path.join(root, "test", "foreign", "fixtures")
    for name in sorted(os.listdir(fixtures)):
        if not name.endswith(".txt"):
            continue
        stem = name[:-4]
        with open(os.path.join(fixtures, name)) as f:
            _, type_name, md5 = f.readline().split()
        with open(os.path.join(fixtures, stem + ".bin"), "rb") as f:
            data = f.read()
        if stem.startswith("walk_"):
            (length,) = struct.unpack_from("<I", data, 0)
            data = data[4:4 + length]
        p = Program()
        p.byte(versions.index((type_name, md5)))
        p.data += data
        p.write("fuzz_foreign", stem)


# fuzz_skeletons: byte 0 picks the decoder (0 jsk HumanSkeletonArray, 1 the Azure Kinect
# driver's MarkerArray, 2 hri_msgs/IdsList; 3 and 4 the first and last with an unknown md5), the
# rest one serialized message, written here field by field as ROS 1 serializes it.
def ros_string(s):
    b = s.encode()
    return struct.pack("<I", len(b)) + b


def ros_header(seq, secs, frame):
    return struct.pack("<III", seq, secs, 0) + ros_string(frame)


def jsk_skeletons(ids, skeletons):
    # skeletons: [(bone_names, [(start xyz, end xyz)])]
    out = ros_header(1, 100, "camera") + struct.pack("<I", len(ids))
    out += b"".join(struct.pack("<i", i) for i in ids)
    out += struct.pack("<I", len(skeletons))
    for names, segments in skeletons:
        out += ros_header(1, 100, "camera") + struct.pack("<I", len(names))
        out += b"".join(ros_string(n) for n in names)
        out += struct.pack("<I", len(segments))
        for a, b in segments:
            out += struct.pack("<6d", *a, *b)
    return out


def k4abt_marker(marker_id, position, frame="depth_camera_link"):
    SPHERE, ADD = 2, 0
    out = ros_header(0, 100, frame) + ros_string("")
    out += struct.pack("<iii", marker_id, SPHERE, ADD)
    out += struct.pack("<7d", *position, 0.0, 0.0, 0.0, 1.0)  # pose
    out += struct.pack("<3d", 0.05, 0.05, 0.05)  # scale
    out += struct.pack("<4f", 1.0, 0.0, 0.0, 1.0)  # color
    out += struct.pack("<ii", 0, 250000000)  # lifetime
    out += struct.pack("<B", 0)  # frame_locked
    out += struct.pack("<II", 0, 0)  # points[], colors[]
    return out + ros_string("") + ros_string("") + struct.pack("<B", 0)


def skeleton_seeds():
    arm = [((0.0, -0.2, 1.4), (0.0, -0.2, 1.1)), ((0.0, -0.2, 1.1), (0.2, -0.2, 1.0)),
           ((0.2, -0.2, 1.0), (0.28, -0.2, 1.0))]
    trunk = [((0.0, 0.0, 1.5), (0.0, 0.0, 1.7)), ((0.0, 0.0, 1.5), (0.0, 0.0, 1.0)),
             ((0.0, 0.1, 1.0), (0.0, 0.1, 0.5)), ((0.0, 0.1, 0.5), (0.0, 0.1, 0.05))]
    names_arm = ["RShoulder->RElbow", "RElbow->RWrist", "RWrist->RHand"]
    names_trunk = ["Neck->Head", "Neck->MidHip", "LHip->LKnee", "LKnee->LAnkle"]
    p = Program().byte(0)
    p.data += jsk_skeletons([7, 9], [(names_arm + ["Unknown->Thing"], arm + arm[:1]),
                                     (names_trunk, trunk)])
    p.write("fuzz_skeletons", "jsk_two_bodies")
    p = Program().byte(0)
    p.data += jsk_skeletons([], [(names_trunk, trunk)])
    p.write("fuzz_skeletons", "jsk_no_ids")

    # Two bodies of 32 joints each (one without its left hand), ids body * 100 + joint.
    p = Program().byte(1)
    markers = []
    for body in (1, 2):
        for j in range(32):
            if body == 2 and j == 8:
                continue
            markers.append(k4abt_marker(body * 100 + j, (0.5 * body, 0.03 * j, 1.0 + 0.02 * j)))
    p.data += struct.pack("<I", len(markers)) + b"".join(markers)
    p.write("fuzz_skeletons", "k4abt_two_bodies")

    p = Program().byte(2)
    ids = ["1a2b3", "zq9"]
    p.data += ros_header(3, 100, "") + struct.pack("<I", len(ids))
    p.data += b"".join(ros_string(i) for i in ids)
    p.write("fuzz_skeletons", "hri_ids")


def event_seeds():
    """fuzz_events: 100 pairs; a coherent stretch (times shrinking by a cycle), then times drawn
    afresh every cycle (the radix sort's path), then special values and a clear()."""
    import random
    rng = random.Random(5)
    p = Program().byte(92).byte(8)  # 8 + 92 = 100 pairs, initial capacity 9
    for cycle in range(6):
        p.byte(0)
        for i in range(100):
            p.byte(1 | (32 << 2) if i % 9 else 0)  # reported, last time less a cycle
    for cycle in range(4):
        p.byte(0)
        for i in range(100):
            p.byte(2).u16(rng.randrange(65536))  # a fresh time
    p.byte(0xFF)  # clear()
    for i in range(100):
        p.byte(3 | ((i % 8) << 2) | ((i % 4) << 5))  # +0, -0, inf, denormal, last, jump, < 0
    p.write("fuzz_events", "coherent_scrambled_special")


if __name__ == "__main__":
    world_seeds()
    sap_seeds()
    message_seeds()
    foreign_seeds()
    skeleton_seeds()
    event_seeds()
