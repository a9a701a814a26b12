#include "workspace_proximity/ros/marker_builder.hpp"

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

}  // namespace

MarkerBuilder::MarkerBuilder(const std::string& frame, double lifetime)
    : frame_(frame), lifetime_(lifetime) {}

int MarkerBuilder::idFor(const std::string& key) {
  auto it = ids_.find(key);
  if (it != ids_.end()) return it->second;
  int id;
  if (!free_ids_.empty()) {
    id = free_ids_.back();
    free_ids_.pop_back();
  } else {
    id = next_id_++;
  }
  ids_.emplace(key, id);
  keys_.emplace(id, key);
  return id;
}

visualization_msgs::Marker MarkerBuilder::base(const std::string& ns, const std::string& key,
                                               const ros::Time& stamp) {
  visualization_msgs::Marker m;
  m.header.frame_id = frame_;
  m.header.stamp = stamp;
  m.ns = ns;
  m.id = idFor(ns + "|" + key);
  m.action = visualization_msgs::Marker::ADD;
  m.lifetime = lifetime_;
  m.pose.orientation.w = 1.0;
  m.frame_locked = false;
  current_.emplace(ns, m.id);
  return m;
}

void MarkerBuilder::build(const std::vector<MarkerBody>& bodies, const ContactEventArray& events,
                          const ros::Time& stamp, visualization_msgs::MarkerArray* out) {
  out->markers.clear();
  current_.clear();

  for (const MarkerBody& b : bodies) {
    visualization_msgs::Marker m = base("bodies", b.id, stamp);
    setPose(b.pose, &m);
    const Shape& s = b.shape;
    switch (s.type) {
      case ShapeType::kBox:
        m.type = visualization_msgs::Marker::CUBE;
        m.scale.x = 2 * s.half_extents.x();
        m.scale.y = 2 * s.half_extents.y();
        m.scale.z = 2 * s.half_extents.z();
        break;
      case ShapeType::kSphere:
        m.type = visualization_msgs::Marker::SPHERE;
        m.scale.x = m.scale.y = m.scale.z = 2 * s.radius;
        break;
      case ShapeType::kCylinder:
      case ShapeType::kCapsule:  // drawn as its enclosing cylinder
        m.type = visualization_msgs::Marker::CYLINDER;
        m.scale.x = m.scale.y = 2 * s.radius;
        m.scale.z = s.type == ShapeType::kCylinder ? s.length : s.length + 2 * s.radius;
        break;
    }
    m.color = levelColour(b.level, b.robot, 0.8f);
    out->markers.push_back(m);

    visualization_msgs::Marker w = base("swept", b.id, stamp);
    w.type = visualization_msgs::Marker::CUBE;
    w.pose.position = point(0.5 * (b.swept.lower + b.swept.upper));
    const Eigen::Vector3d size = b.swept.upper - b.swept.lower;
    w.scale.x = size.x();
    w.scale.y = size.y();
    w.scale.z = size.z();
    w.color = levelColour(b.level, b.robot, 0.12f);
    out->markers.push_back(w);

    if (b.velocity.norm() > 1e-3) {
      visualization_msgs::Marker v = base("velocity", b.id, stamp);
      v.type = visualization_msgs::Marker::ARROW;
      v.points.push_back(point(b.pose.translation()));
      v.points.push_back(point(b.pose.translation() + b.velocity));  // 1 s of motion
      v.scale.x = 0.04;  // shaft diameter
      v.scale.y = 0.08;  // head diameter
      v.scale.z = 0.12;  // head length
      v.color = colour(0.9f, 0.9f, 0.9f, 0.9f);
      out->markers.push_back(v);
    }
  }

  for (const ContactEvent& e : events.events) {
    if (e.state == ContactEvent::END) continue;
    const std::string key = e.id_a + "|" + e.id_b;
    visualization_msgs::Marker line = base("nearest", key, stamp);
    line.type = visualization_msgs::Marker::LINE_LIST;
    line.points.push_back(e.point_a);
    line.points.push_back(e.point_b);
    line.scale.x = 0.02;
    line.color = levelColour(e.level, false, 1.0f);
    out->markers.push_back(line);

    visualization_msgs::Marker text = base("ttc_text", key, stamp);
    text.type = visualization_msgs::Marker::TEXT_VIEW_FACING;
    text.pose.position.x = 0.5 * (e.point_a.x + e.point_b.x);
    text.pose.position.y = 0.5 * (e.point_a.y + e.point_b.y);
    text.pose.position.z = 0.5 * (e.point_a.z + e.point_b.z) + 0.15;
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.2f s", e.time_to_contact);
    text.text = buffer;
    text.scale.z = 0.18;  // text height, m
    text.color = levelColour(e.level, false, 1.0f);
    out->markers.push_back(text);
  }

  // Whatever was shown last cycle and is gone now is deleted explicitly.
  for (const auto& old : published_) {
    if (current_.count(old)) continue;
    visualization_msgs::Marker d;
    d.header.frame_id = frame_;
    d.header.stamp = stamp;
    d.ns = old.first;
    d.id = old.second;
    d.action = visualization_msgs::Marker::DELETE;
    out->markers.push_back(d);
    // Forget the key so a long run with many short tracks does not grow the tables.
    auto k = keys_.find(old.second);
    if (k != keys_.end()) {
      ids_.erase(k->second);
      keys_.erase(k);
      free_ids_.push_back(old.second);
    }
  }
  published_.swap(current_);
}

}  // namespace workspace_proximity
