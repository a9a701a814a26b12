#include "workspace_proximity/ros/ssm_publisher.hpp"

#include <algorithm>
#include <cmath>

#include <ros/console.h>
#include <std_msgs/Empty.h>
#include <std_msgs/Float64.h>
#include <std_msgs/Int64.h>
#include <std_msgs/String.h>
#include <std_srvs/Trigger.h>
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
  out->unseen_share = report.unseen_share;
  if (v.latch != nullptr) {
    const LatchState& l = *v.latch;
    out->stopped = l.stopped;
    out->hold = l.hold;
    out->reset_required = l.reset_required;
    out->halt_requested = l.halt_requested;
    out->muted = l.muted;
    out->mute_scope = l.mute_scope;
    out->mute_left = l.mute_left;
  } else {
    out->stopped = false;
    out->hold.clear();
    out->reset_required = false;
    out->halt_requested = false;
    out->muted = false;
    out->mute_scope.clear();
    out->mute_left = 0.0;
  }
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
  nh_ = nh;
  if (!params.halt_topic.empty()) halt_pub_ = nh.advertise<std_msgs::Empty>(params.halt_topic, 1);
  if (!params.halt_service.empty()) {
    halt_service_ = nh.resolveName(params.halt_service);
    halt_thread_ = std::thread([this] { haltLoop(); });
  }
}

SsmPublisher::~SsmPublisher() {
  {
    std::lock_guard<std::mutex> lock(halt_mutex_);
    closing_ = true;
  }
  halt_wake_.notify_all();
  if (halt_thread_.joinable()) halt_thread_.join();
}

void SsmPublisher::haltLoop() {
  // Off the cycle: a slow or absent halt service never delays the scale.
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(halt_mutex_);
      halt_wake_.wait(lock, [this] { return closing_ || halts_waiting_ > 0; });
      if (closing_) return;
      halts_waiting_ = 0;  // one call answers every request made while it waited
    }
    ros::ServiceClient client = nh_.serviceClient<std_srvs::Trigger>(halt_service_);
    std_srvs::Trigger call;
    if (!client.waitForExistence(ros::Duration(1.0))) {
      ROS_ERROR("proximity_monitor: halt service %s not available; the robot stays held at "
                "scale 0 but is NOT halted", halt_service_.c_str());
    } else if (!client.call(call)) {
      ROS_ERROR("proximity_monitor: halt service %s failed; the robot stays held at scale 0 but "
                "is NOT halted", halt_service_.c_str());
    } else if (!call.response.success) {
      ROS_ERROR("proximity_monitor: halt service %s refused: %s", halt_service_.c_str(),
                call.response.message.c_str());
    } else {
      ROS_WARN("proximity_monitor: halt service %s: %s", halt_service_.c_str(),
               call.response.message.c_str());
    }
  }
}

void SsmPublisher::publish(const CycleReport& report, const ProximityWorld& world) {
  // What a controller acts on goes out before the status message is even filled.
  std_msgs::Float64 scale;
  scale.data = report.ssm.speed_scale;
  scale_pub_.publish(scale);
  std_msgs::Int64 percent;
  percent.data = speedOverride(report.ssm.speed_scale);
  override_pub_.publish(percent);
  fillSafetyStatus(report, world, fixed_frame_, &msg_);
  status_pub_.publish(msg_);
  stopActions(report);
  latchEvents(report);
}

void SsmPublisher::latchEvents(const CycleReport& report) {
  const LatchEvents* events = report.ssm.latch_events;
  if (events == nullptr) return;
  for (int i = 0; i < events->size(); ++i) {
    const LatchEvent& e = (*events)[i];
    switch (e.kind) {
      case LatchEventKind::kStop:
        break;  // stopActions() logs the stop
      case LatchEventKind::kHaltRequested:
        ROS_WARN("proximity_monitor: %s", e.reason.c_str());
        if (!halt_pub_.getTopic().empty()) halt_pub_.publish(std_msgs::Empty());
        if (!halt_service_.empty()) {
          {
            std::lock_guard<std::mutex> lock(halt_mutex_);
            ++halts_waiting_;
          }
          halt_wake_.notify_one();
        }
        break;
      case LatchEventKind::kResetRefused:
      case LatchEventKind::kMuteRefused:
      case LatchEventKind::kMuteStarted:
      case LatchEventKind::kMuteEnded:
        ROS_WARN("proximity_monitor: %s", e.reason.c_str());
        break;
      default:
        ROS_INFO("proximity_monitor: %s", e.reason.c_str());
        break;
    }
  }
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
