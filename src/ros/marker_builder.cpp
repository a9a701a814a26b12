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
constexpr std::uint8_t kBodies = 1, kSwept = 2, kVelocity = 4, kIds = 8;
constexpr std::pair<std::uint8_t, const char*> kBodyNamespaces[] = {
    {kBodies, "bodies"}, {kSwept, "swept"}, {kVelocity, "velocity"}, {kIds, "ids"}};

const char* levelName(Level level) {
  switch (level) {
    case Level::kWarning: return "WARNING";
    case Level::kCritical: return "CRITICAL";
    default: return "NOTICE";
  }
}

// Labels of pairs that share a body start at the same place; spread them along the pair's line
// and in height by the pair id (golden-ratio steps, so neighbouring ids land far apart).
double spread(std::int32_t pair) {
  const double f = static_cast<double>(pair) * 0.6180339887498949;
  return f - std::floor(f);
}

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
    if (!world.contains(b.handle)) continue;
    const std::vector<std::uint8_t>* muted = report.ssm.muted_slots;
    const auto slot = static_cast<std::size_t>(b.handle.index);
    addBody(b, report.bodyLevel(b.handle.index),
            muted != nullptr && slot < muted->size() && (*muted)[slot] != 0, world, out);
  }
  for (std::size_t i = 0; i < report.eventCount(); ++i) {
    const PairEvent& e = report.event(i);
    if (e.state != ContactState::kEnd && e.pair >= 0) addPair(e, report.levels[i], world, out);
  }
  addStatus(report, world, out);
  addSsm(report, world, out);
  deleteVanished(out);
  out->markers.resize(used_);
}

void MarkerBuilder::addBody(const ReportedBody& b, int level, bool muted,
                            const ProximityWorld& world, visualization_msgs::MarkerArray* out) {
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

  const BodyDesc& desc = world.desc(b.handle);
  Marker& id = add("ids", b.handle.index, Marker::ADD, out);
  id.type = Marker::TEXT_VIEW_FACING;
  id.pose.position = point(pose.translation());
  id.pose.position.z = swept.upper.z() + 0.1;
  id.text = desc.id;
  id.scale.z = 0.12;
  id.color = colour(0.85f, 0.85f, 0.85f, 0.9f);
  // A muted object (~mute) says so where it stands: it does not lower the speed scale.
  if (muted) {
    id.text.append(" (MUTED)");
    id.color = colour(1.0f, 0.6f, 0.0f, 1.0f);
  }
  showing_[slot] |= kIds;

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

void MarkerBuilder::addPair(const PairEvent& e, Level level, const ProximityWorld& world,
                            visualization_msgs::MarkerArray* out) {
  fit(&pair_showing_, static_cast<std::size_t>(e.pair));
  pair_showing_[static_cast<std::size_t>(e.pair)] = 1;
  const int l = static_cast<int>(level);

  Marker& line = add("nearest", e.pair, Marker::ADD, out);
  line.type = Marker::LINE_LIST;
  line.points.push_back(point(e.point_a));
  line.points.push_back(point(e.point_b));
  line.scale.x = 0.02;
  line.color = levelColour(l, false, 1.0f);

  // "person_3 - tool 0.42 s", in white (readable on every level colour), placed along the
  // pair's line and raised by the pair's own amount so that labels sharing a body do not stack.
  Marker& text = add("ttc_text", e.pair, Marker::ADD, out);
  text.type = Marker::TEXT_VIEW_FACING;
  const double along = 0.3 + 0.4 * spread(e.pair);
  text.pose.position = point(e.point_a + along * (e.point_b - e.point_a));
  text.pose.position.z += 0.15 + 0.25 * spread(e.pair + 7);
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, " %.2f s", e.time_to_contact);
  text.text.assign(world.desc(e.body_a).id).append(" - ").append(world.desc(e.body_b).id).append(buffer);
  text.scale.z = 0.16;  // text height, m
  text.color = colour(1.0f, 1.0f, 1.0f, 1.0f);
}

