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
  const Eigen::Matrix3d rotation = motion.orientation.normalized().toRotationMatrix();
  Eigen::Vector3d half = staticHalfExtents(shape, rotation);

  const double theta = std::min(motion.angular_velocity.norm() * std::max(horizon, 0.0), M_PI);
  if (theta > 0.0 && shape.type != ShapeType::kSphere) {
    // Each column of R(t) moves by at most the chord 2 sin(theta / 2), so every |R_kj(t)|
    // grows by at most that much: the rotated local box grows by chord * sum(local half
    // extents) on every axis. The bounding sphere caps the result for large turns.
    const double chord = 2.0 * std::sin(0.5 * theta);
    const Eigen::Vector3d local = shape.localHalfExtents();
    const Eigen::Vector3d box_now = rotation.cwiseAbs() * local;
    const double cap = shape.boundingRadius();
    for (int k = 0; k < 3; ++k) {
      half[k] = std::min(box_now[k] + chord * local.sum(), cap);
    }
  }
  return half.array() + margin;
}

Aabb sweptBounds(const Shape& shape, const BodyMotion& motion, double margin, double horizon) {
  const Eigen::Vector3d half = rotationHalfExtents(shape, motion, margin, horizon);
  const Eigen::Vector3d start = motion.position;
  const Eigen::Vector3d end = motion.position + motion.linear_velocity * std::max(horizon, 0.0);
  return Aabb{start.cwiseMin(end) - half, start.cwiseMax(end) + half};
}

}  // namespace workspace_proximity
