#include "workspace_proximity/ros/ssm_publisher.hpp"

#include <algorithm>
#include <cmath>

#include <ros/console.h>
#include <std_msgs/Float64.h>
#include <std_msgs/Int64.h>
#include <std_msgs/String.h>
#include <trajectory_msgs/JointTrajectory.h>

#include "workspace_proximity/ros/conversions.hpp"

namespace workspace_proximity {

void fillSafetyStatus(const CycleReport& report, const ProximityWorld& world,
                      const std::string& fixed_frame, SafetyStatus* out) {
  const SsmVerdict& v = report.ssm;
  out->header.stamp = toTime(report.stamp);
  out->header.frame_id = fixed_frame;
  out->speed_scale = v.speed_scale;
  out->raw_scale = v.raw_scale;
  out->protective_stop = v.speed_scale <= 0.0;
  if (v.limited && world.contains(v.robot) && world.contains(v.object)) {
    out->id_robot = world.desc(v.robot).id;
    out->id_object = world.desc(v.object).id;
  } else {
    out->id_robot.clear();
    out->id_object.clear();
  }
  out->separation = v.separation;
  out->required_separation = v.required_separation;
  out->approach_speed = v.approach_speed;
  out->status = report.degraded ? SafetyStatus::DEGRADED : SafetyStatus::OK;
  out->reason = v.reason;
}

std::int64_t speedOverride(double scale) {
  return static_cast<std::int64_t>(std::lround(100.0 * std::clamp(scale, 0.0, 1.0)));
}

SsmPublisher::SsmPublisher(ros::NodeHandle& nh, const std::string& fixed_frame,
                           const SsmParams& params)
    : fixed_frame_(fixed_frame),
      scale_pub_(nh.advertise<std_msgs::Float64>("speed_scale", 10)),
      status_pub_(nh.advertise<SafetyStatus>("safety_status", 10)),
      override_pub_(nh.advertise<std_msgs::Int64>("speed_override", 10)) {
  for (const std::string& topic : params.stop_trajectory_topics) {
    trajectory_pubs_.push_back(nh.advertise<trajectory_msgs::JointTrajectory>(topic, 1));
  }
  for (const std::string& topic : params.stop_event_topics) {
    event_pubs_.push_back(nh.advertise<std_msgs::String>(topic, 1));
  }
}

void SsmPublisher::publish(const CycleReport& report, const ProximityWorld& world) {
  fillSafetyStatus(report, world, fixed_frame_, &msg_);
  std_msgs::Float64 scale;
  scale.data = report.ssm.speed_scale;
  scale_pub_.publish(scale);
  status_pub_.publish(msg_);
  std_msgs::Int64 percent;
  percent.data = speedOverride(report.ssm.speed_scale);
  override_pub_.publish(percent);
  stopActions(report);
}

void SsmPublisher::stopActions(const CycleReport& report) {
  const bool stop = report.ssm.speed_scale <= 0.0;
  if (!stop) {
    stopped_ = false;  // re-armed: the next stop acts again
    return;
  }
  if (stopped_) return;  // once per stop
  stopped_ = true;
  ++stops_;
  ROS_WARN("proximity_monitor: protective stop (speed scale 0): %s%s", msg_.reason.c_str(),
           trajectory_pubs_.empty() && event_pubs_.empty() ? "" : "; stop actions sent");
  // An empty trajectory makes a ros_control joint_trajectory_controller hold its position;
  // "stop" on MoveIt 1's trajectory_execution_event cancels the running execution.
  const trajectory_msgs::JointTrajectory empty;
  for (ros::Publisher& p : trajectory_pubs_) p.publish(empty);
  std_msgs::String word;
  word.data = "stop";
  for (ros::Publisher& p : event_pubs_) p.publish(word);
}

}  // namespace workspace_proximity
