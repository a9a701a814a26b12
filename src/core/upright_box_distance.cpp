#include "workspace_proximity/upright_box_distance.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "upright_corners.hpp"

namespace workspace_proximity {

namespace upright {

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

}  // namespace upright

namespace {

using upright::nearestCornerTo;
using upright::Vec2;

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

}  // namespace workspace_proximity
