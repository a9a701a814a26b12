#include "workspace_proximity/ros/marker_builder.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace workspace_proximity {
namespace {

std_msgs::ColorRGBA colour(float r, float g, float b, float a) {
  std_msgs::ColorRGBA c;
  c.r = r;
  c.g = g;
  c.b = b;
  c.a = a;
  return c;
}

std_msgs::ColorRGBA levelColour(int level, bool robot, float alpha) {
  switch (level) {
    case ContactEvent::NOTICE:
      return colour(1.0f, 0.9f, 0.1f, alpha);
    case ContactEvent::WARNING:
      return colour(1.0f, 0.5f, 0.0f, alpha);
    case ContactEvent::CRITICAL:
      return colour(1.0f, 0.1f, 0.1f, alpha);
    default:
      return robot ? colour(0.3f, 0.5f, 1.0f, alpha) : colour(0.2f, 0.8f, 0.3f, alpha);
  }
}

geometry_msgs::Point point(const Eigen::Vector3d& v) {
  geometry_msgs::Point p;
  p.x = v.x();
  p.y = v.y();
  p.z = v.z();
  return p;
}

void setPose(const Eigen::Isometry3d& pose, visualization_msgs::Marker* m) {
  m->pose.position = point(pose.translation());
  const Eigen::Quaterniond q(pose.linear());
  m->pose.orientation.w = q.w();
  m->pose.orientation.x = q.x();
  m->pose.orientation.y = q.y();
  m->pose.orientation.z = q.z();
}

// Namespaces of the per-body markers, as bits of MarkerBuilder's per-slot masks.
constexpr std::uint8_t kBodies = 1, kSwept = 2, kVelocity = 4;
constexpr std::pair<std::uint8_t, const char*> kBodyNamespaces[] = {
    {kBodies, "bodies"}, {kSwept, "swept"}, {kVelocity, "velocity"}};

}  // namespace

MarkerBuilder::MarkerBuilder(const std::string& frame, double lifetime)
    : frame_(frame), lifetime_(lifetime), pairs_(256) {}

visualization_msgs::Marker& MarkerBuilder::add(const char* ns, std::int32_t id,
                                               const ros::Time& stamp, std::uint8_t action,
                                               visualization_msgs::MarkerArray* out) {
  if (used_ == out->markers.size()) out->markers.emplace_back();
  visualization_msgs::Marker& m = out->markers[used_++];
  m.header.frame_id = frame_;
  m.header.stamp = stamp;
  m.ns = ns;
  m.id = id;
  m.type = visualization_msgs::Marker::CUBE;
  m.action = action;
  m.pose = geometry_msgs::Pose();
  m.pose.orientation.w = 1.0;
  m.scale = geometry_msgs::Vector3();
  m.color = std_msgs::ColorRGBA();
  m.lifetime = action == visualization_msgs::Marker::ADD ? lifetime_ : ros::Duration();
  m.frame_locked = false;
  m.points.clear();
  m.colors.clear();
  m.text.clear();
  m.mesh_resource.clear();
  m.mesh_use_embedded_materials = false;
  return m;
}

