#include "workspace_proximity/upright_box_distance.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace workspace_proximity {
namespace {

using Vec2 = Eigen::Vector2d;

// A box's footprint: centre, unit axes and half sizes in the x-y plane.
struct Footprint {
  Vec2 centre, u, v;
  double hu, hv;

  Footprint(const Eigen::Isometry3d& pose, const Eigen::Vector3d& half)
      : centre(pose.translation().head<2>()),
        u(pose.linear().col(0).head<2>()),
        v(pose.linear().col(1).head<2>()),
        hu(half.x()),
        hv(half.y()) {}

  Vec2 corner(int i) const {
    return centre + ((i & 1) ? hu : -hu) * u + ((i & 2) ? hv : -hv) * v;
  }
  // Half width of the projection on unit axis n.
  double radius(const Vec2& n) const { return hu * std::abs(n.dot(u)) + hv * std::abs(n.dot(v)); }
};

// `other` seen from `self`'s frame: the offset of its centre and its two axes, in self's
// (u, v) coordinates. In that frame self is the axis-aligned rectangle [-hu, hu] x [-hv, hv],
// so the separating-axis test and the nearest points take a few products each.
struct Seen {
  Vec2 centre, u, v;
  Seen(const Footprint& self, const Footprint& other) {
    const Vec2 d = other.centre - self.centre;
    centre = Vec2(self.u.dot(d), self.v.dot(d));
    u = Vec2(self.u.dot(other.u), self.v.dot(other.u));
    v = Vec2(self.u.dot(other.v), self.v.dot(other.v));
  }
};

// Largest separating-axis gap over self's two edge normals; with both orders this covers the
// four axes that decide whether two rectangles are disjoint (> 0: disjoint).
double gapAlongOwnAxes(const Footprint& self, const Footprint& other, const Seen& s) {
  const double gu = std::abs(s.centre.x()) - self.hu - other.hu * std::abs(s.u.x()) -
                    other.hv * std::abs(s.v.x());
  const double gv = std::abs(s.centre.y()) - self.hv - other.hu * std::abs(s.u.y()) -
                    other.hv * std::abs(s.v.y());
  return std::max(gu, gv);
}

// The nearest of a rectangle's four corners (centre `centre`, half-size vectors eu and ev, all
// in self's frame) to self's rectangle [-high, high]: the squared distance, the corner and its
// nearest point on self (clamped to the rectangle).
double nearestCornerTo(const Vec2& high, const Vec2& centre, const Vec2& eu, const Vec2& ev,
                       Vec2* corner, Vec2* on_self) {
  const Vec2 low = -high;
  double best = HUGE_VAL;
  for (int i = 0; i < 4; ++i) {
    const Vec2 q = centre + ((i & 1) ? eu : -eu) + ((i & 2) ? ev : -ev);
    // The clamp to the rectangle, both coordinates at once (one packed max and min).
    const Vec2 p = q.cwiseMax(low).cwiseMin(high);
    const double d = (q - p).squaredNorm();
    if (d < best) {
      best = d;
      *corner = q;
      *on_self = p;
    }
  }
  return best;
}

// The nearest of other's four corners to self's rectangle, in self's frame.
double nearestCorner(const Footprint& self, const Footprint& other, const Seen& s, Vec2* corner,
                     Vec2* on_self) {
  return nearestCornerTo(Vec2(self.hu, self.hv), s.centre, other.hu * s.u, other.hv * s.v,
                         corner, on_self);
}

// A point given in self's frame, in world x-y.
Vec2 toWorld(const Footprint& self, const Vec2& p) {
  return self.centre + p.x() * self.u + p.y() * self.v;
}

// Nearest points of two disjoint footprints: the pair has a vertex of one of them, so it is
// the better of each one's nearest corner to the other's rectangle.
void nearestPoints(const Footprint& fa, const Footprint& fb, const Seen& b_from_a,
                   const Seen& a_from_b, Vec2* pa, Vec2* pb) {
  Vec2 corner_b, on_a, corner_a, on_b;
  const double via_b = nearestCorner(fa, fb, b_from_a, &corner_b, &on_a);
  const double via_a = nearestCorner(fb, fa, a_from_b, &corner_a, &on_b);
  if (via_b < via_a) {
    *pa = toWorld(fa, on_a);
    *pb = toWorld(fa, corner_b);
  } else {
    *pa = toWorld(fb, corner_a);
    *pb = toWorld(fb, on_b);
  }
}

// A point common to both footprints: a's rectangle clipped by b's four half planes
// (Sutherland-Hodgman), averaged. False when rounding leaves nothing.
bool commonPoint(const Footprint& a, const Footprint& b, Vec2* out) {
  std::array<Vec2, 16> poly, next;
  int n = 4;
  poly[0] = a.corner(0);
  poly[1] = a.corner(1);
  poly[2] = a.corner(3);
  poly[3] = a.corner(2);
  const std::array<std::pair<Vec2, double>, 4> planes = {{{b.u, b.hu + b.u.dot(b.centre)},
                                                          {-b.u, b.hu - b.u.dot(b.centre)},
                                                          {b.v, b.hv + b.v.dot(b.centre)},
                                                          {-b.v, b.hv - b.v.dot(b.centre)}}};
  for (const auto& plane : planes) {  // keep n . p <= offset
    int m = 0;
    for (int i = 0; i < n; ++i) {
      const Vec2& p = poly[i];
      const Vec2& q = poly[(i + 1) % n];
      const double sp = plane.first.dot(p) - plane.second;
      const double sq = plane.first.dot(q) - plane.second;
      if (sp <= 0.0) next[m++] = p;
      if ((sp < 0.0 && sq > 0.0) || (sp > 0.0 && sq < 0.0)) {
        next[m++] = p + (sp / (sp - sq)) * (q - p);
      }
    }
    n = m;
    std::swap(poly, next);
    if (n == 0) return false;
  }
  Vec2 sum = Vec2::Zero();
  for (int i = 0; i < n; ++i) sum += poly[i];
  *out = sum / n;
  return true;
}

// Contact of touching or overlapping boxes: `xy`, `z` a common point; the normal is the
// axis (of the five that can separate two vertical prisms) with the least overlap, pointing
// from a towards b.
UprightBoxDistance overlap(const Footprint& fa, const Footprint& fb,
                           const Eigen::Isometry3d& pose_a, const Eigen::Vector3d& half_a,
                           const Eigen::Isometry3d& pose_b, const Eigen::Vector3d& half_b,
                           const Vec2& xy, double z) {
  UprightBoxDistance out;
  out.solved = true;
  out.overlapping = true;
  out.point_a = out.point_b = Eigen::Vector3d(xy.x(), xy.y(), z);
  const Eigen::Vector3d d = pose_b.translation() - pose_a.translation();
  // z first: stacked boxes separate vertically when that is no worse.
  double least = half_a.z() + half_b.z() - std::abs(d.z());
  out.normal = Eigen::Vector3d(0.0, 0.0, d.z() < 0.0 ? -1.0 : 1.0);
  for (const Vec2* n : {&fa.u, &fa.v, &fb.u, &fb.v}) {
    const double along = n->dot(d.head<2>());
    const double depth = fa.radius(*n) + fb.radius(*n) - std::abs(along);
    if (depth < least) {
      least = depth;
      out.normal = Eigen::Vector3d(n->x(), n->y(), 0.0) * (along < 0.0 ? -1.0 : 1.0);
    }
  }
  return out;
}

}  // namespace

