// cloud_tracker as a nodelet (workspace_proximity/CloudTrackerNodelet): the same CloudTracker
// as the node, so a camera driver's or depth_image_proc's clouds arrive as shared pointers.
// On a bad parameter it logs it and refuses to load (the manager keeps running).

#include <memory>

#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>

#include "workspace_proximity/ros/cloud_tracker.hpp"

namespace workspace_proximity {

class CloudTrackerNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    try {
      const CloudTrackerParams params = readCloudTrackerParams(getPrivateNodeHandle());
      tracker_ = std::make_unique<CloudTracker>(getNodeHandle(), getPrivateNodeHandle(), params);
    } catch (const std::exception& e) {
      NODELET_FATAL("cloud_tracker: %s", e.what());
      throw;
    }
  }
  std::unique_ptr<CloudTracker> tracker_;
};

}  // namespace workspace_proximity

PLUGINLIB_EXPORT_CLASS(workspace_proximity::CloudTrackerNodelet, nodelet::Nodelet)
