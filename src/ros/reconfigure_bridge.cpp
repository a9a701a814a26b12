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

// A label group of the config: its five settings (no margin for the robot's thresholds, whose
// margin is robot_margin).
struct LabelFields {
  double Config::*margin;
  double Config::*warning_time;
  double Config::*critical_time;
  double Config::*warning_distance;
  double Config::*critical_distance;
};
constexpr LabelFields kDefaultLabel{&Config::default_margin, &Config::default_warning_time,
                                    &Config::default_critical_time,
                                    &Config::default_warning_distance,
                                    &Config::default_critical_distance};
constexpr LabelFields kPersonLabel{&Config::person_margin, &Config::person_warning_time,
                                   &Config::person_critical_time,
                                   &Config::person_warning_distance,
                                   &Config::person_critical_distance};
constexpr LabelFields kRobotThresholds{nullptr, &Config::robot_warning_time,
                                       &Config::robot_critical_time,
                                       &Config::robot_warning_distance,
                                       &Config::robot_critical_distance};

void put(const LabelSettings& l, const LabelFields& f, Config* c) {
  if (f.margin != nullptr) c->*f.margin = l.margin;
  c->*f.warning_time = l.warning_time;
  c->*f.critical_time = l.critical_time;
  c->*f.warning_distance = l.warning_distance;
  c->*f.critical_distance = l.critical_distance;
}

LabelSettings get(const Config& c, const LabelFields& f, LabelSettings l) {
  if (f.margin != nullptr) l.margin = c.*f.margin;
  l.warning_time = c.*f.warning_time;
  l.critical_time = c.*f.critical_time;
  l.warning_distance = c.*f.warning_distance;
  l.critical_distance = c.*f.critical_distance;
  return l;
}

bool sameSettings(const LabelSettings& a, const LabelSettings& b) {
  return a.margin == b.margin && a.warning_time == b.warning_time &&
         a.critical_time == b.critical_time && a.warning_distance == b.warning_distance &&
         a.critical_distance == b.critical_distance;
}

}  // namespace

ProximityMonitorConfig toConfig(const MonitorParams& p) {
  Config c = Config::__getDefault__();
  for (const ScalarField& f : kScalars) c.*f.config = p.*f.param;
  put(p.label("default"), kDefaultLabel, &c);
  put(p.label("person"), kPersonLabel, &c);  // the default's when not listed
  put(p.robot_thresholds, kRobotThresholds, &c);
  c.publish_markers = p.publish_markers;
  return c;
}

MonitorParams applyConfig(MonitorParams p, const ProximityMonitorConfig& c) {
  for (const ScalarField& f : kScalars) p.*f.param = c.*f.config;
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
