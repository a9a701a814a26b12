#include "workspace_proximity/ros/marker_builder.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <workspace_proximity/ContactEvent.h>

namespace workspace_proximity {
namespace {

using visualization_msgs::Marker;

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

void setPose(const Eigen::Isometry3d& pose, Marker* m) {
  m->pose.position = point(pose.translation());
  const Eigen::Quaterniond q(pose.linear());
  m->pose.orientation.w = q.w();
  m->pose.orientation.x = q.x();
  m->pose.orientation.y = q.y();
  m->pose.orientation.z = q.z();
}

void setShape(const Shape& s, Marker* m) {
  switch (s.type) {
    case ShapeType::kBox:
      m->type = Marker::CUBE;
      m->scale.x = 2 * s.half_extents.x();
      m->scale.y = 2 * s.half_extents.y();
      m->scale.z = 2 * s.half_extents.z();
      break;
    case ShapeType::kSphere:
      m->type = Marker::SPHERE;
      m->scale.x = m->scale.y = m->scale.z = 2 * s.radius;
      break;
    case ShapeType::kCylinder:
    case ShapeType::kCapsule:  // drawn as its enclosing cylinder
      m->type = Marker::CYLINDER;
      m->scale.x = m->scale.y = 2 * s.radius;
      m->scale.z = s.type == ShapeType::kCylinder ? s.length : s.length + 2 * s.radius;
      break;
  }
}

// Namespaces of the per-body markers, as bits of MarkerBuilder's per-slot masks.
constexpr std::uint8_t kBodies = 1, kSwept = 2, kVelocity = 4;
constexpr std::pair<std::uint8_t, const char*> kBodyNamespaces[] = {
    {kBodies, "bodies"}, {kSwept, "swept"}, {kVelocity, "velocity"}};

// Grows a per-index flag array to hold `index` (with the world's slots or the pair pool only).
void fit(std::vector<std::uint8_t>* flags, std::size_t index) {
  if (index >= flags->size()) flags->resize(index + 1, 0);
}

}  // namespace

MarkerBuilder::MarkerBuilder(const std::string& frame, double lifetime)
    : frame_(frame), lifetime_(lifetime) {}

Marker& MarkerBuilder::add(const char* ns, std::int32_t id, std::uint8_t action,
                           visualization_msgs::MarkerArray* out) {
  if (used_ == out->markers.size()) out->markers.emplace_back();
  Marker& m = out->markers[used_++];
  m.header.frame_id = frame_;
  m.header.stamp = stamp_;
  m.ns = ns;
  m.id = id;
  m.type = Marker::CUBE;
  m.action = action;
  m.pose = geometry_msgs::Pose();
  m.pose.orientation.w = 1.0;
  m.scale = geometry_msgs::Vector3();
  m.color = std_msgs::ColorRGBA();
  m.lifetime = action == Marker::ADD ? lifetime_ : ros::Duration();
  m.frame_locked = false;
  m.points.clear();
  m.colors.clear();
  m.text.clear();
  m.mesh_resource.clear();
  m.mesh_use_embedded_materials = false;
  return m;
}

void MarkerBuilder::build(const CycleReport& report, const ProximityWorld& world,
                          visualization_msgs::MarkerArray* out) {
  stamp_.fromNSec(static_cast<std::uint64_t>(report.stamp));
  used_ = 0;
  std::fill(showing_.begin(), showing_.end(), 0);
  std::fill(pair_showing_.begin(), pair_showing_.end(), 0);
  for (const ReportedBody& b : report.bodies) {
    if (world.contains(b.handle)) addBody(b, report.bodyLevel(b.handle.index), world, out);
  }
  for (std::size_t i = 0; i < report.eventCount(); ++i) {
    const PairEvent& e = report.event(i);
    if (e.state != ContactState::kEnd && e.pair >= 0) addPair(e, report.levels[i], out);
  }
  deleteVanished(out);
  out->markers.resize(used_);
}

void MarkerBuilder::addBody(const ReportedBody& b, int level, const ProximityWorld& world,
                            visualization_msgs::MarkerArray* out) {
  const auto slot = static_cast<std::size_t>(b.handle.index);
  fit(&showing_, slot);
  const BodyMotion& motion = world.motion(b.handle);
  const Eigen::Isometry3d pose = motion.poseAt(0.0);

  Marker& m = add("bodies", b.handle.index, Marker::ADD, out);
  setPose(pose, &m);
  setShape(world.desc(b.handle).shape, &m);
  m.color = levelColour(level, b.robot, 0.8f);
  showing_[slot] |= kBodies;

  const Aabb swept = world.sweptBounds(b.handle);
  Marker& w = add("swept", b.handle.index, Marker::ADD, out);
  w.type = Marker::CUBE;
  w.pose.position = point(0.5 * (swept.lower + swept.upper));
  const Eigen::Vector3d size = swept.upper - swept.lower;
  w.scale.x = size.x();
  w.scale.y = size.y();
  w.scale.z = size.z();
  w.color = levelColour(level, b.robot, 0.12f);
  showing_[slot] |= kSwept;

  if (motion.linear_velocity.norm() > 1e-3) {
    Marker& v = add("velocity", b.handle.index, Marker::ADD, out);
    v.type = Marker::ARROW;
    v.points.push_back(point(pose.translation()));
    v.points.push_back(point(pose.translation() + motion.linear_velocity));  // 1 s of motion
    v.scale.x = 0.04;  // shaft diameter
    v.scale.y = 0.08;  // head diameter
    v.scale.z = 0.12;  // head length
    v.color = colour(0.9f, 0.9f, 0.9f, 0.9f);
    showing_[slot] |= kVelocity;
  }
}

void MarkerBuilder::addPair(const PairEvent& e, Level level, visualization_msgs::MarkerArray* out) {
  fit(&pair_showing_, static_cast<std::size_t>(e.pair));
  pair_showing_[static_cast<std::size_t>(e.pair)] = 1;
  const int l = static_cast<int>(level);

  Marker& line = add("nearest", e.pair, Marker::ADD, out);
  line.type = Marker::LINE_LIST;
  line.points.push_back(point(e.point_a));
  line.points.push_back(point(e.point_b));
  line.scale.x = 0.02;
  line.color = levelColour(l, false, 1.0f);

  Marker& text = add("ttc_text", e.pair, Marker::ADD, out);
  text.type = Marker::TEXT_VIEW_FACING;
  text.pose.position = point(0.5 * (e.point_a + e.point_b));
  text.pose.position.z += 0.15;
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.2f s", e.time_to_contact);
  text.text = buffer;
  text.scale.z = 0.18;  // text height, m
  text.color = levelColour(l, false, 1.0f);
}

void MarkerBuilder::deleteVanished(visualization_msgs::MarkerArray* out) {
  // Whatever was shown last build and is gone now is deleted explicitly.
  if (shown_.size() < showing_.size()) shown_.resize(showing_.size(), 0);
  for (std::size_t slot = 0; slot < shown_.size(); ++slot) {
    const std::uint8_t now = slot < showing_.size() ? showing_[slot] : 0;
    const std::uint8_t gone = shown_[slot] & static_cast<std::uint8_t>(~now);
    for (const auto& ns : kBodyNamespaces) {
      if (gone & ns.first) add(ns.second, static_cast<std::int32_t>(slot), Marker::DELETE, out);
    }
    shown_[slot] = now;
  }
  if (pair_shown_.size() < pair_showing_.size()) pair_shown_.resize(pair_showing_.size(), 0);
  for (std::size_t id = 0; id < pair_shown_.size(); ++id) {
    const std::uint8_t now = id < pair_showing_.size() ? pair_showing_[id] : 0;
    if (pair_shown_[id] && !now) {
      add("nearest", static_cast<std::int32_t>(id), Marker::DELETE, out);
      add("ttc_text", static_cast<std::int32_t>(id), Marker::DELETE, out);
    }
    pair_shown_[id] = now;
  }
}

}  // namespace workspace_proximity
