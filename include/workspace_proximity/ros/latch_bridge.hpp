#pragma once
/// The stop latch's ROS side (rules/stop_latch.hpp): the services ~reset (std_srvs/Trigger) and
/// ~mute (workspace_proximity/Mute), and, for stop category 1, the joint speeds from
/// joint_states. Requests are decided at once against the last cycle (the response carries the
/// reason); their events come out with the next cycle. Every call into the latch holds `mutex`,
/// which the node's cycle holds too (a nodelet's callbacks may run on several threads).

#include <mutex>

#include <ros/node_handle.h>
#include <ros/service_server.h>
#include <ros/subscriber.h>
#include <sensor_msgs/JointState.h>
#include <std_srvs/Trigger.h>
#include <workspace_proximity/Mute.h>

#include "workspace_proximity/rules/ssm_rule.hpp"
#include "workspace_proximity/rules/stop_latch.hpp"

namespace workspace_proximity {

/// The largest |velocity| of a joint_states message, and whether every joint's is known (a
/// velocity array as long as the names, all finite).
double maxJointSpeed(const sensor_msgs::JointState& msg, bool* known);

class LatchBridge {
 public:
  /// Services in `private_nh`'s namespace, joint_states in `nh`'s (category 1 only). `latch`
  /// and `mutex` are borrowed.
  LatchBridge(ros::NodeHandle& nh, ros::NodeHandle& private_nh, const SsmParams& params,
              StopLatch* latch, std::mutex* mutex);

 private:
  bool onReset(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);
  bool onMute(Mute::Request& req, Mute::Response& res);
  void onJointState(const sensor_msgs::JointState::ConstPtr& msg);

  StopLatch* latch_;
  std::mutex* mutex_;
  ros::ServiceServer reset_srv_;
  ros::ServiceServer mute_srv_;
  ros::Subscriber joints_sub_;
};

}  // namespace workspace_proximity