void MarkerBuilder::addStatus(const CycleReport& report, const ProximityWorld& world,
                              visualization_msgs::MarkerArray* out) {
  // One line above the scene: OK / DEGRADED (why), and the earliest contact.
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double top = 0.0;
  int n = 0;
  for (const ReportedBody& b : report.bodies) {
    if (!world.contains(b.handle)) continue;
    const Aabb swept = world.sweptBounds(b.handle);
    centre += 0.5 * (swept.lower + swept.upper);
    top = n == 0 ? swept.upper.z() : std::max(top, swept.upper.z());
    ++n;
  }
  if (n > 0) centre /= n;
  std::string& line = status_text_;
  if (report.degraded) {
    line = "DEGRADED: " + (report.status_lines.empty() ? std::string("?") : report.status_lines.front());
    if (report.status_lines.size() > 1) {
      line += " (+" + std::to_string(report.status_lines.size() - 1) + " more)";
    }
  } else {
    line = "OK";
  }
  const PairEvent* earliest = nullptr;
  Level level = Level::kNotice;
  for (std::size_t i = 0; i < report.eventCount(); ++i) {
    if (report.event(i).state == ContactState::kEnd) continue;
    earliest = &report.event(i);  // events are sorted earliest first
    level = report.levels[i];
    break;
  }
  if (earliest != nullptr) {
    char buffer[48];
    std::snprintf(buffer, sizeof buffer, " in %.2f s (%s)", earliest->time_to_contact, levelName(level));
    line += " | earliest: " + world.desc(earliest->body_a).id + " - " +
            world.desc(earliest->body_b).id + buffer;
  } else {
    line += " | no contact predicted";
  }
  if (report.ssm.enabled) {
    char buffer[48];
    std::snprintf(buffer, sizeof buffer, " | speed scale %.2f%s", report.ssm.speed_scale,
                  report.ssm.speed_scale <= 0.0 ? " (STOP)" : "");
    line += buffer;
    // The stop latch: a hold and a mute are shown where the operator looks.
    const LatchState* latch = report.ssm.latch;
    if (latch != nullptr && !latch->hold.empty()) {
      line += latch->hold == "reset" ? " | HELD until reset" : " | HELD (minimum stop time)";
    }
    if (latch != nullptr && latch->muted) {
      std::snprintf(buffer, sizeof buffer, " (%.0f s left)", latch->mute_left);
      line += " | MUTED " + latch->mute_scope + buffer;
    }
  }
  Marker& m = add("status", 0, Marker::ADD, out);
  m.type = Marker::TEXT_VIEW_FACING;
  m.pose.position = point(Eigen::Vector3d(centre.x(), centre.y(), top + 1.0));
  m.text = line;
  m.scale.z = 0.3;
  m.color = report.degraded ? colour(1.0f, 0.5f, 0.0f, 1.0f)
                            : (earliest != nullptr ? levelColour(static_cast<int>(level), false, 1.0f)
                                                   : colour(0.2f, 0.9f, 0.3f, 1.0f));
}

void MarkerBuilder::addSsm(const CycleReport& report, const ProximityWorld& world,
                           visualization_msgs::MarkerArray* out) {
  const SsmVerdict& v = report.ssm;
  const bool show = v.enabled && v.limited && world.contains(v.robot) && world.contains(v.object);
  if (!show) {
    if (ssm_shown_) {
      for (std::int32_t id = 0; id < 3; ++id) add("ssm", id, Marker::DELETE, out);
    }
    ssm_shown_ = false;
    return;
  }
  ssm_shown_ = true;
  // Red at a stop, orange while slowed, green at full speed.
  const std_msgs::ColorRGBA c = v.speed_scale <= 0.0  ? colour(1.0f, 0.1f, 0.1f, 1.0f)
                                : v.speed_scale < 1.0 ? colour(1.0f, 0.5f, 0.0f, 1.0f)
                                                      : colour(0.2f, 0.9f, 0.3f, 1.0f);
  // The robot body grown by S_p on every side: an object whose shape enters it limits the
  // robot (the zone of the limiting pair's approach speed; a box, so it holds the rounded zone).
  const BodyDesc& robot = world.desc(v.robot);
  const Eigen::Vector3d half =
      robot.shape.localHalfExtents() + Eigen::Vector3d::Constant(v.required_separation);
  Marker& zone = add("ssm", 0, Marker::ADD, out);
  zone.type = Marker::CUBE;
  setPose(world.motion(v.robot).poseAt(0.0), &zone);
  zone.scale.x = 2 * half.x();
  zone.scale.y = 2 * half.y();
  zone.scale.z = 2 * half.z();
  zone.color = c;
  zone.color.a = 0.15f;

  Marker& line = add("ssm", 1, Marker::ADD, out);
  line.type = Marker::LINE_LIST;
  line.points.push_back(point(v.point_object));
  line.points.push_back(point(v.point_robot));
  line.scale.x = 0.03;
  line.color = c;

  Marker& text = add("ssm", 2, Marker::ADD, out);
  text.type = Marker::TEXT_VIEW_FACING;
  text.pose.position = point(0.5 * (v.point_object + v.point_robot));
  text.pose.position.z += 0.35;
  char buffer[96];
  std::snprintf(buffer, sizeof buffer, "scale %.2f: ", v.speed_scale);
  if (v.speed_scale < v.raw_scale - 0.005) {
    // Below what the pair allows: capped while DEGRADED, or the hysteresis (hold, then the
    // rate) still bringing it up; without this "0.00 ... >= S_p" reads like a wrong verdict.
    if (v.degraded) {
      std::snprintf(buffer, sizeof buffer, "scale %.2f (DEGRADED): ", v.speed_scale);
    } else {
      std::snprintf(buffer, sizeof buffer, "scale %.2f (rising to %.2f): ", v.speed_scale, v.raw_scale);
    }
  }
  text.text.assign(buffer).append(world.desc(v.object).id);
  std::snprintf(buffer, sizeof buffer, " %.2f m %s S_p %.2f m", v.separation,
                v.separation < v.required_separation ? "<" : ">=", v.required_separation);
  text.text.append(buffer);
  text.scale.z = 0.2;
  text.color = colour(1.0f, 1.0f, 1.0f, 1.0f);
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
