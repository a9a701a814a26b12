#pragma once
/// How serious a predicted contact is: levels from per-label thresholds, and the label settings
/// addressed by small indices (looked up by name once, when a body is added).

#include <cstdint>
#include <string>
#include <vector>

#include "workspace_proximity/rules/monitor_params.hpp"
#include "workspace_proximity/pair_event.hpp"

namespace workspace_proximity {

/// Levels of a contact; the numbers are those of ContactEvent's NOTICE / WARNING / CRITICAL.
enum class Level : std::uint8_t { kNotice = 0, kWarning = 1, kCritical = 2 };

/// Level of an event from the thresholds of its two bodies (the stricter one counts):
/// CRITICAL when time_to_contact <= critical_time or distance <= critical_distance, WARNING
/// likewise with the warning thresholds, else NOTICE. END events are NOTICE.
Level contactLevel(const PairEvent& event, const LabelSettings& a, const LabelSettings& b);

/// Every label's settings in a flat array: index kRobot holds ~robot_thresholds, kDefault the
/// "default" label, then the listed labels. Labels not listed use kDefault.
class LabelTable {
 public:
  static constexpr int kRobot = 0;
  static constexpr int kDefault = 1;

  explicit LabelTable(const MonitorParams& params);
  /// Index of a label's settings (kDefault when not listed). A string comparison per listed
  /// label: call it when a body is added, not per cycle.
  int indexOf(const std::string& label) const;
  const LabelSettings& settings(int index) const { return settings_[static_cast<std::size_t>(index)]; }

 private:
  std::vector<std::string> names_;        // parallel to settings_ ("" for the robot entry)
  std::vector<LabelSettings> settings_;
};

}  // namespace workspace_proximity
