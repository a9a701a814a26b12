// load_generator as a node (see include/workspace_proximity/tools/load_generator.hpp).

#include <ros/ros.h>

#include "workspace_proximity/tools/load_generator.hpp"

int main(int argc, char** argv) {
  ros::init(argc, argv, "load_generator");
  workspace_proximity::LoadGenerator generator(ros::NodeHandle(), ros::NodeHandle("~"), false);
  // Contacts are received on their own thread(s), so receipt times are not held back by the
  // publishing loop.
  ros::AsyncSpinner spinner(2);
  spinner.start();
  generator.run();
  return 0;
}
