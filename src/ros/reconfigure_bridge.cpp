#include "workspace_proximity/ros/reconfigure_bridge.hpp"

namespace workspace_proximity {
namespace {

bool sameSettings(const LabelSettings& a, const LabelSettings& b) {
  return a.margin == b.margin && a.warning_time == b.warning_time &&
         a.critical_time == b.critical_time && a.warning_distance == b.warning_distance &&
         a.critical_distance == b.critical_distance && a.position_error == b.position_error &&
         a.velocity_error == b.velocity_error && a.max_accel == b.max_accel &&
         a.max_speed == b.max_speed;
}

// The config's values of one label group (every field the sliders tune).
LabelSettings labelFrom(double margin, double warning_time, double critical_time,
                        double warning_distance, double critical_distance, double position_error,
                        double velocity_error, double max_accel, double max_speed) {
  LabelSettings l;
  l.margin = margin;
  l.warning_time = warning_time;
  l.critical_time = critical_time;
  l.warning_distance = warning_distance;
  l.critical_distance = critical_distance;
  l.position_error = position_error;
  l.velocity_error = velocity_error;
  l.max_accel = max_accel;
  l.max_speed = max_speed;
  return l;
}

}  // namespace

ProximityMonitorConfig toConfig(const MonitorParams& p) {
  ProximityMonitorConfig c = ProximityMonitorConfig::__getDefault__();
  c.rate = p.rate;
  c.horizon = p.horizon;
  c.track_timeout = p.track_timeout;
  c.stale_after = p.stale_after;
  c.source_timeout = p.source_timeout;
  c.robot_margin = p.robot_margin;
  const LabelSettings& d = p.label("default");
  c.default_margin = d.margin;
  c.default_warning_time = d.warning_time;
  c.default_critical_time = d.critical_time;
  c.default_warning_distance = d.warning_distance;
  c.default_critical_distance = d.critical_distance;
  c.default_position_error = d.position_error;
  c.default_velocity_error = d.velocity_error;
  c.default_max_accel = d.max_accel;
  c.default_max_speed = d.max_speed;
  const LabelSettings& person = p.label("person");  // the default's when not listed
  c.person_margin = person.margin;
  c.person_warning_time = person.warning_time;
  c.person_critical_time = person.critical_time;
  c.person_warning_distance = person.warning_distance;
  c.person_critical_distance = person.critical_distance;
  c.person_position_error = person.position_error;
  c.person_velocity_error = person.velocity_error;
  c.person_max_accel = person.max_accel;
  c.person_max_speed = person.max_speed;
  const LabelSettings& r = p.robot_thresholds;
  c.robot_warning_time = r.warning_time;
  c.robot_critical_time = r.critical_time;
  c.robot_warning_distance = r.warning_distance;
  c.robot_critical_distance = r.critical_distance;
  c.publish_markers = p.publish_markers;
  c.marker_rate = p.marker_rate;
  c.marker_lifetime = p.marker_lifetime;
  return c;
}

MonitorParams applyConfig(MonitorParams p, const ProximityMonitorConfig& c) {
  p.rate = c.rate;
  p.horizon = c.horizon;
  p.track_timeout = c.track_timeout;
  p.stale_after = c.stale_after;
  p.source_timeout = c.source_timeout;
  p.robot_margin = c.robot_margin;
  LabelSettings& d = p.labels["default"];
  d = labelFrom(c.default_margin, c.default_warning_time, c.default_critical_time,
                c.default_warning_distance, c.default_critical_distance, c.default_position_error,
                c.default_velocity_error, c.default_max_accel, c.default_max_speed);
  const LabelSettings person =
      labelFrom(c.person_margin, c.person_warning_time, c.person_critical_time,
                c.person_warning_distance, c.person_critical_distance, c.person_position_error,
                c.person_velocity_error, c.person_max_accel, c.person_max_speed);
  if (p.labels.count("person") != 0 || !sameSettings(person, d)) p.labels["person"] = person;
  p.robot_thresholds.warning_time = c.robot_warning_time;
  p.robot_thresholds.critical_time = c.robot_critical_time;
  p.robot_thresholds.warning_distance = c.robot_warning_distance;
  p.robot_thresholds.critical_distance = c.robot_critical_distance;
  p.publish_markers = c.publish_markers;
  p.marker_rate = c.marker_rate;
  p.marker_lifetime = c.marker_lifetime;
  return p;
}

bool checkConfig(const MonitorParams& current, const ProximityMonitorConfig& config,
                 MonitorParams* next, std::vector<std::string>* errors) {
  MonitorParams candidate = applyConfig(current, config);
  *errors = validate(candidate);
  if (!errors->empty()) return false;
  *next = std::move(candidate);
  return true;
}

}  // namespace workspace_proximity
