// proximity_monitor: predicts contacts between robot links and tracked objects.
// Parameters are read and checked before anything is built; nonsense stops the node with a
// message naming the parameter.

#include <csignal>

#include <ros/ros.h>

#include "workspace_proximity/ros/node_main.hpp"
#include "workspace_proximity/ros/proximity_monitor.hpp"
#include "workspace_proximity/ros/ros_params.hpp"

int main(int argc, char** argv) {
  // A file size limit (ulimit -f) must make a write to ~audit_log fail (EFBIG: the status then
  // stays DEGRADED, docs/node.md "Audit trail"), not kill the monitor.
  std::signal(SIGXFSZ, SIG_IGN);
  ros::init(argc, argv, "proximity_monitor");
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");

  workspace_proximity::MonitorParams params;
  try {
    params = workspace_proximity::readParams(pnh);
  } catch (const std::exception& e) {
    ROS_FATAL("proximity_monitor: invalid parameter %s", e.what());
    return 1;
  }
  for (const std::string& w : workspace_proximity::unknownParams(pnh)) {
    ROS_WARN("proximity_monitor: %s", w.c_str());
  }
  const std::vector<std::string> errors = workspace_proximity::validate(params);
  if (!errors.empty()) {
    for (const std::string& e : errors) ROS_FATAL("proximity_monitor: invalid parameter %s", e.c_str());
    return 1;
  }

  return workspace_proximity::runNode("proximity_monitor", [&] {
    workspace_proximity::ProximityMonitor monitor(nh, pnh, params);
    ros::spin();
  });
}
