"""An independent oracle for pairs of tracked objects: upright boxes (turned about z only)
standing on the same floor, rounded by their margins, moving with a constant twist.

When two such boxes' height intervals overlap, their distance is the distance between their
footprints (rectangles in the x-y plane), and the rounded boxes touch when that distance is at
most the sum of the margins. The footprint distance is computed directly: zero when the
rectangles overlap (separating-axis test on their four edge normals), otherwise the smallest
vertex-to-edge distance. The first contact within the horizon is found by sampling at steps of
at least `step` seconds, longer only while the footprints are too far apart to touch before the
next sample (the gap shrinks at most at the relative speed plus each yaw rate times the
footprint's half-diagonal), and bisecting the first sampled crossing. Written from the geometry
alone, sharing nothing with the monitor's code.
"""
import math


class Box2D(object):
    """Footprint of an upright box: centre (x, y), yaw, half extents (hx, hy), with its
    velocity (vx, vy) and yaw rate wz."""

    def __init__(self, x, y, yaw, hx, hy, vx=0.0, vy=0.0, wz=0.0):
        self.x, self.y, self.yaw, self.hx, self.hy = x, y, yaw, hx, hy
        self.vx, self.vy, self.wz = vx, vy, wz

    def at(self, t):
        return Box2D(self.x + self.vx * t, self.y + self.vy * t, self.yaw + self.wz * t,
                     self.hx, self.hy, self.vx, self.vy, self.wz)

    def corners(self):
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        out = []
        for sx, sy in ((1, 1), (-1, 1), (-1, -1), (1, -1)):
            lx, ly = sx * self.hx, sy * self.hy
            out.append((self.x + c * lx - s * ly, self.y + s * lx + c * ly))
        return out

    def axes(self):
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        return [(c, s), (-s, c)]


def _overlap(a, b):
    ca, cb = a.corners(), b.corners()
    for ax in a.axes() + b.axes():
        pa = [p[0] * ax[0] + p[1] * ax[1] for p in ca]
        pb = [p[0] * ax[0] + p[1] * ax[1] for p in cb]
        if max(pa) < min(pb) or max(pb) < min(pa):
            return False
    return True


def _point_segment(p, a, b):
    dx, dy = b[0] - a[0], b[1] - a[1]
    L = dx * dx + dy * dy
    u = 0.0 if L == 0 else max(0.0, min(1.0, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / L))
    qx, qy = a[0] + u * dx, a[1] + u * dy
    return math.hypot(p[0] - qx, p[1] - qy)


def distance(a, b):
    """Distance between two footprints (0 when they overlap)."""
    if _overlap(a, b):
        return 0.0
    best = math.inf
    for P, Q in ((a, b), (b, a)):
        q = Q.corners()
        for p in P.corners():
            for i in range(4):
                best = min(best, _point_segment(p, q[i], q[(i + 1) % 4]))
    return best


def first_contact(a, b, reach, horizon, step=0.002):
    """Smallest t in [0, horizon] with distance(a(t), b(t)) <= reach (to 1e-6 s), or None."""
    def touching(t):
        return distance(a.at(t), b.at(t)) <= reach
    if touching(0.0):
        return 0.0
    # Fastest the gap can shrink: relative speed, plus rotation of each footprint's corners.
    shrink = (math.hypot(a.vx - b.vx, a.vy - b.vy) + abs(a.wz) * math.hypot(a.hx, a.hy) +
              abs(b.wz) * math.hypot(b.hx, b.hy))
    prev = 0.0
    while prev < horizon:
        gap = distance(a.at(prev), b.at(prev)) - reach
        safe = gap / shrink if shrink > 0 else math.inf
        t = min(horizon, prev + max(step, safe))
        if touching(t):
            lo, hi = prev, t
            while hi - lo > 1e-6:
                mid = 0.5 * (lo + hi)
                if touching(mid):
                    hi = mid
                else:
                    lo = mid
            return hi
        if t >= horizon:
            return None
        prev = t
    return None
