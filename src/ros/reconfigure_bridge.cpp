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

// A label group of the config: each slider and the label setting it tunes. The robot's group
// has no margin (that is robot_margin), no approach speed and no growth (it is no track).
struct LabelField {
  double Config::*config;
  double LabelSettings::*setting;
};
#define WP_LABEL_FIELD(group, name) {&Config::group##_##name, &LabelSettings::name}
#define WP_TRACK_LABEL_FIELDS(group)                                                       \
  WP_LABEL_FIELD(group, margin), WP_LABEL_FIELD(group, warning_time),                      \
      WP_LABEL_FIELD(group, critical_time), WP_LABEL_FIELD(group, warning_distance),       \
      WP_LABEL_FIELD(group, critical_distance), WP_LABEL_FIELD(group, ssm_min_speed),      \
      WP_LABEL_FIELD(group, position_error), WP_LABEL_FIELD(group, velocity_error),        \
      WP_LABEL_FIELD(group, max_accel), WP_LABEL_FIELD(group, max_speed)
constexpr LabelField kDefaultLabel[] = {WP_TRACK_LABEL_FIELDS(default)};
constexpr LabelField kPersonLabel[] = {WP_TRACK_LABEL_FIELDS(person)};
constexpr LabelField kRobotThresholds[] = {
    WP_LABEL_FIELD(robot, warning_time), WP_LABEL_FIELD(robot, critical_time),
    WP_LABEL_FIELD(robot, warning_distance), WP_LABEL_FIELD(robot, critical_distance)};
#undef WP_TRACK_LABEL_FIELDS
#undef WP_LABEL_FIELD

template <std::size_t N>
void put(const LabelSettings& l, const LabelField (&fields)[N], Config* c) {
  for (const LabelField& f : fields) c->*f.config = l.*f.setting;
}

template <std::size_t N>
LabelSettings get(const Config& c, const LabelField (&fields)[N], LabelSettings l) {
  for (const LabelField& f : fields) l.*f.setting = c.*f.config;
  return l;
}

// Equal in every setting the sliders tune.
bool sameSettings(const LabelSettings& a, const LabelSettings& b) {
  for (const LabelField& f : kDefaultLabel) {
    if (a.*f.setting != b.*f.setting) return false;
  }
  return true;
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
