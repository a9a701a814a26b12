#include "workspace_proximity/ros/conversions.hpp"

namespace workspace_proximity {
namespace {

static_assert(static_cast<int>(Level::kNotice) == ContactEvent::NOTICE &&
                  static_cast<int>(Level::kWarning) == ContactEvent::WARNING &&
                  static_cast<int>(Level::kCritical) == ContactEvent::CRITICAL,
              "Level and ContactEvent's level constants must agree");
static_assert(static_cast<int>(ContactState::kBegin) == ContactEvent::BEGIN &&
                  static_cast<int>(ContactState::kOngoing) == ContactEvent::ONGOING &&
                  static_cast<int>(ContactState::kEnd) == ContactEvent::END,
              "ContactState and ContactEvent's state constants must agree");

Eigen::Vector3d vec(const geometry_msgs::Vector3& v) { return Eigen::Vector3d(v.x, v.y, v.z); }
Eigen::Vector3d vec(const geometry_msgs::Point& v) { return Eigen::Vector3d(v.x, v.y, v.z); }
void toVector3(const Eigen::Vector3d& v, geometry_msgs::Vector3* m) {
  m->x = v.x();
  m->y = v.y();
  m->z = v.z();
}
void toPoint(const Eigen::Vector3d& v, geometry_msgs::Point* m) {
  m->x = v.x();
  m->y = v.y();
  m->z = v.z();
}

}  // namespace

void observe(const TrackedBox& box, BoxObservation* out) {
  out->id = box.id;
  out->label = box.label;
  out->position = vec(box.pose.position);
  const auto& q = box.pose.orientation;
  out->quaternion = Eigen::Vector4d(q.x, q.y, q.z, q.w);
  out->dimensions = vec(box.dimensions);
  out->linear_velocity = vec(box.twist.linear);
  out->angular_velocity = vec(box.twist.angular);
  // Zeros (every array published before these fields, and v1 arrays decoded as foreign) say
  // "the label's settings"; checkBox rejects NaN and negative errors by name.
  out->position_error = box.position_error;
  out->velocity_error = box.velocity_error;
  out->velocity_known = !box.velocity_unknown;
}

BoxObservation observe(const TrackedBox& box) {
  BoxObservation o;
  observe(box, &o);
  return o;
}

TrackedBox toTrackedBox(const std::string& id, const std::string& label, const Shape& shape,
                        const BodyMotion& motion) {
  TrackedBox box;
  box.id = id;
  box.label = label;
  toPoint(motion.position, &box.pose.position);
  box.pose.orientation.w = motion.orientation.w();
  box.pose.orientation.x = motion.orientation.x();
  box.pose.orientation.y = motion.orientation.y();
  box.pose.orientation.z = motion.orientation.z();
  toVector3(2.0 * shape.localHalfExtents(), &box.dimensions);
  toVector3(motion.linear_velocity, &box.twist.linear);
  toVector3(motion.angular_velocity, &box.twist.angular);
  return box;
}

void toMsg(const PairEvent& event, const BodyDesc& a, const BodyDesc& b, Level level,
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
  toPoint(event.point_a, &msg.point_a);
  toPoint(event.point_b, &msg.point_b);
  toVector3(event.normal, &msg.normal);
  msg.closing_speed = event.closing_speed;
  msg.level = static_cast<std::uint8_t>(level);
  msg.stale = false;
}

ContactEvent toMsg(const PairEvent& event, const BodyDesc& a, const BodyDesc& b, Level level) {
  ContactEvent msg;
  toMsg(event, a, b, level, &msg);
  return msg;
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
