#include "workspace_proximity/ros/reconfigure_bridge.hpp"

namespace workspace_proximity {
namespace {

bool sameSettings(const LabelSettings& a, const LabelSettings& b) {
  return a.margin == b.margin && a.warning_time == b.warning_time &&
         a.critical_time == b.critical_time && a.warning_distance == b.warning_distance &&
         a.critical_distance == b.critical_distance && a.ssm_min_speed == b.ssm_min_speed;
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
  c.default_ssm_min_speed = d.ssm_min_speed;
  const LabelSettings& person = p.label("person");  // the default's when not listed
  c.person_margin = person.margin;
  c.person_warning_time = person.warning_time;
  c.person_critical_time = person.critical_time;
  c.person_warning_distance = person.warning_distance;
  c.person_critical_distance = person.critical_distance;
  c.person_ssm_min_speed = person.ssm_min_speed;
  const LabelSettings& r = p.robot_thresholds;
  c.robot_warning_time = r.warning_time;
  c.robot_critical_time = r.critical_time;
  c.robot_warning_distance = r.warning_distance;
  c.robot_critical_distance = r.critical_distance;
  c.publish_markers = p.publish_markers;
  c.marker_rate = p.marker_rate;
  c.marker_lifetime = p.marker_lifetime;
  c.ssm_reaction_time = p.ssm.reaction_time;
  c.ssm_stopping_time = p.ssm.stopping_time;
  c.ssm_intrusion_distance = p.ssm.intrusion_distance;
  c.ssm_sensor_uncertainty = p.ssm.sensor_uncertainty;
  c.ssm_robot_uncertainty = p.ssm.robot_uncertainty;
  c.ssm_robot_max_speed = p.ssm.robot_max_speed;
  c.ssm_max_increase_rate = p.ssm.max_increase_rate;
  c.ssm_hold_time = p.ssm.hold_time;
  c.ssm_degraded_scale = p.ssm.degraded_scale;
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
  d = LabelSettings{c.default_margin, c.default_warning_time, c.default_critical_time,
                    c.default_warning_distance, c.default_critical_distance,
                    c.default_ssm_min_speed};
  const LabelSettings person{c.person_margin, c.person_warning_time, c.person_critical_time,
                             c.person_warning_distance, c.person_critical_distance,
                             c.person_ssm_min_speed};
  if (p.labels.count("person") != 0 || !sameSettings(person, d)) p.labels["person"] = person;
  p.robot_thresholds.warning_time = c.robot_warning_time;
  p.robot_thresholds.critical_time = c.robot_critical_time;
  p.robot_thresholds.warning_distance = c.robot_warning_distance;
  p.robot_thresholds.critical_distance = c.robot_critical_distance;
  p.publish_markers = c.publish_markers;
  p.marker_rate = c.marker_rate;
  p.marker_lifetime = c.marker_lifetime;
  p.ssm.reaction_time = c.ssm_reaction_time;
  p.ssm.stopping_time = c.ssm_stopping_time;
  p.ssm.intrusion_distance = c.ssm_intrusion_distance;
  p.ssm.sensor_uncertainty = c.ssm_sensor_uncertainty;
  p.ssm.robot_uncertainty = c.ssm_robot_uncertainty;
  p.ssm.robot_max_speed = c.ssm_robot_max_speed;
  p.ssm.max_increase_rate = c.ssm_max_increase_rate;
  p.ssm.hold_time = c.ssm_hold_time;
  p.ssm.degraded_scale = c.ssm_degraded_scale;
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
