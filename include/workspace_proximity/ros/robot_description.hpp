#pragma once
/// The robot's bodies as the node configures them: every collision element of the URDF on
/// the robot description parameter (when ~use_robot_description) and every ~robot_bodies
/// entry, each name once.

#include <vector>

#include <ros/node_handle.h>

#include "workspace_proximity/monitor/monitor_params.hpp"

namespace workspace_proximity {

/// Reads the URDF from `nh`'s parameter `params.robot_description_param` and merges its bodies
/// with `params.robot_bodies` (those first; a name declared twice keeps the first, with a
/// warning). Throws std::runtime_error when the URDF does not parse.
std::vector<RobotBodySpec> loadRobotBodies(const ros::NodeHandle& nh, const MonitorParams& params);

}  // namespace workspace_proximity
