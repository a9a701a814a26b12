#include "workspace_proximity/ros/robot_description.hpp"

#include <string>
#include <unordered_set>

#include <ros/console.h>
#include <ros/package.h>

#include "workspace_proximity/ros/robot_model.hpp"

namespace workspace_proximity {
namespace {

// "package://pkg/path" and "file:///path" to a local path; empty when unresolvable.
std::string resolveMesh(const std::string& url) {
  const std::string package_prefix = "package://";
  const std::string file_prefix = "file://";
  if (url.compare(0, package_prefix.size(), package_prefix) == 0) {
    const std::string rest = url.substr(package_prefix.size());
    const auto slash = rest.find('/');
    if (slash == std::string::npos) return std::string();
    const std::string root = ros::package::getPath(rest.substr(0, slash));
    return root.empty() ? std::string() : root + rest.substr(slash);
  }
  if (url.compare(0, file_prefix.size(), file_prefix) == 0) return url.substr(file_prefix.size());
  return url;
}

}  // namespace

std::vector<RobotBodySpec> loadRobotBodies(const ros::NodeHandle& nh, const MonitorParams& params) {
  std::vector<RobotBodySpec> specs = params.robot_bodies;
  if (params.use_robot_description) {
    std::string urdf;
    if (nh.getParam(params.robot_description_param, urdf)) {
      std::vector<std::string> warnings;
      const std::vector<RobotBodySpec> from_urdf = bodiesFromUrdf(urdf, resolveMesh, &warnings);
      for (const std::string& w : warnings) ROS_WARN("proximity_monitor: URDF %s", w.c_str());
      specs.insert(specs.end(), from_urdf.begin(), from_urdf.end());
    } else {
      ROS_INFO("proximity_monitor: no '%s' parameter; robot bodies from ~robot_bodies only",
               params.robot_description_param.c_str());
    }
  }
  std::vector<RobotBodySpec> unique;
  std::unordered_set<std::string> names;
  for (const RobotBodySpec& spec : specs) {
    if (!names.insert(spec.name).second) {
      ROS_WARN("proximity_monitor: robot body '%s' declared twice; the first is used",
               spec.name.c_str());
      continue;
    }
    unique.push_back(spec);
  }
  return unique;
}

}  // namespace workspace_proximity
