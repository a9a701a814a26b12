#pragma once
/// The robot's bodies for the offline replay, as the node configures them but with the URDF
/// read from a file instead of the robot description parameter.

#include <string>
#include <vector>

#include "workspace_proximity/rules/monitor_params.hpp"
#include "workspace_proximity/ros/robot_description.hpp"

namespace workspace_proximity {

/// robotDescription() (the node's rule) of the URDF in `urdf_path` (none when the path is
/// empty). Duplicate names go to `warnings`; elements that cannot be modelled are in the
/// result's `unmodelled` (the replay's status carries them every cycle, as the node's does).
/// Throws std::runtime_error naming the file when it cannot be read or does not parse.
RobotDescription robotBodiesFromFile(const std::string& urdf_path, const MonitorParams& params,
                                     std::vector<std::string>* warnings);

}  // namespace workspace_proximity
