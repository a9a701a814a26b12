#pragma once
/// The robot's bodies for the offline replay, as the node configures them but with the URDF
/// read from a file instead of the robot description parameter.

#include <string>
#include <vector>

#include "workspace_proximity/monitor/monitor_params.hpp"

namespace workspace_proximity {

/// `params.robot_bodies`, then every collision element of the URDF in `urdf_path` (none when
/// the path is empty or `params.use_robot_description` is false); a name declared twice keeps
/// the first. Meshes are found as the node finds them ("package://" through ROS_PACKAGE_PATH,
/// "file://"). Lines for skipped elements and duplicate names go to `warnings`. Throws
/// std::runtime_error naming the file when it cannot be read or does not parse.
std::vector<RobotBodySpec> robotBodiesFromFile(const std::string& urdf_path,
                                               const MonitorParams& params,
                                               std::vector<std::string>* warnings);

}  // namespace workspace_proximity
