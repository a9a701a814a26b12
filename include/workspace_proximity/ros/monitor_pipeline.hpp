#pragma once
/// The monitor with its input and robot bridges: everything one prediction cycle needs, fed
/// from any source of arrays and tf. The node feeds it from subscriptions and tf2_ros; the
/// offline replay feeds it from a bag. Needs no master.
///
/// One cycle: (clock went back? reset) -> waiting arrays -> robot poses from tf -> robot
/// links moved by joints from the joint states (when enabled) -> Monitor::cycle (expire,
/// extrapolate, predict) -> CycleReport.

#include <memory>
#include <string>
#include <vector>

#include <tf2/buffer_core.h>
#include <workspace_proximity/TrackedBoxArray.h>

#include "workspace_proximity/monitor/monitor.hpp"
#include "workspace_proximity/ros/diagnostics_bridge.hpp"
#include "workspace_proximity/ros/input_bridge.hpp"
#include "workspace_proximity/ros/robot_joint_bridge.hpp"
#include "workspace_proximity/ros/robot_tf_bridge.hpp"

namespace workspace_proximity {

class MonitorPipeline {
 public:
  /// `params` must have passed validate(). `topics`: resolved input topic names (ids are
  /// qualified by them with `qualify`). `tf` and `sink` (may be null) are borrowed.
  MonitorPipeline(const MonitorParams& params, std::vector<RobotBodySpec> robot,
                  const std::vector<std::string>& topics, bool qualify, tf2::BufferCore* tf,
                  RejectionSink* sink);

  /// An array of input `source` arrived at `now`.
  void onArray(int source, const TrackedBoxArray::ConstPtr& msg, Stamp now) {
    input_.onArray(source, msg, now);
  }
  /// Poses the robot bodies on links that `model`'s joints move from the joint states (and a
  /// planned trajectory) instead of tf. Returns how many bodies that is.
  int enableJoints(std::shared_ptr<const KinematicModel> model);
  bool jointsEnabled() const { return joints_ != nullptr; }
  /// A sensor_msgs/JointState arrived at `now` (ignored unless enableJoints()).
  void onJointState(const sensor_msgs::JointState& msg, Stamp now) {
    if (joints_) joints_->onJointState(msg, now);
  }
  /// A trajectory_msgs/JointTrajectory arrived at `now` (ignored unless enableJoints()).
  void onTrajectory(const trajectory_msgs::JointTrajectory& msg, Stamp now) {
    if (joints_) joints_->onTrajectory(msg, now);
  }
  /// One cycle at `now`. `*reset` tells whether the clock had gone back, so the history (and
  /// tf's buffer) was reset first. May throw; then call Monitor::cycleFailed.
  const CycleReport& cycle(Stamp now, StageClock* clock, bool* reset);

  Monitor& monitor() { return monitor_; }
  const Monitor& monitor() const { return monitor_; }
  BridgeCounters counters() const {
    BridgeCounters out;
    out.tf_failures = input_.tfFailures() + robot_.tfFailures();
    if (joints_) {
      out.joints = true;
      out.joint = joints_->counters();
    }
    return out;
  }

 private:
  tf2::BufferCore* tf_;
  Monitor monitor_;
  InputBridge input_;
  RobotTfBridge robot_;
  std::unique_ptr<RobotJointBridge> joints_;
};

}  // namespace workspace_proximity
