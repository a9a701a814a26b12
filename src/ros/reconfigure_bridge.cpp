#include "workspace_proximity/ros/reconfigure_bridge.hpp"

#include <algorithm>
#include <stdexcept>

#include <boost/pointer_cast.hpp>

#include "workspace_proximity/rules/param_table.hpp"

namespace workspace_proximity {
namespace {

using Config = ProximityMonitorConfig;

// The config's field for the slider `name` (cfg/ProximityMonitor.cfg), of type T.
template <typename T>
T Config::*sliderField(const std::string& name, const std::string& parameter) {
  for (const Config::AbstractParamDescriptionConstPtr& d : Config::__getParamDescriptions__()) {
    if (d->name != name) continue;
    if (auto typed = boost::dynamic_pointer_cast<const Config::ParamDescription<T>>(d)) {
      return typed->field;
    }
    break;
  }
  throw std::logic_error("cfg/ProximityMonitor.cfg has no slider '" + name + "' of the right type for ~" +
                         parameter + " (a live row of param_table.cpp)");
}

// A live row of the table and its slider, named as the row with '/' as '_' (ssm_hold_time).
struct Slider {
  const ParamRow* row;
  double Config::*number = nullptr;  // for a number
  bool Config::*flag = nullptr;      // for a bool
};
// A live label setting and its slider in a label's group (person_margin).
struct LabelSlider {
  const LabelRow* row;
  double Config::*field;
};
struct Sliders {
  std::vector<Slider> params;
  // The label groups of the config: the default label, the person label and the robot's
  // thresholds (no margin, approach speed or growth: track_only settings are not its).
  std::vector<LabelSlider> default_label;
  std::vector<LabelSlider> person_label;
  std::vector<LabelSlider> robot_thresholds;
};

// The sliders of the group `group` (default_margin, ...) for the settings under `prefix`.
std::vector<LabelSlider> labelSliders(const std::string& group, const std::string& prefix,
                                      bool track_label) {
  std::vector<LabelSlider> out;
  for (const LabelRow& row : labelTable()) {
    if (row.tuning != Tuning::kLive || (row.track_only && !track_label)) continue;
    out.push_back({&row, sliderField<double>(group + "_" + row.key, prefix + row.key)});
  }
  return out;
}

// Every live row bound to its slider, once (throws std::logic_error when the .cfg lacks one,
// which test_param_files rules out).
const Sliders& sliders() {
  static const Sliders bound = [] {
    Sliders s;
    for (const ParamRow& row : paramTable()) {
      if (row.tuning != Tuning::kLive || row.member.type == ParamType::kStructure) continue;
      std::string name = row.name;
      std::replace(name.begin(), name.end(), '/', '_');
      Slider slider{&row};
      if (row.member.type == ParamType::kBool) {
        slider.flag = sliderField<bool>(name, row.name);
      } else {
        slider.number = sliderField<double>(name, row.name);
      }
      s.params.push_back(slider);
    }
    s.default_label = labelSliders("default", "labels/default/", true);
    s.person_label = labelSliders("person", "labels/person/", true);
    s.robot_thresholds = labelSliders("robot", "robot_thresholds/", false);
    return s;
  }();
  return bound;
}

void put(const LabelSettings& l, const std::vector<LabelSlider>& sliders, Config* c) {
  for (const LabelSlider& s : sliders) c->*s.field = l.*s.row->member;
}

LabelSettings get(const Config& c, const std::vector<LabelSlider>& sliders, LabelSettings l) {
  for (const LabelSlider& s : sliders) l.*s.row->member = c.*s.field;
  return l;
}

// Equal in every setting the sliders tune.
bool sameSettings(const LabelSettings& a, const LabelSettings& b) {
  for (const LabelSlider& s : sliders().default_label) {
    if (a.*s.row->member != b.*s.row->member) return false;
  }
  return true;
}

}  // namespace

ProximityMonitorConfig toConfig(const MonitorParams& p) {
  const Sliders& all = sliders();
  Config c = Config::__getDefault__();
  MonitorParams& q = const_cast<MonitorParams&>(p);  // the row accessors only read here
  for (const Slider& s : all.params) {
    if (s.flag != nullptr) {
      c.*s.flag = s.row->member.flag(q);
    } else {
      c.*s.number = s.row->member.number(q);
    }
  }
  put(p.label("default"), all.default_label, &c);
  put(p.label("person"), all.person_label, &c);  // the default's when not listed
  put(p.robot_thresholds, all.robot_thresholds, &c);
  return c;
}

MonitorParams applyConfig(MonitorParams p, const ProximityMonitorConfig& c) {
  const Sliders& all = sliders();
  for (const Slider& s : all.params) {
    if (s.flag != nullptr) {
      s.row->member.flag(p) = c.*s.flag;
    } else {
      s.row->member.number(p) = c.*s.number;
    }
  }
  LabelSettings& d = p.labels["default"];
  d = get(c, all.default_label, d);
  const LabelSettings person = get(c, all.person_label, d);
  if (p.labels.count("person") != 0 || !sameSettings(person, d)) p.labels["person"] = person;
  p.robot_thresholds = get(c, all.robot_thresholds, p.robot_thresholds);
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
