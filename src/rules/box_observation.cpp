#include "workspace_proximity/rules/box_observation.hpp"

#include <cmath>
#include <sstream>

namespace workspace_proximity {
namespace {

// A rejection's explanation from its parts (only built when a box is rejected).
template <typename... Parts>
std::string explain(const Parts&... parts) {
  std::ostringstream why;
  (why << ... << parts);
  return why.str();
}

}  // namespace

Drop checkBox(const BoxObservation& box, const BoxLimits& limits, std::string* detail) {
  // Called for every box of every array: the explanation is only built on a rejection.
  auto reject = [&](Drop reason, std::string text) {
    *detail = std::move(text);
    return reason;
  };
  if (box.id.empty()) return reject(Drop::kEmptyId, "empty id");
  if (!box.position.allFinite() || !box.quaternion.allFinite()) {
    return reject(Drop::kNonFinite, "non-finite pose");
  }
  if (!box.dimensions.allFinite()) return reject(Drop::kNonFinite, "non-finite dimensions");
  if (!box.linear_velocity.allFinite() || !box.angular_velocity.allFinite()) {
    return reject(Drop::kNonFinite, "non-finite twist");
  }
  if (!std::isfinite(box.position_error) || !std::isfinite(box.velocity_error)) {
    return reject(Drop::kNonFinite, "non-finite position_error or velocity_error");
  }
  const Eigen::Vector3d& d = box.dimensions;
  if ((d.array() < 2.0 * Limits::kMinSize).any()) {
    return reject(Drop::kDimensions, explain("dimensions ", d.transpose(),
                                             " m: every edge must be at least ",
                                             2.0 * Limits::kMinSize, " m"));
  }
  if ((d.array() > limits.max_dimension).any()) {
    return reject(Drop::kDimensions, explain("dimensions ", d.transpose(), " m: an edge exceeds ",
                                             limits.max_dimension, " m"));
  }
  if (box.position.cwiseAbs().maxCoeff() > limits.max_coordinate) {
    return reject(Drop::kPosition, explain("position ", box.position.transpose(), " m is beyond ",
                                           limits.max_coordinate, " m"));
  }
  // The tracker's own errors: a negative bound means nothing, one beyond the limits is nonsense
  // (and would grow the track over the whole cell).
  if (box.position_error < 0.0 || box.position_error > limits.max_dimension) {
    return reject(Drop::kPosition, explain("position_error ", box.position_error,
                                           " m must be in [0, ", limits.max_dimension, "]"));
  }
  if (box.velocity_error < 0.0 || box.velocity_error > limits.max_speed) {
    return reject(Drop::kSpeed, explain("velocity_error ", box.velocity_error,
                                        " m/s must be in [0, ", limits.max_speed, "]"));
  }
  const double qn = box.quaternion.norm();
  if (std::abs(qn - 1.0) > limits.quaternion_tolerance) {
    return reject(Drop::kOrientation, explain("orientation quaternion has length ", qn,
                                              " (must be 1 within ", limits.quaternion_tolerance,
                                              ")"));
  }
  if (box.linear_velocity.norm() > limits.max_speed) {
    return reject(Drop::kSpeed, explain("speed ", box.linear_velocity.norm(), " m/s exceeds ",
                                        limits.max_speed));
  }
  if (box.angular_velocity.norm() > limits.max_angular_speed) {
    return reject(Drop::kAngularSpeed, explain("angular speed ", box.angular_velocity.norm(),
                                               " rad/s exceeds ", limits.max_angular_speed));
  }
  return Drop::kCount;
}

Shape boxShape(const BoxObservation& box) { return Shape::box(0.5 * box.dimensions); }

BodyMotion boxMotion(const BoxObservation& box, const Eigen::Isometry3d& fixed_from_box_frame) {
  const Eigen::Vector4d& q = box.quaternion;
  const Eigen::Quaterniond orientation = Eigen::Quaterniond(q.w(), q.x(), q.y(), q.z()).normalized();
  const Eigen::Matrix3d rotation = fixed_from_box_frame.linear();
  BodyMotion m;
  m.position = fixed_from_box_frame * box.position;
  // Boxes given in the fixed frame (the usual case) keep their quaternion as it is.
  m.orientation = rotation.isIdentity(0.0)
                      ? orientation
                      : Eigen::Quaterniond(rotation * orientation.toRotationMatrix()).normalized();
  m.linear_velocity = rotation * box.linear_velocity;
  m.angular_velocity = rotation * box.angular_velocity;
  return m;
}

}  // namespace workspace_proximity
