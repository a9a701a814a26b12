#include "workspace_proximity/ros/conversions.hpp"

#include <cmath>
#include <sstream>

namespace workspace_proximity {
namespace {

bool finite(const geometry_msgs::Vector3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
bool finite(const geometry_msgs::Point& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
Eigen::Vector3d vec(const geometry_msgs::Vector3& v) { return Eigen::Vector3d(v.x, v.y, v.z); }
Eigen::Vector3d vec(const geometry_msgs::Point& v) { return Eigen::Vector3d(v.x, v.y, v.z); }
geometry_msgs::Vector3 toVector3(const Eigen::Vector3d& v) {
  geometry_msgs::Vector3 m;
  m.x = v.x();
  m.y = v.y();
  m.z = v.z();
  return m;
}
geometry_msgs::Point toPoint(const Eigen::Vector3d& v) {
  geometry_msgs::Point m;
  m.x = v.x();
  m.y = v.y();
  m.z = v.z();
  return m;
}

// A rejection reason from its parts (only built when a box is rejected).
template <typename... Parts>
std::string explain(const Parts&... parts) {
  std::ostringstream why;
  (why << ... << parts);
  return why.str();
}

}  // namespace

std::string checkTrackedBox(const TrackedBox& box, const BoxLimits& limits) {
  // Called for every box of every array: the stream is only built to explain a rejection.
  if (box.id.empty()) return "empty id";
  const auto& q = box.pose.orientation;
  if (!finite(box.pose.position) || !std::isfinite(q.x) || !std::isfinite(q.y) ||
      !std::isfinite(q.z) || !std::isfinite(q.w)) {
    return "non-finite pose";
  }
  if (!finite(box.dimensions)) return "non-finite dimensions";
  if (!finite(box.twist.linear) || !finite(box.twist.angular)) return "non-finite twist";
  const Eigen::Vector3d d = vec(box.dimensions);
  if ((d.array() < 2.0 * Limits::kMinSize).any()) {
    return explain("dimensions ", d.transpose(), " m: every edge must be at least ",
                   2.0 * Limits::kMinSize, " m");
  }
  if ((d.array() > limits.max_dimension).any()) {
    return explain("dimensions ", d.transpose(), " m: an edge exceeds ", limits.max_dimension,
                   " m");
  }
  if (vec(box.pose.position).cwiseAbs().maxCoeff() > limits.max_coordinate) {
    return explain("position ", vec(box.pose.position).transpose(), " m is beyond ",
                   limits.max_coordinate, " m");
  }
  const double qn = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
  if (std::abs(qn - 1.0) > limits.quaternion_tolerance) {
    return explain("orientation quaternion has length ", qn, " (must be 1 within ",
                   limits.quaternion_tolerance, ")");
  }
  if (vec(box.twist.linear).norm() > limits.max_speed) {
    return explain("speed ", vec(box.twist.linear).norm(), " m/s exceeds ", limits.max_speed);
  }
  if (vec(box.twist.angular).norm() > limits.max_angular_speed) {
    return explain("angular speed ", vec(box.twist.angular).norm(), " rad/s exceeds ",
                   limits.max_angular_speed);
  }
  return std::string();
}

Shape toShape(const TrackedBox& box) { return Shape::box(0.5 * vec(box.dimensions)); }

BodyMotion toMotion(const TrackedBox& box, const Eigen::Isometry3d& fixed_from_box_frame) {
  const auto& q = box.pose.orientation;
  const Eigen::Quaterniond orientation = Eigen::Quaterniond(q.w, q.x, q.y, q.z).normalized();
  const Eigen::Matrix3d rotation = fixed_from_box_frame.linear();
  BodyMotion m;
  m.position = fixed_from_box_frame * vec(box.pose.position);
  // Boxes given in the fixed frame (the usual case) keep their quaternion as it is.
  m.orientation = rotation.isIdentity(0.0)
                      ? orientation
                      : Eigen::Quaterniond(rotation * orientation.toRotationMatrix()).normalized();
  m.linear_velocity = rotation * vec(box.twist.linear);
  m.angular_velocity = rotation * vec(box.twist.angular);
  return m;
}

TrackedBox toTrackedBox(const std::string& id, const std::string& label, const Shape& shape,
                        const BodyMotion& motion) {
  TrackedBox box;
  box.id = id;
  box.label = label;
  box.pose.position = toPoint(motion.position);
  box.pose.orientation.w = motion.orientation.w();
  box.pose.orientation.x = motion.orientation.x();
  box.pose.orientation.y = motion.orientation.y();
  box.pose.orientation.z = motion.orientation.z();
  box.dimensions = toVector3(2.0 * shape.localHalfExtents());
  box.twist.linear = toVector3(motion.linear_velocity);
  box.twist.angular = toVector3(motion.angular_velocity);
  return box;
}

std::uint8_t contactLevel(const PairEvent& event, const LabelSettings& a, const LabelSettings& b) {
  if (event.state == ContactState::kEnd) return ContactEvent::NOTICE;
  auto level = [&](const LabelSettings& l) -> std::uint8_t {
    if (event.time_to_contact <= l.critical_time || event.distance <= l.critical_distance) {
      return ContactEvent::CRITICAL;
    }
    if (event.time_to_contact <= l.warning_time || event.distance <= l.warning_distance) {
      return ContactEvent::WARNING;
    }
    return ContactEvent::NOTICE;
  };
  return std::max(level(a), level(b));
}

ContactEvent toMsg(const PairEvent& event, const BodyDesc& a, const BodyDesc& b,
                   std::uint8_t level) {
  ContactEvent msg;
  toMsg(event, a, b, level, &msg);
  return msg;
}

void toMsg(const PairEvent& event, const BodyDesc& a, const BodyDesc& b, std::uint8_t level,
           ContactEvent* out) {
  ContactEvent& msg = *out;
  msg.state = static_cast<std::uint8_t>(event.state);
  msg.id_a = a.id;
  msg.id_b = b.id;
  msg.label_a = a.label;
  msg.label_b = b.label;
  msg.time_to_contact = event.time_to_contact;
  msg.time_to_separation = event.time_to_separation;
  msg.distance = event.distance;
  msg.point_a = toPoint(event.point_a);
  msg.point_b = toPoint(event.point_b);
  msg.normal = toVector3(event.normal);
  msg.closing_speed = event.closing_speed;
  msg.level = level;
  msg.stale = false;
}

PairEvent fromMsg(const ContactEvent& msg) {
  PairEvent e;
  e.state = static_cast<ContactState>(msg.state);
  e.time_to_contact = msg.time_to_contact;
  e.time_to_separation = msg.time_to_separation;
  e.distance = msg.distance;
  e.point_a = vec(msg.point_a);
  e.point_b = vec(msg.point_b);
  e.normal = vec(msg.normal);
  e.closing_speed = msg.closing_speed;
  return e;
}

}  // namespace workspace_proximity
