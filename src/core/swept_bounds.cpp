#include "workspace_proximity/swept_bounds.hpp"

#include <algorithm>
#include <cmath>

namespace workspace_proximity {

namespace {

// Exact half extents of the shape's world AABB at orientation R.
Eigen::Vector3d staticHalfExtents(const Shape& shape, const Eigen::Matrix3d& r) {
  switch (shape.type) {
    case ShapeType::kSphere:
      return Eigen::Vector3d::Constant(shape.radius);
    case ShapeType::kCapsule: {
      // Segment along local z of half length L/2, swept by a ball of the radius.
      const Eigen::Vector3d axis = r.col(2).cwiseAbs();
      return axis * (0.5 * shape.length) + Eigen::Vector3d::Constant(shape.radius);
    }
    case ShapeType::kCylinder: {
      // Segment plus a disc of the radius perpendicular to the axis: the disc's extent along
      // world axis k is radius * sqrt(1 - a_k^2).
      const Eigen::Vector3d axis = r.col(2);
      Eigen::Vector3d half;
      for (int k = 0; k < 3; ++k) {
        half[k] = std::abs(axis[k]) * 0.5 * shape.length +
                  shape.radius * std::sqrt(std::max(0.0, 1.0 - axis[k] * axis[k]));
      }
      return half;
    }
    case ShapeType::kBox:
      break;
  }
  // Box: h_k = sum_j |R_kj| e_j.
  return r.cwiseAbs() * shape.half_extents;
}

}  // namespace

Eigen::Vector3d rotationHalfExtents(const Shape& shape, const BodyMotion& motion, double margin,
                                    double horizon) {
  return rotationHalfExtents(shape, motion.orientation.normalized().toRotationMatrix(),
                             motion.angular_velocity, margin, horizon);
}

Eigen::Vector3d rotationHalfExtents(const Shape& shape, const Eigen::Matrix3d& rotation,
                                    const Eigen::Vector3d& angular_velocity, double margin,
                                    double horizon) {
  Eigen::Vector3d half = staticHalfExtents(shape, rotation);
  // Not turning (the common case: people, vehicles, resting links): the box as it is.
  if (isExactlyZero(angular_velocity)) return half.array() + margin;

  const double speed = angular_velocity.norm();
  const double theta = std::min(speed * std::max(horizon, 0.0), M_PI);
  if (theta > 0.0 && shape.type != ShapeType::kSphere) {
    // Rotation about the fixed world axis k by at most theta moves a unit vector u by the
    // chord 2 sin(theta / 2) |u_perp| (u_perp: its part perpendicular to k), and only
    // within the plane perpendicular to k, so world axis j sees at most that times
    // sqrt(1 - k_j^2). Summed over the local box's axes this bounds how much |R_ji| e_i
    // can grow; the bounding sphere caps the result for large turns.
    const double chord = 2.0 * std::sin(0.5 * theta);
    const Eigen::Vector3d k = angular_velocity / speed;
    const Eigen::Vector3d local = shape.localHalfExtents();
    const Eigen::Vector3d box_now = rotation.cwiseAbs() * local;
    double sweep = 0.0;  // sum_i e_i |c_i perpendicular to k|
    for (int i = 0; i < 3; ++i) {
      const double along = k.dot(rotation.col(i));
      sweep += local[i] * std::sqrt(std::max(0.0, 1.0 - along * along));
    }
    const double cap = shape.boundingRadius();
    for (int j = 0; j < 3; ++j) {
      const double off_axis = std::sqrt(std::max(0.0, 1.0 - k[j] * k[j]));
      half[j] = std::min(box_now[j] + chord * off_axis * sweep, cap);
    }
  }
  return half.array() + margin;
}

Aabb sweptBounds(const Shape& shape, const BodyMotion& motion, double margin, double horizon) {
  return sweptBoundsOfHalf(rotationHalfExtents(shape, motion, margin, horizon), motion, horizon);
}

Aabb sweptBoundsOfHalf(const Eigen::Vector3d& half, const BodyMotion& motion, double horizon) {
  const Eigen::Vector3d start = motion.position;
  const Eigen::Vector3d end = motion.position + motion.linear_velocity * std::max(horizon, 0.0);
  return Aabb{start.cwiseMin(end) - half, start.cwiseMax(end) + half};
}

}  // namespace workspace_proximity