void MarkerBuilder::build(const std::vector<MarkerBody>& bodies, const ContactEventArray& events,
                          const std::vector<std::pair<std::int32_t, std::int32_t>>& event_slots,
                          const ros::Time& stamp, visualization_msgs::MarkerArray* out) {
  using visualization_msgs::Marker;
  used_ = 0;
  ++serial_;
  std::fill(showing_.begin(), showing_.end(), 0);

  for (const MarkerBody& b : bodies) {
    const auto slot = static_cast<std::size_t>(b.slot);
    if (slot >= showing_.size()) showing_.resize(slot + 1, 0);  // grows with the world only

    Marker& m = add("bodies", b.slot, stamp, Marker::ADD, out);
    setPose(b.pose, &m);
    const Shape& s = b.shape;
    switch (s.type) {
      case ShapeType::kBox:
        m.type = Marker::CUBE;
        m.scale.x = 2 * s.half_extents.x();
        m.scale.y = 2 * s.half_extents.y();
        m.scale.z = 2 * s.half_extents.z();
        break;
      case ShapeType::kSphere:
        m.type = Marker::SPHERE;
        m.scale.x = m.scale.y = m.scale.z = 2 * s.radius;
        break;
      case ShapeType::kCylinder:
      case ShapeType::kCapsule:  // drawn as its enclosing cylinder
        m.type = Marker::CYLINDER;
        m.scale.x = m.scale.y = 2 * s.radius;
        m.scale.z = s.type == ShapeType::kCylinder ? s.length : s.length + 2 * s.radius;
        break;
    }
    m.color = levelColour(b.level, b.robot, 0.8f);
    showing_[slot] |= kBodies;

    Marker& w = add("swept", b.slot, stamp, Marker::ADD, out);
    w.type = Marker::CUBE;
    w.pose.position = point(0.5 * (b.swept.lower + b.swept.upper));
    const Eigen::Vector3d size = b.swept.upper - b.swept.lower;
    w.scale.x = size.x();
    w.scale.y = size.y();
    w.scale.z = size.z();
    w.color = levelColour(b.level, b.robot, 0.12f);
    showing_[slot] |= kSwept;

    if (b.velocity.norm() > 1e-3) {
      Marker& v = add("velocity", b.slot, stamp, Marker::ADD, out);
      v.type = Marker::ARROW;
      v.points.push_back(point(b.pose.translation()));
      v.points.push_back(point(b.pose.translation() + b.velocity));  // 1 s of motion
      v.scale.x = 0.04;  // shaft diameter
      v.scale.y = 0.08;  // head diameter
      v.scale.z = 0.12;  // head length
      v.color = colour(0.9f, 0.9f, 0.9f, 0.9f);
      showing_[slot] |= kVelocity;
    }
  }

  for (std::size_t i = 0; i < events.events.size() && i < event_slots.size(); ++i) {
    const ContactEvent& e = events.events[i];
    if (e.state == ContactEvent::END) continue;
    bool inserted = false;
    ProxyPair* pair = pairs_.insert(event_slots[i].first, event_slots[i].second, &inserted);
    if (inserted) {
      if (!free_ids_.empty()) {
        pair->user = static_cast<std::uint32_t>(free_ids_.back());
        free_ids_.pop_back();
      } else {
        pair->user = static_cast<std::uint32_t>(next_id_++);
      }
    }
    pair->stamp = serial_;
    const auto id = static_cast<std::int32_t>(pair->user);

    Marker& line = add("nearest", id, stamp, Marker::ADD, out);
    line.type = Marker::LINE_LIST;
    line.points.push_back(e.point_a);
    line.points.push_back(e.point_b);
    line.scale.x = 0.02;
    line.color = levelColour(e.level, false, 1.0f);

    Marker& text = add("ttc_text", id, stamp, Marker::ADD, out);
    text.type = Marker::TEXT_VIEW_FACING;
    text.pose.position.x = 0.5 * (e.point_a.x + e.point_b.x);
    text.pose.position.y = 0.5 * (e.point_a.y + e.point_b.y);
    text.pose.position.z = 0.5 * (e.point_a.z + e.point_b.z) + 0.15;
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.2f s", e.time_to_contact);
    text.text = buffer;
    text.scale.z = 0.18;  // text height, m
    text.color = levelColour(e.level, false, 1.0f);
  }

  // Whatever was shown last build and is gone now is deleted explicitly.
  if (shown_.size() < showing_.size()) shown_.resize(showing_.size(), 0);
  for (std::size_t slot = 0; slot < shown_.size(); ++slot) {
    const std::uint8_t now = slot < showing_.size() ? showing_[slot] : 0;
    const std::uint8_t gone = shown_[slot] & static_cast<std::uint8_t>(~now);
    if (gone == 0) continue;
    for (const auto& ns : kBodyNamespaces) {
      if (gone & ns.first) add(ns.second, static_cast<std::int32_t>(slot), stamp, Marker::DELETE, out);
    }
  }
  std::copy(showing_.begin(), showing_.end(), shown_.begin());
  // Backwards: eraseAt moves the last pair into the hole, which has been visited already.
  for (int i = pairs_.size() - 1; i >= 0; --i) {
    const ProxyPair& p = pairs_.pairs()[static_cast<std::size_t>(i)];
    if (p.stamp == serial_) continue;
    const auto id = static_cast<std::int32_t>(p.user);
    add("nearest", id, stamp, Marker::DELETE, out);
    add("ttc_text", id, stamp, Marker::DELETE, out);
    free_ids_.push_back(id);
    pairs_.eraseAt(i);
  }
  out->markers.resize(used_);
}

}  // namespace workspace_proximity
