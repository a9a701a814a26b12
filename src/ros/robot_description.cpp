#include "workspace_proximity/ros/robot_description.hpp"

#include <string>
#include <unordered_set>

#include <ros/console.h>

#include "workspace_proximity/ros/robot_model.hpp"

namespace workspace_proximity {

RobotDescription robotDescription(const std::string* urdf_xml, const MonitorParams& params,
                                  std::vector<std::string>* warnings) {
  RobotDescription out;
  std::vector<RobotBodySpec> specs = params.robot_bodies;
  if (params.use_robot_description && urdf_xml != nullptr) {
    const UrdfBodies from_urdf = bodiesFromUrdf(*urdf_xml);
    for (const UnmodelledElement& e : from_urdf.unmodelled) {
      out.unmodelled.push_back("robot link " + e.link + ": collision element " +
                               std::to_string(e.index) + " cannot be modelled: " + e.reason);
    }
    specs.insert(specs.end(), from_urdf.bodies.begin(), from_urdf.bodies.end());
  }
  std::unordered_set<std::string> names;
  for (const RobotBodySpec& spec : specs) {
    if (!names.insert(spec.name).second) {
      warnings->push_back("robot body '" + spec.name + "' declared twice; the first is used");
      continue;
    }
    out.bodies.push_back(spec);
  }
  return out;
}

RobotDescription loadRobotBodies(const ros::NodeHandle& nh, const MonitorParams& params) {
  std::string urdf;
  const bool have_urdf = params.use_robot_description && nh.getParam(params.robot_description_param, urdf);
  if (params.use_robot_description && !have_urdf) {
    ROS_INFO("proximity_monitor: no '%s' parameter; robot bodies from ~robot_bodies only",
             params.robot_description_param.c_str());
  }
  std::vector<std::string> warnings;
  RobotDescription out = robotDescription(have_urdf ? &urdf : nullptr, params, &warnings);
  for (const std::string& w : warnings) ROS_WARN("proximity_monitor: %s", w.c_str());
  return out;
}

}  // namespace workspace_proximity
