#include "workspace_proximity/ros/robot_description.hpp"

#include <string>
#include <unordered_set>

#include <ros/console.h>

#include "workspace_proximity/ros/robot_model.hpp"

namespace workspace_proximity {

RobotDescription loadRobotBodies(const ros::NodeHandle& nh, const MonitorParams& params) {
  RobotDescription out;
  std::vector<RobotBodySpec> specs = params.robot_bodies;
  if (params.use_robot_description) {
    std::string urdf;
    if (nh.getParam(params.robot_description_param, urdf)) {
      const UrdfBodies from_urdf = bodiesFromUrdf(urdf);
      for (const UnmodelledElement& e : from_urdf.unmodelled) {
        out.unmodelled.push_back("robot link " + e.link + ": collision element " +
                                 std::to_string(e.index) + " cannot be modelled: " + e.reason);
      }
      specs.insert(specs.end(), from_urdf.bodies.begin(), from_urdf.bodies.end());
    } else {
      ROS_INFO("proximity_monitor: no '%s' parameter; robot bodies from ~robot_bodies only",
               params.robot_description_param.c_str());
    }
  }
  std::unordered_set<std::string> names;
  for (const RobotBodySpec& spec : specs) {
    if (!names.insert(spec.name).second) {
      ROS_WARN("proximity_monitor: robot body '%s' declared twice; the first is used",
               spec.name.c_str());
      continue;
    }
    out.bodies.push_back(spec);
  }
  return out;
}

}  // namespace workspace_proximity
