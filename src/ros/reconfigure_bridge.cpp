#include "workspace_proximity/ros/reconfigure_bridge.hpp"

namespace workspace_proximity {
namespace {

using Config = ProximityMonitorConfig;

// The config's scalars and the parameters they set, one table for both directions.
struct ScalarField {
  double Config::*config;
  double MonitorParams::*param;
};
constexpr ScalarField kScalars[] = {
    {&Config::rate, &MonitorParams::rate},
    {&Config::horizon, &MonitorParams::horizon},
    {&Config::track_timeout, &MonitorParams::track_timeout},
    {&Config::stale_after, &MonitorParams::stale_after},
    {&Config::source_timeout, &MonitorParams::source_timeout},
    {&Config::robot_margin, &MonitorParams::robot_margin},
    {&Config::marker_rate, &MonitorParams::marker_rate},
    {&Config::marker_lifetime, &MonitorParams::marker_lifetime},
};
struct SsmField {
  double Config::*config;
  double SsmParams::*param;
};
constexpr SsmField kSsmScalars[] = {
    {&Config::ssm_reaction_time, &SsmParams::reaction_time},
    {&Config::ssm_stopping_time, &SsmParams::stopping_time},
    {&Config::ssm_intrusion_distance, &SsmParams::intrusion_distance},
    {&Config::ssm_sensor_uncertainty, &SsmParams::sensor_uncertainty},
    {&Config::ssm_robot_uncertainty, &SsmParams::robot_uncertainty},
    {&Config::ssm_robot_max_speed, &SsmParams::robot_max_speed},
    {&Config::ssm_max_increase_rate, &SsmParams::max_increase_rate},
    {&Config::ssm_hold_time, &SsmParams::hold_time},
    {&Config::ssm_degraded_scale, &SsmParams::degraded_scale},
};

// A label group of the config: its six settings (no margin and no minimum approach speed for
// the robot's thresholds: its margin is robot_margin, and it is not a tracked object).
struct LabelFields {
  double Config::*margin;
  double Config::*warning_time;
  double Config::*critical_time;
  double Config::*warning_distance;
  double Config::*critical_distance;
  double Config::*ssm_min_speed;
};
constexpr LabelFields kDefaultLabel{&Config::default_margin, &Config::default_warning_time,
                                    &Config::default_critical_time,
                                    &Config::default_warning_distance,
                                    &Config::default_critical_distance,
                                    &Config::default_ssm_min_speed};
constexpr LabelFields kPersonLabel{&Config::person_margin, &Config::person_warning_time,
                                   &Config::person_critical_time,
                                   &Config::person_warning_distance,
                                   &Config::person_critical_distance,
                                   &Config::person_ssm_min_speed};
constexpr LabelFields kRobotThresholds{nullptr, &Config::robot_warning_time,
                                       &Config::robot_critical_time,
                                       &Config::robot_warning_distance,
                                       &Config::robot_critical_distance, nullptr};

void put(const LabelSettings& l, const LabelFields& f, Config* c) {
  if (f.margin != nullptr) c->*f.margin = l.margin;
  c->*f.warning_time = l.warning_time;
  c->*f.critical_time = l.critical_time;
  c->*f.warning_distance = l.warning_distance;
  c->*f.critical_distance = l.critical_distance;
  if (f.ssm_min_speed != nullptr) c->*f.ssm_min_speed = l.ssm_min_speed;
}

LabelSettings get(const Config& c, const LabelFields& f, LabelSettings l) {
  if (f.margin != nullptr) l.margin = c.*f.margin;
  l.warning_time = c.*f.warning_time;
  l.critical_time = c.*f.critical_time;
  l.warning_distance = c.*f.warning_distance;
  l.critical_distance = c.*f.critical_distance;
  if (f.ssm_min_speed != nullptr) l.ssm_min_speed = c.*f.ssm_min_speed;
  return l;
}

bool sameSettings(const LabelSettings& a, const LabelSettings& b) {
  return a.margin == b.margin && a.warning_time == b.warning_time &&
         a.critical_time == b.critical_time && a.warning_distance == b.warning_distance &&
         a.critical_distance == b.critical_distance && a.ssm_min_speed == b.ssm_min_speed;
}

}  // namespace

ProximityMonitorConfig toConfig(const MonitorParams& p) {
  Config c = Config::__getDefault__();
  for (const ScalarField& f : kScalars) c.*f.config = p.*f.param;
  for (const SsmField& f : kSsmScalars) c.*f.config = p.ssm.*f.param;
  put(p.label("default"), kDefaultLabel, &c);
  put(p.label("person"), kPersonLabel, &c);  // the default's when not listed
  put(p.robot_thresholds, kRobotThresholds, &c);
  c.publish_markers = p.publish_markers;
  return c;
}

MonitorParams applyConfig(MonitorParams p, const ProximityMonitorConfig& c) {
  for (const ScalarField& f : kScalars) p.*f.param = c.*f.config;
  for (const SsmField& f : kSsmScalars) p.ssm.*f.param = c.*f.config;
  LabelSettings& d = p.labels["default"];
  d = get(c, kDefaultLabel, d);
  const LabelSettings person = get(c, kPersonLabel, d);
  if (p.labels.count("person") != 0 || !sameSettings(person, d)) p.labels["person"] = person;
  p.robot_thresholds = get(c, kRobotThresholds, p.robot_thresholds);
  p.publish_markers = c.publish_markers;
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
