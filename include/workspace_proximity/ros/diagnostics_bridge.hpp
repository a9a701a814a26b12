#pragma once
/// The monitor's state as a /diagnostics status: ERROR when a cycle overruns its period, WARN
/// while the prediction is DEGRADED (with the reasons), else OK; plus cycle and stage times,
/// counts, each source's rate and age, and dropped inputs by reason.

#include <cstdint>

#include <diagnostic_updater/DiagnosticStatusWrapper.h>

#include "workspace_proximity/monitor/monitor.hpp"
#include "workspace_proximity/ros/robot_joint_bridge.hpp"

namespace workspace_proximity {

/// Counters the ROS bridges keep themselves.
struct BridgeCounters {
  std::uint64_t tf_failures = 0;  ///< arrays and robot poses tf could not transform
  bool joints = false;            ///< robot links posed from joint states
  JointBridgeCounters joint;      ///< their counters (when `joints`)
};

/// Fills `status` from the monitor's last report and counters, at `now`.
void diagnose(const Monitor& monitor, const BridgeCounters& bridges, Stamp now,
              diagnostic_updater::DiagnosticStatusWrapper* status);

}  // namespace workspace_proximity
