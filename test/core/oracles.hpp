#pragma once
// Independent reference checks for the tests. Nothing here calls the library's algorithms:
// these are the brute-force and textbook answers the library is compared against.

#include <algorithm>
#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace oracle {

struct Obb {
  Eigen::Vector3d center;
  Eigen::Matrix3d rotation;  // columns: the box's axes in the world
  Eigen::Vector3d half;
};

// Closed oriented boxes overlap iff no separating axis among the 3 + 3 face normals and the
// 9 edge cross products separates them (separating axis theorem for convex polytopes).
inline bool overlaps(const Obb& a, const Obb& b) {
  Eigen::Vector3d axes[15];
  int n = 0;
  for (int i = 0; i < 3; ++i) axes[n++] = a.rotation.col(i);
  for (int i = 0; i < 3; ++i) axes[n++] = b.rotation.col(i);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const Eigen::Vector3d c = a.rotation.col(i).cross(b.rotation.col(j));
      if (c.squaredNorm() > 1e-12) axes[n++] = c.normalized();
    }
  }
  const Eigen::Vector3d d = b.center - a.center;
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d& l = axes[k];
    double ra = 0.0, rb = 0.0;
    for (int i = 0; i < 3; ++i) {
      ra += a.half[i] * std::abs(l.dot(a.rotation.col(i)));
      rb += b.half[i] * std::abs(l.dot(b.rotation.col(i)));
    }
    if (std::abs(d.dot(l)) > ra + rb) return false;
  }
  return true;
}

// Pose of a body at time t under constant linear and world-frame angular velocity, written
// out independently of BodyMotion::poseAt.
inline Obb obbAt(const Eigen::Vector3d& c0, const Eigen::Quaterniond& q0, const Eigen::Vector3d& half,
                 const Eigen::Vector3d& v, const Eigen::Vector3d& w, double t) {
  Obb o;
  o.center = c0 + v * t;
  const double angle = w.norm() * t;
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  if (angle != 0.0) {
    // Rodrigues' formula.
    const Eigen::Vector3d k = w.normalized();
    Eigen::Matrix3d kx;
    kx << 0, -k.z(), k.y(), k.z(), 0, -k.x(), -k.y(), k.x(), 0;
    r = Eigen::Matrix3d::Identity() + std::sin(angle) * kx + (1 - std::cos(angle)) * kx * kx;
  }
  o.rotation = r * q0.normalized().toRotationMatrix();
  o.half = half;
  return o;
}

}  // namespace oracle
