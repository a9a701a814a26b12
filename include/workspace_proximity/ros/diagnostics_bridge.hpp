#pragma once
/// The monitor's state as a /diagnostics status: ERROR when a cycle overruns its period, WARN
/// while the prediction is DEGRADED (with the reasons), else OK; plus cycle and stage times,
/// counts, each source's rate and age, and dropped inputs by reason.

#include <string>

#include <diagnostic_updater/DiagnosticStatusWrapper.h>

#include "workspace_proximity/ros/monitor_bridges.hpp"

namespace workspace_proximity {

/// Fills `status` from the monitor's last report, its counts (MonitorStatus, the bridges'
/// counters) and its cycle times, at `now`; with the configuration's fingerprint
/// (config_fingerprint.hpp).
void diagnose(const MonitorBridges& bridges, Stamp now, const std::string& fingerprint,
              diagnostic_updater::DiagnosticStatusWrapper* status);

}  // namespace workspace_proximity
