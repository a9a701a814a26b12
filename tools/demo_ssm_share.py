#!/usr/bin/env python3
"""How much of the time the demo's arm is stopped or slowed, and why (issue 23, demo3).

Runs beside `scripts/demo` (true boxes) or `scripts/demo sensors:=true` (cloud_tracker from the
simulated camera and scanner) on the same master, headless, and measures over one window of
the scripted scene's own clock (scene_simulator's ~scene_start), so that both runs see the same
people at the same places:

  * the share of time the speed scale is 0 and below 1 (and the raw scale, before DEGRADED and
    the hysteresis), from safety_status, each cycle weighted by its duration;
  * what held the scale at 0: DEGRADED (by reason, numbers stripped), the hysteresis (raw scale
    above the scale), or the limiting object: with the sensors a track, told apart by whether
    its velocity was known, whether v_h was the label's ssm_min_speed floor, and whether a true
    box lies within 0.2 m of its footprint (a person or the forklift seen) or none does (a ghost:
    the arm's own points, noise);
  * with the sensors, per track (perceived_objects): how long it lived, how long its velocity
    stayed unknown, how many never got a velocity.

    /usr/bin/python3 tools/demo_ssm_share.py [--start 10] [--length 60] [--label NAME]
    /usr/bin/python3 tools/demo_ssm_share.py --bag RUN.bag   (offline: how the tracks started)
(a development tool, not installed; tools/demo_ssm_share.sh starts the demo and this together).
"""
import argparse
import collections
import math
import re
import sys

import rospy
from workspace_proximity.msg import PerceptionStatus, SafetyStatus, TrackedBoxArray

GHOST_DISTANCE = 0.2  # m: a track whose footprint is farther from every true box is a ghost


def footprint(box):
    """Axis-aligned (x, y) extent of a box: (xmin, xmax, ymin, ymax)."""
    q = box.pose.orientation
    yaw = math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))
    c, s = abs(math.cos(yaw)), abs(math.sin(yaw))
    hx = 0.5 * (c * box.dimensions.x + s * box.dimensions.y)
    hy = 0.5 * (s * box.dimensions.x + c * box.dimensions.y)
    p = box.pose.position
    return p.x - hx, p.x + hx, p.y - hy, p.y + hy


def gap(a, b):
    dx = max(0.0, a[0] - b[1], b[0] - a[1])
    dy = max(0.0, a[2] - b[3], b[2] - a[3])
    return math.hypot(dx, dy)


def shifted(box, dt):
    """The true box's footprint moved along its twist by dt s."""
    f = footprint(box)
    dx, dy = box.twist.linear.x * dt, box.twist.linear.y * dt
    return f[0] + dx, f[1] + dx, f[2] + dy, f[3] + dy


class Meter(object):
    def __init__(self, start, length):
        self.scene_start = None
        self.start, self.length = start, length
        self.status = []          # (t, scale, raw, degraded, reason, id_object, approach, separation)
        self.truth = None         # the latest true boxes
        self.tracks = {}          # id -> (its latest TrackedBox, that array's stamp)
        self.track_life = {}      # id -> [first t, first known t or None, last t, near truth ever]
        self.limiting = []        # per status sample in the window: the class of the limiting object
        self.shares = []

    def scene_t(self, stamp):
        return stamp.to_sec() - self.scene_start

    def in_window(self, t):
        return self.start <= t <= self.start + self.length

    def on_truth(self, msg):
        self.truth = msg

    def near_truth(self, box, stamp):
        if self.truth is None:
            return None
        dt = (stamp - self.truth.header.stamp).to_sec()
        best = (float('inf'), None)
        f = footprint(box)
        for b in self.truth.boxes:
            best = min(best, (gap(f, shifted(b, dt)), b.id))
        return best

    def on_tracks(self, msg):
        if self.scene_start is None:
            return
        t = self.scene_t(msg.header.stamp)
        for b in msg.boxes:
            self.tracks[b.id] = (b, msg.header.stamp)
        if not self.in_window(t):
            return
        for b in msg.boxes:
            if b.label == 'unseen':
                continue
            life = self.track_life.get(b.id)
            if life is None:
                life = self.track_life[b.id] = [t, None, t, False, None]
            life[2] = t
            if life[1] is None and not b.velocity_unknown:
                life[1] = t
            near = self.near_truth(b, msg.header.stamp)
            if near is not None and near[0] <= GHOST_DISTANCE:
                life[3] = True
                if life[4] is None:
                    life[4] = re.sub(r'_\d+$', '', near[1])

    def on_perception(self, msg):
        if self.scene_start is not None and self.in_window(self.scene_t(msg.header.stamp)):
            self.shares.append(msg.unseen_share)

    def on_status(self, msg):
        if self.scene_start is None:
            return
        t = self.scene_t(msg.header.stamp)
        if not self.in_window(t):
            return
        self.status.append((t, msg.speed_scale, msg.raw_scale, msg.status == SafetyStatus.DEGRADED,
                            msg.reason, msg.id_object, msg.approach_speed, msg.separation))
        self.limiting.append(self.classify(msg))

    def classify(self, msg):
        """What the limiting object of this cycle is."""
        if not msg.id_object:
            return 'none within reach'
        oid = msg.id_object.split('/')[-1]
        if oid not in self.tracks:  # a true box (the run without sensors), by its id without the number
            return re.sub(r'_\d+$', '', oid)
        box, stamp = self.tracks[oid]
        if box.label == 'unseen':
            return 'unseen box'
        near = self.near_truth(box, stamp)
        where = ('on %s' % re.sub(r'_\d+$', '', near[1])) if near and near[0] <= GHOST_DISTANCE \
            else 'ghost (no true box within %.1f m)' % GHOST_DISTANCE
        speed = 'velocity unknown' if box.velocity_unknown else 'velocity known'
        return 'track, %s, %s' % (speed, where)


