// proximity_monitor as a nodelet (workspace_proximity/ProximityMonitorNodelet): the same
// ProximityMonitor as the node, so a tracker nodelet in the same manager hands its arrays over
// as shared pointers, without serialisation. Parameters are read and checked the same way; on
// nonsense the nodelet logs each problem and refuses to load (the manager keeps running).

#include <memory>
#include <stdexcept>

#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>

#include "workspace_proximity/ros/proximity_monitor.hpp"
#include "workspace_proximity/ros/ros_params.hpp"

namespace workspace_proximity {

class ProximityMonitorNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    // Single-threaded handles: the cycle, the arrays, tf and reconfigure never run at once.
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    MonitorParams params;
    try {
      params = readParams(pnh);
    } catch (const std::exception& e) {
      NODELET_FATAL("proximity_monitor: invalid parameter %s", e.what());
      throw;
    }
    for (const std::string& w : unknownParams(pnh)) NODELET_WARN("proximity_monitor: %s", w.c_str());
    const std::vector<std::string> errors = validate(params);
    if (!errors.empty()) {
      for (const std::string& e : errors) NODELET_FATAL("proximity_monitor: invalid parameter %s", e.c_str());
      throw std::runtime_error("proximity_monitor: invalid parameters: " + errors.front());
    }
    monitor_ = std::make_unique<ProximityMonitor>(nh, pnh, params);
  }

  std::unique_ptr<ProximityMonitor> monitor_;
};

}  // namespace workspace_proximity

PLUGINLIB_EXPORT_CLASS(workspace_proximity::ProximityMonitorNodelet, nodelet::Nodelet)
