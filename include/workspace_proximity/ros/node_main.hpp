#pragma once
/// The end of a node executable's main(), shared by proximity_monitor, cloud_tracker and
/// trajectory_relay: build the node and spin; an exception (a parameter that makes no sense, a
/// resource that cannot be had) stops it with a fatal message naming the node.

#include <exception>

#include <ros/console.h>

namespace workspace_proximity {

/// Calls `run()` (builds the node object and calls ros::spin()); returns the exit status: 0
/// when it returns, 1 after logging "<name>: <what>" as ROS_FATAL when it throws.
template <typename Run>
int runNode(const char* name, Run run) {
  try {
    run();
  } catch (const std::exception& e) {
    ROS_FATAL("%s: %s", name, e.what());
    return 1;
  }
  return 0;
}

}  // namespace workspace_proximity
