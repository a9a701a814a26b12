#include "workspace_proximity/ros/latch_bridge.hpp"

#include <algorithm>
#include <cmath>

#include <ros/console.h>

#include "workspace_proximity/ros/conversions.hpp"

namespace workspace_proximity {

double maxJointSpeed(const sensor_msgs::JointState& msg, bool* known) {
  // An empty or short velocity array means "not measured": never a standstill.
  *known = !msg.name.empty() && msg.velocity.size() == msg.name.size();
  double fastest = 0.0;
  for (const double v : msg.velocity) {
    if (!std::isfinite(v)) *known = false;
    fastest = std::max(fastest, std::abs(v));
  }
  return fastest;
}

LatchBridge::LatchBridge(ros::NodeHandle& nh, ros::NodeHandle& private_nh, const SsmParams& params,
                         StopLatch* latch, std::mutex* mutex)
    : latch_(latch), mutex_(mutex) {
  reset_srv_ = private_nh.advertiseService("reset", &LatchBridge::onReset, this);
  mute_srv_ = private_nh.advertiseService("mute", &LatchBridge::onMute, this);
  if (params.stop_category == 1) {
    joints_sub_ = nh.subscribe("joint_states", 10, &LatchBridge::onJointState, this,
                               ros::TransportHints().tcpNoDelay());
  }
  ROS_INFO("proximity_monitor: restart %s, minimum stop time %.2f s, stop category %d%s%s, "
           "muting %s", params.restart.c_str(), params.min_stop_time, params.stop_category,
           params.stop_category == 1 ? ", halt on " : "",
           params.stop_category != 1 ? ""
           : !params.halt_service.empty() ? nh.resolveName(params.halt_service).c_str()
                                          : nh.resolveName(params.halt_topic).c_str(),
           params.max_mute_time > 0.0 ? "on (~mute)" : "off (~ssm/max_mute_time 0)");
}

bool LatchBridge::onReset(std_srvs::Trigger::Request& /*req*/, std_srvs::Trigger::Response& res) {
  std::lock_guard<std::mutex> lock(*mutex_);
  res.success = latch_->requestReset(toStamp(ros::Time::now()), &res.message);
  return true;
}

bool LatchBridge::onMute(Mute::Request& req, Mute::Response& res) {
  std::lock_guard<std::mutex> lock(*mutex_);
  res.success = latch_->requestMute(toStamp(ros::Time::now()), req.labels, req.ids, req.duration,
                                    &res.message);
  return true;
}

void LatchBridge::onJointState(const sensor_msgs::JointState::ConstPtr& msg) {
  bool known = false;
  const double fastest = maxJointSpeed(*msg, &known);
  std::lock_guard<std::mutex> lock(*mutex_);
  latch_->noteJointSpeed(toStamp(ros::Time::now()), fastest, known);
}

}  // namespace workspace_proximity
