#pragma once
/// Building blocks of the rules layer's tests: parameters without margins (so contact times
/// and distances have exact analytic values) and robot bodies as boxes on the "base" frame.

#include <string>

#include <Eigen/Core>

#include "workspace_proximity/rules/monitor_params.hpp"

namespace wp_test {

/// Default parameters with horizon `horizon` (s), no robot margin and no default-label margin;
/// the person label, when given, as `person`.
inline workspace_proximity::MonitorParams marginFreeParams(double horizon) {
  workspace_proximity::MonitorParams p;
  p.horizon = horizon;
  p.robot_margin = 0.0;
  p.labels["default"].margin = 0.0;
  return p;
}

inline workspace_proximity::MonitorParams marginFreeParams(
    double horizon, const workspace_proximity::LabelSettings& person) {
  workspace_proximity::MonitorParams p = marginFreeParams(horizon);
  p.labels["person"] = person;
  return p;
}

/// A robot body: a box of half extents `half` (m) on frame "base", centred `centre` (m) from it.
inline workspace_proximity::RobotBodySpec robotBox(const std::string& name,
                                                   const Eigen::Vector3d& half,
                                                   const Eigen::Vector3d& centre = Eigen::Vector3d::Zero()) {
  workspace_proximity::RobotBodySpec s;
  s.name = name;
  s.frame = "base";
  s.shape = workspace_proximity::Shape::box(half);
  s.offset.translation() = centre;
  return s;
}

}  // namespace wp_test
