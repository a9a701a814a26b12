#pragma once
/// Reading MonitorParams from the ROS parameter server, or from the same tree loaded
/// elsewhere (the offline replay loads it from YAML files).

#include <XmlRpcValue.h>
#include <ros/node_handle.h>

#include "workspace_proximity/monitor/monitor_params.hpp"

namespace workspace_proximity {

/// Reads every parameter of the node from `root`, the node's private namespace as one
/// dictionary (an invalid, i.e. empty, value means nothing is set), keeping defaults for those
/// not set. Throws std::runtime_error naming the parameter ("~name: must be ...") when one has
/// the wrong type or structure. Ranges are checked separately by validate().
MonitorParams readParams(const XmlRpc::XmlRpcValue& root);

/// The same from the private handle: its whole namespace fetched in one call.
MonitorParams readParams(const ros::NodeHandle& private_nh);

}  // namespace workspace_proximity
