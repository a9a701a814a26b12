#pragma once
/// Reading MonitorParams from the ROS parameter server, or from the same tree loaded
/// elsewhere (the offline replay loads it from YAML files).

#include <string>
#include <vector>

#include <XmlRpcValue.h>
#include <ros/node_handle.h>

#include "workspace_proximity/rules/monitor_params.hpp"

namespace workspace_proximity {

/// Reads every parameter of the node from `root`, the node's private namespace as one
/// dictionary (an invalid, i.e. empty, value means nothing is set), keeping defaults for those
/// not set. Throws std::runtime_error naming the parameter ("~name: must be ...") when one has
/// the wrong type or structure. Ranges are checked separately by validate().
MonitorParams readParams(const XmlRpc::XmlRpcValue& root);

/// The same from the private handle: its whole namespace fetched in one call.
MonitorParams readParams(const ros::NodeHandle& private_nh);

/// One line per key under `root` (and under each ~robot_bodies entry) that the node does not
/// read, e.g. "~horizen: unknown parameter, not used (did you mean ~horizon?)": a misspelled
/// key would otherwise be ignored silently. Label names under ~labels are free; their settings
/// are checked by readParams.
std::vector<std::string> unknownParams(const XmlRpc::XmlRpcValue& root);
std::vector<std::string> unknownParams(const ros::NodeHandle& private_nh);

}  // namespace workspace_proximity
