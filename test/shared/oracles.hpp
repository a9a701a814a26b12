#pragma once
// Independent reference answers for the tests, fuzz harnesses and benchmarks. Nothing here
// calls the library's algorithms (only its plain data types cross the boundary): these are
// the brute-force and textbook answers the library is compared against.

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "workspace_proximity/aabb.hpp"

namespace oracle {

// ------------------------------------------------------------------------------------------
// Axis-aligned boxes.

/// Closed boxes overlap (touching counts) iff their intervals overlap on every axis; the
/// comparisons are written so that NaN never overlaps.
/// (Box: Aabb, or anything with lower[k] and upper[k]: the fuzz harness passes plain arrays,
/// whose loops its sanitizer build does not trace through Eigen's checked accessors.)
template <class Box>
inline bool aabbOverlap(const Box& a, const Box& b) {
  for (int k = 0; k < 3; ++k) {
    if (!(a.lower[k] <= b.upper[k]) || !(b.lower[k] <= a.upper[k])) return false;
  }
  return true;
}

/// The same for bounds read back from a SweepAndPrune (storedBounds(), enlargedBounds()): an
/// upper bound read back as -0.0 stands for a key just below zero (the upper-tagged key of the
/// smallest negative number), so it does not reach a lower bound at +0.0.
template <class Box>
inline bool readBackOverlap(const Box& a, const Box& b) {
  auto reaches = [](double lower, double upper) {
    if (lower == 0.0 && upper == 0.0) return !std::signbit(upper) || std::signbit(lower);
    return lower <= upper;
  };
  for (int k = 0; k < 3; ++k) {
    if (!reaches(a.lower[k], b.upper[k]) || !reaches(b.lower[k], a.upper[k])) return false;
  }
  return true;
}

// ------------------------------------------------------------------------------------------
// Motion: pose at time t under constant linear and world-frame angular velocity, written out
// with Rodrigues' formula, independently of BodyMotion::poseAt.

inline Eigen::Isometry3d poseAt(const Eigen::Vector3d& position, const Eigen::Quaterniond& orientation,
                                const Eigen::Vector3d& velocity, const Eigen::Vector3d& angular,
                                double t) {
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  const double angle = angular.norm() * t;
  if (angle != 0.0) {
    const Eigen::Vector3d k = angular.normalized();
    Eigen::Matrix3d kx;
    kx << 0, -k.z(), k.y(), k.z(), 0, -k.x(), -k.y(), k.x(), 0;
    r = Eigen::Matrix3d::Identity() + std::sin(angle) * kx + (1 - std::cos(angle)) * kx * kx;
  }
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = r * orientation.normalized().toRotationMatrix();
  pose.translation() = position + velocity * t;
  return pose;
}

/// The same for anything with position, orientation, linear_velocity and angular_velocity
/// (BodyMotion's fields).
template <class Motion>
Eigen::Isometry3d poseAt(const Motion& m, double t) {
  return poseAt(m.position, m.orientation, m.linear_velocity, m.angular_velocity, t);
}

/// Pose from a translation and a rotation.
inline Eigen::Isometry3d makePose(const Eigen::Vector3d& t,
                                  const Eigen::Quaterniond& q = Eigen::Quaterniond::Identity()) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = q.normalized().toRotationMatrix();
  pose.translation() = t;
  return pose;
}

// ------------------------------------------------------------------------------------------
// Piecewise motion and growing margins, written out from their definitions
// (motion_path.hpp) independently of the library.

/// Pose at time t along a piecewise constant-twist path: anything with a vector of segments
/// with start, motion (BodyMotion's fields) and margin. The segment in force is the last one
/// starting at or before t.
template <class Segment>
Eigen::Isometry3d pathPoseAt(const std::vector<Segment>& path, double t) {
  std::size_t k = 0;
  while (k + 1 < path.size() && path[k + 1].start <= t) ++k;
  return poseAt(path[k].motion, t - path[k].start);
}

/// The segment margin in force at t.
template <class Segment>
double pathMarginAt(const std::vector<Segment>& path, double t) {
  std::size_t k = 0;
  while (k + 1 < path.size() && path[k + 1].start <= t) ++k;
  return path[k].margin;
}

/// Margin grown s = age + t seconds after an observation: min(e s + a s^2 / 2, cap s).
inline double grownMargin(double velocity_error, double max_accel, double speed_cap, double age,
                          double t) {
  const double s = age + t;
  const double quadratic = velocity_error * s + 0.5 * max_accel * s * s;
  return std::isinf(speed_cap) ? quadratic : std::min(quadratic, speed_cap * s);
}

// ------------------------------------------------------------------------------------------
// Oriented boxes.

/// Oriented box: pose of the centre and half extents, m.
struct Obb {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  Eigen::Vector3d half = Eigen::Vector3d::Constant(0.5);
};

inline std::array<Eigen::Vector3d, 8> vertices(const Obb& box) {
  std::array<Eigen::Vector3d, 8> v;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d local((i & 1) ? box.half.x() : -box.half.x(),
                                (i & 2) ? box.half.y() : -box.half.y(),
                                (i & 4) ? box.half.z() : -box.half.z());
    v[i] = box.pose * local;
  }
  return v;
}

