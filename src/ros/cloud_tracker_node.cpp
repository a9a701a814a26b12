// cloud_tracker: depth clouds and laser scans into clusters (docs/perception.md). Parameters
// are read and checked before anything is built; nonsense stops the node naming the parameter.

#include <ros/ros.h>

#include "workspace_proximity/ros/cloud_tracker.hpp"
#include "workspace_proximity/ros/node_main.hpp"

int main(int argc, char** argv) {
  ros::init(argc, argv, "cloud_tracker");
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  return workspace_proximity::runNode("cloud_tracker", [&] {
    const workspace_proximity::CloudTrackerParams params = workspace_proximity::readCloudTrackerParams(pnh);
    workspace_proximity::CloudTracker tracker(nh, pnh, params);
    ros::spin();
  });
}