UprightBoxDistance uprightBoxDistance(const Eigen::Isometry3d& pose_a,
                                      const Eigen::Vector3d& half_a,
                                      const Eigen::Isometry3d& pose_b,
                                      const Eigen::Vector3d& half_b) {
  UprightBoxDistance out;
  const Footprint fa(pose_a, half_a), fb(pose_b, half_b);

  // Height intervals and their gap.
  const double za = pose_a.translation().z(), zb = pose_b.translation().z();
  const double a_lo = za - half_a.z(), a_hi = za + half_a.z();
  const double b_lo = zb - half_b.z(), b_hi = zb + half_b.z();
  double pa_z, pb_z;
  double dz = 0.0;
  if (b_lo > a_hi) {
    dz = b_lo - a_hi;
    pa_z = a_hi;
    pb_z = b_lo;
  } else if (a_lo > b_hi) {
    dz = a_lo - b_hi;
    pa_z = a_lo;
    pb_z = b_hi;
  } else {
    pa_z = pb_z = 0.5 * (std::max(a_lo, b_lo) + std::min(a_hi, b_hi));
  }

  Vec2 pa_xy, pb_xy;
  const Seen b_from_a(fa, fb), a_from_b(fb, fa);
  if (std::max(gapAlongOwnAxes(fa, fb, b_from_a), gapAlongOwnAxes(fb, fa, a_from_b)) > 0.0) {
    nearestPoints(fa, fb, b_from_a, a_from_b, &pa_xy, &pb_xy);
  } else {
    // Footprints overlap: one box straight above the other, or the boxes overlap.
    if (!commonPoint(fa, fb, &pa_xy)) return out;
    pb_xy = pa_xy;
    if (dz == 0.0) return overlap(fa, fb, pose_a, half_a, pose_b, half_b, pa_xy, pa_z);
  }
  out.point_a = Eigen::Vector3d(pa_xy.x(), pa_xy.y(), pa_z);
  out.point_b = Eigen::Vector3d(pb_xy.x(), pb_xy.y(), pb_z);
  out.distance = (out.point_b - out.point_a).norm();
  if (!(out.distance > 0.0)) {
    // Touching: report it as a contact, like overlapping boxes.
    return overlap(fa, fb, pose_a, half_a, pose_b, half_b, pa_xy, pa_z);
  }
  out.normal = (out.point_b - out.point_a) / out.distance;
  out.solved = true;
  return out;
}

