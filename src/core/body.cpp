#include "workspace_proximity/body.hpp"

#include <cmath>

namespace workspace_proximity {

namespace {

// A shape of the given type and dimensions; half_extents is the local bounding box's.
Shape makeShape(ShapeType type, const Eigen::Vector3d& half_extents, double radius, double length) {
  Shape s;
  s.type = type;
  s.radius = radius;
  s.length = length;
  s.half_extents = half_extents;
  if (type != ShapeType::kBox) s.half_extents = s.localHalfExtents();
  return s;
}

}  // namespace

Shape Shape::box(const Eigen::Vector3d& half_extents) {
  return makeShape(ShapeType::kBox, half_extents, 0.0, 0.0);
}
Shape Shape::sphere(double radius) {
  return makeShape(ShapeType::kSphere, Eigen::Vector3d::Zero(), radius, 0.0);
}
Shape Shape::cylinder(double radius, double length) {
  return makeShape(ShapeType::kCylinder, Eigen::Vector3d::Zero(), radius, length);
}
Shape Shape::capsule(double radius, double length) {
  return makeShape(ShapeType::kCapsule, Eigen::Vector3d::Zero(), radius, length);
}

Eigen::Vector3d Shape::localHalfExtents() const {
  switch (type) {
    case ShapeType::kBox:
      return half_extents;
    case ShapeType::kSphere:
      return Eigen::Vector3d::Constant(radius);
    case ShapeType::kCylinder:
      return Eigen::Vector3d(radius, radius, 0.5 * length);
    case ShapeType::kCapsule:
      return Eigen::Vector3d(radius, radius, 0.5 * length + radius);
  }
  return half_extents;
}

double Shape::boundingRadius() const {
  switch (type) {
    case ShapeType::kBox:
      return half_extents.norm();
    case ShapeType::kSphere:
      return radius;
    case ShapeType::kCylinder:
      return std::hypot(radius, 0.5 * length);
    case ShapeType::kCapsule:
      return 0.5 * length + radius;
  }
  return half_extents.norm();
}

bool Shape::valid() const {
  auto positive = [](double x) {
    return std::isfinite(x) && x >= Limits::kMinSize && x <= Limits::kMaxSize;
  };
  switch (type) {
    case ShapeType::kBox:
      return positive(half_extents.x()) && positive(half_extents.y()) && positive(half_extents.z());
    case ShapeType::kSphere:
      return positive(radius);
    case ShapeType::kCylinder:
      return positive(radius) && positive(length);
    case ShapeType::kCapsule:
      // A capsule of zero segment length is a sphere, which FCL handles.
      return positive(radius) && (length == 0.0 || positive(length));
  }
  return false;
}

bool validMargin(double margin) {
  return std::isfinite(margin) && margin >= 0.0 && margin <= Limits::kMaxMargin;
}

Eigen::Isometry3d BodyMotion::poseAt(double t) const {
  Eigen::Quaterniond q = orientation;
  if (t != 0.0) {
    const double speed = angular_velocity.norm();
    if (speed > 0.0) {
      q = Eigen::Quaterniond(Eigen::AngleAxisd(speed * t, angular_velocity / speed)) * orientation;
    }
  }
  // Every entry written once (no identity first): this runs for every moved body per cycle.
  Eigen::Isometry3d pose;
  pose.linear() = q.normalized().toRotationMatrix();
  pose.translation() = position + linear_velocity * t;
  pose.makeAffine();
  return pose;
}

BodyMotion BodyMotion::advanced(double dt) const {
  BodyMotion m = *this;
  if (isExactlyZero(angular_velocity)) {
    // Not turning: the orientation stays exactly as it is (no matrix round trip).
    m.position = position + linear_velocity * dt;
    return m;
  }
  const Eigen::Isometry3d pose = poseAt(dt);
  m.position = pose.translation();
  m.orientation = Eigen::Quaterniond(pose.linear()).normalized();
  return m;
}

bool BodyMotion::valid() const {
  return position.allFinite() && linear_velocity.allFinite() && angular_velocity.allFinite() &&
         orientation.coeffs().allFinite() && std::abs(orientation.norm() - 1.0) <= 1e-6 &&
         position.cwiseAbs().maxCoeff() <= Limits::kMaxCoordinate &&
         linear_velocity.norm() <= Limits::kMaxSpeed &&
         angular_velocity.norm() <= Limits::kMaxAngularSpeed;
}

}  // namespace workspace_proximity
