#include "workspace_proximity/rules/level_policy.hpp"

#include <algorithm>

namespace workspace_proximity {

Level contactLevel(const PairEvent& event, const LabelSettings& a, const LabelSettings& b) {
  if (event.state == ContactState::kEnd) return Level::kNotice;
  auto level = [&](const LabelSettings& l) {
    if (event.time_to_contact <= l.critical_time || event.distance <= l.critical_distance) {
      return Level::kCritical;
    }
    if (event.time_to_contact <= l.warning_time || event.distance <= l.warning_distance) {
      return Level::kWarning;
    }
    return Level::kNotice;
  };
  return std::max(level(a), level(b));
}

LabelTable::LabelTable(const MonitorParams& params) {
  names_.push_back("");
  settings_.push_back(params.robot_thresholds);
  names_.push_back("default");
  settings_.push_back(params.label("default"));
  for (const auto& kv : params.labels) {
    if (kv.first == "default") continue;
    names_.push_back(kv.first);
    settings_.push_back(kv.second);
  }
}

int LabelTable::indexOf(const std::string& label) const {
  for (std::size_t i = kDefault + 1; i < names_.size(); ++i) {
    if (names_[i] == label) return static_cast<int>(i);
  }
  return kDefault;
}

}  // namespace workspace_proximity