namespace {

// ------------------------------------------------------------------------------------------
// Rounded upright boxes in translation (roundedUprightInterval). Everything happens in the
// two footprints' frames: a's centred at the origin, b's at b's centre relative to a's, which
// moves linearly, so every coordinate below is x0 + x1 t.

using std::abs;

// Narrows [*first, *last] to the instants at which |x0 + x1 t| <= reach.
inline void clipAbs(double x0, double x1, double reach, double* first, double* last) {
  if (x1 == 0.0) {
    if (abs(x0) > reach) *first = HUGE_VAL;  // never: empty
    return;
  }
  const double t0 = (-reach - x0) / x1, t1 = (reach - x0) / x1;
  *first = std::max(*first, widenDown(std::min(t0, t1)));
  *last = std::min(*last, widenUp(std::max(t0, t1)));
}

// One footprint seen from another's frame: the other's centre `c` and half-size vectors
// `eu`, `ev` there; the frame's own half sizes hu, hv.
struct View {
  Vec2 c, eu, ev;
  double hu, hv;
};

// Among the viewed footprint's corners, the nearest to the frame's rectangle: the squared
// distance, whether the rectangle's nearest point is a corner too, and the vector from that
// point to the corner (in the frame).
double nearestCornerIn(const View& s, bool* corner_pair, Vec2* between) {
  Vec2 corner, on_self;
  const double d2 = nearestCornerTo(Vec2(s.hu, s.hv), s.c, s.eu, s.ev, &corner, &on_self);
  *corner_pair = abs(corner.x()) > s.hu && abs(corner.y()) > s.hv;
  *between = corner - on_self;
  return d2;
}

// Does the viewed footprint touch the frame's face with normal along the frame's axis k (0:
// u, 1: v, on the side of its centre) with its nearest corner (or, when parallel, an edge)
// within that face? Then the footprints' distance is their gap along that axis.
bool onFace(const View& s, int k) {
  const int j = 1 - k;
  const double side = s.c[k] < 0.0 ? -1.0 : 1.0;
  double along = s.c[j], spread = 0.0;
  for (const Vec2* e : {&s.eu, &s.ev}) {
    const double toward = side * (*e)[k];
    if (abs(toward) > 1e-12 * (abs((*e)[0]) + abs((*e)[1]))) {
      along -= toward > 0.0 ? (*e)[j] : -(*e)[j];  // the corner on self's side
    } else {
      spread += abs((*e)[j]);  // parallel: a whole edge faces the frame's face
    }
  }
  return abs(along) <= (k == 0 ? s.hv : s.hu) + spread;
}

// How far apart two footprints are that do not overlap.
struct FootprintGap {
  double distance = 0.0;  // m
  bool corner_pair = false;  // both nearest points are corners
  Vec2 corners = Vec2::Zero();  // then b's corner minus a's, in world x-y
};

}  // namespace