def weights(samples):
    """Each cycle's duration: to the next cycle's stamp, at most 0.2 s (a gap counts 0.2 s)."""
    w = []
    for i, s in enumerate(samples):
        nxt = samples[i + 1][0] if i + 1 < len(samples) else s[0] + (w[-1] if w else 1.0 / 30.0)
        w.append(min(0.2, max(0.0, nxt - s[0])))
    return w


def normalise(reason):
    """A reason's kind: numbers and ids stripped."""
    r = reason.split(';')[0]
    if r.startswith('DEGRADED'):
        r = re.sub(r'[-+]?\d+(\.\d+)?', '#', r)
        return r[:110]
    if r.startswith('clear'):
        return 'clear'
    return 'limited by an object'


def report(m, label, out):
    s = m.status
    if len(s) < 10:
        print('%s: only %d safety_status samples in the window' % (label, len(s)), file=out)
        return
    w = weights(s)
    total = sum(w)

    def share(pred):
        return 100.0 * sum(wi for wi, x in zip(w, s) if pred(x)) / total

    mean_scale = sum(wi * x[1] for wi, x in zip(w, s)) / total
    print('### %s' % label, file=out)
    print('', file=out)
    print('scene time %.0f to %.0f s (%d cycles, %.1f s counted)' % (
        s[0][0], s[-1][0], len(s), total), file=out)
    print('', file=out)
    print('| | share of time |', file=out)
    print('|---|---:|', file=out)
    print('| speed_scale 0 | %.1f %% |' % share(lambda x: x[1] == 0.0), file=out)
    print('| speed_scale below 1 | %.1f %% |' % share(lambda x: x[1] < 1.0), file=out)
    print('| speed_scale mean | %.2f |' % mean_scale, file=out)
    print('| raw_scale 0 | %.1f %% |' % share(lambda x: x[2] == 0.0), file=out)
    print('| raw_scale below 1 | %.1f %% |' % share(lambda x: x[2] < 1.0), file=out)
    print('| DEGRADED | %.1f %% |' % share(lambda x: x[3]), file=out)
    print('', file=out)
    # Why the scale was 0: DEGRADED (by reason), the hysteresis, or the limiting object.
    why = collections.Counter()
    for wi, x, lim in zip(w, s, m.limiting):
        if x[1] != 0.0:
            continue
        if x[3]:
            why['DEGRADED: ' + normalise(x[4])] += wi
        elif x[2] > 0.0:
            why['raw scale > 0, held by the hysteresis; limiting: ' + lim] += wi
        else:
            floor = ' (v_h = the 1.6 m/s floor)' if abs(x[6] - 1.6) < 1e-6 else ''
            why['raw scale 0, limiting: ' + lim + floor] += wi
    print('Scale 0, why (share of the whole window):', file=out)
    print('', file=out)
    print('| cause | share of time |', file=out)
    print('|---|---:|', file=out)
    for k, v in why.most_common():
        print('| %s | %.1f %% |' % (k, 100.0 * v / total), file=out)
    print('', file=out)
    slow = collections.Counter()
    for wi, x, lim in zip(w, s, m.limiting):
        if x[1] < 1.0:
            slow[lim] += wi
    print('Scale below 1, the limiting object (share of the whole window):', file=out)
    print('', file=out)
    print('| limiting object | share of time |', file=out)
    print('|---|---:|', file=out)
    for k, v in slow.most_common():
        print('| %s | %.1f %% |' % (k, 100.0 * v / total), file=out)
    print('', file=out)
    if m.track_life:
        lives = list(m.track_life.values())
        n = len(lives)
        known = [l for l in lives if l[1] is not None]
        to_known = sorted(l[1] - l[0] for l in known)
        life = sorted(l[2] - l[0] for l in lives)
        ghosts = sum(1 for l in lives if not l[3])

        def pct(v, p):
            return v[min(len(v) - 1, int(p * len(v)))] if v else float('nan')
        print('Tracks (perceived_objects, started in or living through the window): %d, %.1f/s; '
              '%d (%.0f %%) never near a true box; %d (%.0f %%) got a velocity, after median '
              '%.2f s (p90 %.2f s); lifetime median %.2f s, p90 %.2f s; %d lived under 0.2 s.' % (
                  n, n / m.length, ghosts, 100.0 * ghosts / n, len(known), 100.0 * len(known) / n,
                  pct(to_known, 0.5), pct(to_known, 0.9), pct(life, 0.5), pct(life, 0.9),
                  sum(1 for x in life if x < 0.2)), file=out)
        born = collections.Counter(l[4] or 'ghost' for l in lives)
        print('Tracks by the true object they were first near: %s.' % ', '.join(
            '%s %d' % kv for kv in born.most_common()), file=out)
        print('', file=out)
    if m.shares:
        sh = sorted(x for x in m.shares if not math.isnan(x))
        if sh:
            print('Unseen share: median %.3f, p90 %.3f, max %.3f (%d samples).' % (
                sh[len(sh) // 2], sh[int(0.9 * len(sh))], sh[-1], len(sh)), file=out)
            print('', file=out)


def births(bag_path, out):
    """Offline, from a bag of the run (tools/demo_ssm_share.sh with WP_SHARE_BAG): how each
    track started, by the true box it is on: the first track on it, or beside another track on
    the same box that lives on (a duplicate), or replacing one that ended at that array."""
    import rosbag
    truth, prev = None, {}
    kinds, shares = collections.Counter(), collections.Counter()
    for topic, msg, _ in rosbag.Bag(bag_path).read_messages(topics=['/true_objects', '/perceived_objects']):
        if topic == '/true_objects':
            truth = msg
            continue
        if truth is None:
            continue
        dt = (msg.header.stamp - truth.header.stamp).to_sec()
        cur = {}
        for b in msg.boxes:
            if b.label == 'unseen':
                continue
            f = footprint(b)
            d, oid = min((gap(f, shifted(t, dt)), t.id) for t in truth.boxes)
            cur[b.id] = oid if d <= GHOST_DISTANCE else 'ghost'
        for oid, n in collections.Counter(cur.values()).items():
            shares[(oid, n)] += 1
        for i, oid in cur.items():
            if i in prev:
                continue
            ended = any(o == oid and j not in cur for j, o in prev.items())
            beside = any(o == oid and j != i and j in prev for j, o in cur.items())
            kind = 'beside a live track' if beside else ('replacing one that ended' if ended else 'first')
            kinds[(re.sub(r'_\d+$', '', oid), kind)] += 1
        prev = cur
    print('Tracks started over the whole bag, by the true box they are on and how:', file=out)
    for (oid, kind), n in sorted(kinds.items()):
        print('  %-10s %-26s %d' % (oid, kind, n), file=out)
    print('Arrays in which a true box was n tracks (box: {n: arrays}):', file=out)
    for oid in sorted({k[0] for k in shares}):
        print('  %-12s %s' % (oid, dict(sorted((n, c) for (o, n), c in shares.items() if o == oid))), file=out)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--bag', help='offline: how the tracks of this bag started (no master needed)')
    ap.add_argument('--start', type=float, default=10.0, help='s of scene time the window starts at')
    ap.add_argument('--length', type=float, default=60.0, help='s the window lasts')
    ap.add_argument('--label', default='demo', help='heading of the report')
    args = ap.parse_args(rospy.myargv()[1:])
    if args.bag:
        births(args.bag, sys.stdout)
        return
    rospy.init_node('demo_ssm_share', anonymous=True)
    m = Meter(args.start, args.length)
    while not rospy.is_shutdown() and m.scene_start is None:
        try:
            m.scene_start = float(rospy.get_param('/scene_simulator/scene_start'))
        except KeyError:
            rospy.sleep(0.2)
    rospy.Subscriber('/safety_status', SafetyStatus, m.on_status, queue_size=100)
    rospy.Subscriber('/tracked_objects', TrackedBoxArray, m.on_truth, queue_size=10)
    rospy.Subscriber('/true_objects', TrackedBoxArray, m.on_truth, queue_size=10)
    rospy.Subscriber('/perceived_objects', TrackedBoxArray, m.on_tracks, queue_size=100)
    rospy.Subscriber('/perception_status', PerceptionStatus, m.on_perception, queue_size=50)
    end = m.scene_start + args.start + args.length + 0.5
    while not rospy.is_shutdown() and rospy.Time.now().to_sec() < end:
        rospy.sleep(0.2)
    report(m, args.label, sys.stdout)


if __name__ == '__main__':
    main()
