#pragma once
/// The robot's bodies as the node configures them: every collision element of the URDF on
/// the robot description parameter (when ~use_robot_description) and every ~robot_bodies
/// entry, each name once; and every collision element that could not be modelled.

#include <string>
#include <vector>

#include <ros/node_handle.h>

#include "workspace_proximity/rules/monitor_params.hpp"

namespace workspace_proximity {

struct RobotDescription {
  std::vector<RobotBodySpec> bodies;
  /// One line per URDF collision element that gives no body ("robot link <link>: collision
  /// element <i> cannot be modelled: <reason>"). The node keeps its status DEGRADED with each
  /// (or refuses to start with ~require_all_links).
  std::vector<std::string> unmodelled;
};

/// `params.robot_bodies` then the bodies of `urdf_xml` (none when null or when
/// `!params.use_robot_description`), each name once (a name declared twice keeps the first, with
/// a line in `warnings`), and a line per collision element that cannot be modelled. Throws
/// std::runtime_error when the URDF does not parse. Needs no master: the node and the offline
/// replay both use it.
RobotDescription robotDescription(const std::string* urdf_xml, const MonitorParams& params,
                                  std::vector<std::string>* warnings);

/// Reads the URDF from `nh`'s parameter `params.robot_description_param` and merges its bodies
/// with `params.robot_bodies` (those first; a name declared twice keeps the first, with a
/// warning). Throws std::runtime_error when the URDF does not parse.
RobotDescription loadRobotBodies(const ros::NodeHandle& nh, const MonitorParams& params);

}  // namespace workspace_proximity