bool roundedUprightInterval(const Eigen::Isometry3d& pose_a, const Eigen::Vector3d& half_a,
                            const Eigen::Vector3d& velocity_a, const Eigen::Isometry3d& pose_b,
                            const Eigen::Vector3d& half_b, const Eigen::Vector3d& velocity_b,
                            double inflation, TimeInterval window, TimeInterval* out) {
  const Eigen::Vector3d d = pose_b.translation() - pose_a.translation();
  const Eigen::Vector3d w = velocity_b - velocity_a;
  if (!(inflation > 0.0) || !std::isfinite(window.first) || !std::isfinite(window.last) ||
      !d.allFinite() || !w.allFinite()) {
    return false;
  }
  if (window.empty()) {
    *out = TimeInterval{};
    return true;
  }
  const Eigen::Matrix3d& ra = pose_a.linear();
  const Eigen::Matrix3d& rb = pose_b.linear();
  const Vec2 ua(ra(0, 0), ra(1, 0)), va(ra(0, 1), ra(1, 1));
  const Vec2 ub(rb(0, 0), rb(1, 0)), vb(rb(0, 1), rb(1, 1));
  const double c11 = ua.dot(ub), c12 = ua.dot(vb), c21 = va.dot(ub), c22 = va.dot(vb);
  const Vec2 d2 = d.head<2>(), w2 = w.head<2>();
  // b seen from a (its centre at pa0 + pa1 t) and a seen from b.
  View in_a{Vec2::Zero(), half_b.x() * Vec2(c11, c21), half_b.y() * Vec2(c12, c22), half_a.x(), half_a.y()};
  View in_b{Vec2::Zero(), half_a.x() * Vec2(c11, c12), half_a.y() * Vec2(c21, c22), half_b.x(), half_b.y()};
  const Vec2 pa0(ua.dot(d2), va.dot(d2)), pa1(ua.dot(w2), va.dot(w2));
  const Vec2 pb0(-ub.dot(d2), -vb.dot(d2)), pb1(-ub.dot(w2), -vb.dot(w2));
  // Each frame's half sizes plus the other footprint's support on its axes.
  const Vec2 reach_a = Vec2(in_a.hu, in_a.hv) + in_a.eu.cwiseAbs() + in_a.ev.cwiseAbs();
  const Vec2 reach_b = Vec2(in_b.hu, in_b.hv) + in_b.eu.cwiseAbs() + in_b.ev.cwiseAbs();
  // A nanometre (and rounding's share of the scene's size) more: never narrower than exact.
  const double scale = abs(d.x()) + abs(d.y()) + half_a.x() + half_a.y() + half_b.x() +
                       half_b.y() + inflation;  // >= the norms it stands for
  const double radius = inflation + 1e-9 + 64.0 * std::numeric_limits<double>::epsilon() * scale;

  // The separating axes of two vertical prisms (four footprint normals and z), each grown by
  // the inflation: every contact lies in this interval (its ends widened as in
  // axisContactInterval), and at its ends the gap is within the radius but for the corners.
  double first = window.first, last = window.last;
  clipAbs(pa0.x(), pa1.x(), reach_a.x() + inflation, &first, &last);
  clipAbs(pa0.y(), pa1.y(), reach_a.y() + inflation, &first, &last);
  clipAbs(pb0.x(), pb1.x(), reach_b.x() + inflation, &first, &last);
  clipAbs(pb0.y(), pb1.y(), reach_b.y() + inflation, &first, &last);
  const double heights = half_a.z() + half_b.z();
  clipAbs(d.z(), w.z(), heights + inflation, &first, &last);
  if (!(first <= last)) {
    *out = TimeInterval{};
    return true;
  }
  // The footprints decide alone while the heights overlap: the distance is then the
  // footprints' distance. |z gap| is convex in t, so both ends suffice.
  if (w.z() == 0.0 ? abs(d.z()) > heights
                   : abs(d.z() + w.z() * first) > heights || abs(d.z() + w.z() * last) > heights) {
    return false;
  }

  // The footprints' distance at t: cheaply when the separating axis of largest gap has the
  // other footprint's nearest corner on its face (the gap is then the distance), else from
  // the corners (two disjoint convex polygons are nearest at a corner of one of them).
  auto near = [&](double t) {
    in_a.c = pa0 + pa1 * t;
    in_b.c = pb0 + pb1 * t;
    const Vec2 gap_a = in_a.c.cwiseAbs() - reach_a, gap_b = in_b.c.cwiseAbs() - reach_b;
    const int k_a = gap_a.y() > gap_a.x(), k_b = gap_b.y() > gap_b.x();
    const double max_a = gap_a[k_a], max_b = gap_b[k_b];
    return std::max(max_a, max_b) <= 0.0 ||  // overlapping
           (std::max(max_a, max_b) <= radius &&
            (max_a >= max_b ? onFace(in_a, k_a) : onFace(in_b, k_b)));
  };
  auto gap = [&]() {  // at the instant near() last set
    FootprintGap g;
    bool pair_b = false, pair_a = false;
    Vec2 between_b, between_a;
    const double via_b = nearestCornerIn(in_a, &pair_b, &between_b);
    const double via_a = nearestCornerIn(in_b, &pair_a, &between_a);
    if (via_b <= via_a) {
      g.distance = std::sqrt(via_b);
      g.corner_pair = pair_b;
      g.corners = between_b.x() * ua + between_b.y() * va;  // a's corner to b's
    } else {
      g.distance = std::sqrt(via_a);
      g.corner_pair = pair_a;
      g.corners = -(between_a.x() * ub + between_a.y() * vb);  // b's to a's, reversed
    }
    return g;
  };

  // Each end: within reach there (it stays), or in the pocket of two corners that are apart
  // by more (it moves to where their distance reaches the radius, or contact never comes).
  enum class End { kStays, kMoves, kNever, kUndecided };
  auto end = [&](double t, bool at_first, double* moved) {
    if (near(t)) return End::kStays;  // most ends: on a face
    const FootprintGap g = gap();
    if (g.distance <= radius) return End::kStays;
    // Outside reach but not at two corners: only rounding puts an instant of the interval
    // there (its points lie within the grown separating axes).
    if (!g.corner_pair) return End::kUndecided;
    // The two corners' distance over time: |corners + w s| <= radius for s in [s0, s1].
    const double qa = w2.squaredNorm(), qb = g.corners.dot(w2);
    const double qc = g.corners.squaredNorm() - radius * radius;
    const double disc = qb * qb - qa * qc;
    if (qa == 0.0 || !(disc >= 0.0)) return End::kNever;
    const double root = std::sqrt(disc);
    const double s0 = (-qb - root) / qa, s1 = (-qb + root) / qa;
    if (at_first) {
      if (s1 < 0.0) return End::kNever;  // past the corners' disk: moving apart
      const double at = t + std::max(s0, 0.0);
      if (at > last) return End::kNever;
      *moved = at;
      return End::kMoves;
    }
    if (s0 > 0.0) return End::kNever;  // not there yet: contact only after the interval
    const double at = t + std::min(s1, 0.0);
    if (at < first) return End::kNever;
    *moved = at;
    return End::kMoves;
  };
  double moved_first = first, moved_last = last;
  const End head = end(first, true, &moved_first);
  const End tail = end(last, false, &moved_last);
  if (head == End::kUndecided || tail == End::kUndecided) return false;
  // A pocket's disk missed at one end means no contact at all (a line meets a convex set in
  // one piece); the other end must agree, or rounding decided one of them.
  if ((head == End::kNever) != (tail == End::kNever)) return false;
  if (head == End::kNever) {
    *out = TimeInterval{};
    return true;
  }
  if (moved_first > moved_last) return false;
  out->first = std::max(first, widenDown(moved_first));
  out->last = std::min(last, widenUp(moved_last));
  return true;
}

}  // namespace workspace_proximity