/// Closed oriented boxes overlap iff no axis among the 3 + 3 face normals and the 9 edge cross
/// products separates them (separating axis theorem for convex polytopes). Cross products of
/// (nearly) parallel edges are skipped: the face axes already cover them.
inline bool overlaps(const Obb& a, const Obb& b) {
  const Eigen::Matrix3d ra = a.pose.linear(), rb = b.pose.linear();
  const Eigen::Vector3d d = b.pose.translation() - a.pose.translation();
  auto separates = [&](const Eigen::Vector3d& axis) {
    const double n = axis.norm();
    if (n < 1e-9) return false;
    const Eigen::Vector3d u = axis / n;
    double ra_u = 0.0, rb_u = 0.0;
    for (int i = 0; i < 3; ++i) {
      ra_u += a.half[i] * std::abs(ra.col(i).dot(u));
      rb_u += b.half[i] * std::abs(rb.col(i).dot(u));
    }
    return std::abs(d.dot(u)) > ra_u + rb_u;
  };
  for (int i = 0; i < 3; ++i) {
    if (separates(ra.col(i)) || separates(rb.col(i))) return false;
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (separates(ra.col(i).cross(rb.col(j)))) return false;
    }
  }
  return true;
}

/// Exact distance from a point to a solid oriented box (0 inside), m.
inline double pointBoxDistance(const Eigen::Vector3d& p, const Obb& box) {
  const Eigen::Vector3d local = box.pose.inverse() * p;
  const Eigen::Vector3d clamped = local.cwiseMax(-box.half).cwiseMin(box.half);
  return (local - clamped).norm();
}

/// How deep a point is inside a box (<= 0 outside or on the surface), m.
inline double pointBoxDepth(const Eigen::Vector3d& p, const Obb& box) {
  const Eigen::Vector3d local = box.pose.inverse() * p;
  return (box.half - local.cwiseAbs()).minCoeff();
}

// ------------------------------------------------------------------------------------------
// Segments (capsule axes, box edges).

/// Closest points c1 on segment [p1, q1] and c2 on [p2, q2]; degenerate segments allowed.
inline void segmentClosestPoints(const Eigen::Vector3d& p1, const Eigen::Vector3d& q1,
                                 const Eigen::Vector3d& p2, const Eigen::Vector3d& q2,
                                 Eigen::Vector3d* c1, Eigen::Vector3d* c2) {
  const Eigen::Vector3d d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0.0, t = 0.0;
  if (a <= 1e-300 && e > 1e-300) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else if (a > 1e-300) {
    const double c = d1.dot(r);
    if (e <= 1e-300) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      // Closest points of the infinite lines, clamped to segment 1, then to segment 2.
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > 1e-300 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  *c1 = p1 + d1 * s;
  *c2 = p2 + d2 * t;
}

/// Exact distance between segments [p1, q1] and [p2, q2], m.
inline double segmentDistance(const Eigen::Vector3d& p1, const Eigen::Vector3d& q1,
                              const Eigen::Vector3d& p2, const Eigen::Vector3d& q2) {
  Eigen::Vector3d c1, c2;
  segmentClosestPoints(p1, q1, p2, q2, &c1, &c2);
  return (c2 - c1).norm();
}

/// Exact distance between two disjoint boxes: the closest pair is vertex-face, face-vertex or
/// edge-edge, so the minimum over those features is the answer.
inline double boxBoxDistance(const Obb& a, const Obb& b) {
  static const int kEdges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                    {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  const auto va = vertices(a), vb = vertices(b);
  double best = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& v : va) best = std::min(best, pointBoxDistance(v, b));
  for (const Eigen::Vector3d& v : vb) best = std::min(best, pointBoxDistance(v, a));
  for (const auto& ea : kEdges) {
    for (const auto& eb : kEdges) {
      best = std::min(best, segmentDistance(va[ea[0]], va[ea[1]], vb[eb[0]], vb[eb[1]]));
    }
  }
  return best;
}

// ------------------------------------------------------------------------------------------
// Time.

/// First and last time in [t0, t1] at which `touching` holds, sampled every `step` seconds
/// and refined by bisection. Returns false when no sample touches.
inline bool contactTimes(const std::function<bool(double)>& touching, double t0, double t1,
                         double step, double* first, double* last) {
  const int n = static_cast<int>(std::ceil((t1 - t0) / step));
  int first_k = -1, last_k = -1;
  for (int k = 0; k <= n; ++k) {
    if (touching(std::min(t0 + k * step, t1))) {
      if (first_k < 0) first_k = k;
      last_k = k;
    }
  }
  if (first_k < 0) return false;
  auto bisect = [&](double free_t, double hit_t) {
    for (int i = 0; i < 60; ++i) {
      const double mid = 0.5 * (free_t + hit_t);
      (touching(mid) ? hit_t : free_t) = mid;
    }
    return hit_t;
  };
  const double hit_first = std::min(t0 + first_k * step, t1);
  const double hit_last = std::min(t0 + last_k * step, t1);
  *first = first_k == 0 ? t0 : bisect(t0 + (first_k - 1) * step, hit_first);
  *last = last_k == n ? t1 : bisect(std::min(t0 + (last_k + 1) * step, t1), hit_last);
  return true;
}

}  // namespace oracle
