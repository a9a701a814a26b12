#pragma once
/// Live tuning through dynamic_reconfigure: the mapping between the generated
/// ProximityMonitorConfig and MonitorParams (free functions, round-trip tested), and the
/// checked application of a change.

#include <string>
#include <vector>

#include <workspace_proximity/ProximityMonitorConfig.h>

#include "workspace_proximity/rules/monitor_params.hpp"

namespace workspace_proximity {

/// The tunable part of `params` (the Tuning::kLive rows of param_table.hpp, each a slider
/// named as its row with '/' as '_', and the default and person labels' and the robot's
/// settings) as a config ("person" shows the default label's values when the person label is
/// not configured).
ProximityMonitorConfig toConfig(const MonitorParams& params);

/// `params` with the config's values. The person label is written only when it exists in
/// `params` or the config gives it values other than the default label's.
MonitorParams applyConfig(MonitorParams params, const ProximityMonitorConfig& config);

/// `current` with `config` applied, when that passes validate(): returns true and sets
/// `*next`. Otherwise returns false with the reasons in `*errors` (and `*next` untouched).
bool checkConfig(const MonitorParams& current, const ProximityMonitorConfig& config,
                 MonitorParams* next, std::vector<std::string>* errors);

}  // namespace workspace_proximity
