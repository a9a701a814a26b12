#pragma once
/// Reading MonitorParams from the ROS parameter server.

#include <ros/node_handle.h>

#include "workspace_proximity/monitor/monitor_params.hpp"

namespace workspace_proximity {

/// Reads every parameter of the node from the private handle, keeping defaults for those
/// not set. Throws std::runtime_error naming the parameter when one has the wrong type or
/// structure. Ranges are checked separately by validate().
MonitorParams readParams(const ros::NodeHandle& private_nh);

}  // namespace workspace_proximity
