#pragma once
/// The monitor with its input and robot bridges and the cycle runner: everything one
/// prediction cycle needs, fed from any source of arrays and tf. The node feeds it from
/// subscriptions and tf2_ros, the offline replay from a bag; both run every cycle through
/// run(), and so through CycleRunner (rules/cycle_runner.hpp), which owns reset, failure and
/// timing. Needs no master.
///
/// The runner itself is ROS-free (the benchmarks run it without ROS); this class is its feed:
/// on a clock that went back it forgets the waiting arrays, tf's history and the joint
/// readings, before each cycle it hands over the waiting arrays and poses the robot (tf, then
/// the links moved by joints, when enabled), and it logs a failed cycle. The setup the node and
/// the replay share lives here too: tfCacheTime() for their tf buffer, jointModel() for the
/// robot's joints.
///
/// One cycle: run(now, out) -> CycleRunner::run: (clock went back? reset) -> waiting arrays
/// -> robot poses from tf -> robot links moved by joints -> Monitor::cycle (expire,
/// extrapolate, predict) -> CycleReport -> out (contacts, then the rest).

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <ros/duration.h>
#include <tf2/buffer_core.h>
#include <workspace_proximity/TrackedBoxArray.h>

#include "workspace_proximity/rules/cycle_runner.hpp"
#include "workspace_proximity/rules/monitor.hpp"
#include "workspace_proximity/ros/input_bridge.hpp"
#include "workspace_proximity/ros/robot_joint_bridge.hpp"
#include "workspace_proximity/ros/robot_tf_bridge.hpp"

namespace workspace_proximity {

/// Counters the ROS bridges keep themselves.
struct BridgeCounters {
  std::uint64_t tf_failures = 0;  ///< arrays and robot poses tf could not transform
  bool joints = false;            ///< robot links posed from joint states
  JointBridgeCounters joint;      ///< their counters (when `joints`)
};

class MonitorBridges : private CycleFeed {
 public:
  /// History a tf buffer feeding the bridges must keep: ten seconds, or four velocity windows.
  static ros::Duration tfCacheTime(const MonitorParams& params);
  /// The robot's joints for posing links from joint states (~use_joint_states with a URDF,
  /// `urdf_xml`): null when not asked for, when no link moves, or when KDL refuses the tree
  /// (logged; every link then stays on tf).
  static std::shared_ptr<const KinematicModel> jointModel(const MonitorParams& params,
                                                          const std::string& urdf_xml);

  /// `params` must have passed validate(). `topics`: resolved input topic names (ids are
  /// qualified by them with `qualify`). `tf` (its cache tfCacheTime()) and `sink` (may be
  /// null) are borrowed.
  MonitorBridges(const MonitorParams& params, std::vector<RobotBodySpec> robot,
                  const std::vector<std::string>& topics, bool qualify, tf2::BufferCore* tf,
                  RejectionSink* sink);

  /// An array of input `source` arrived at `now`.
  void onArray(int source, const TrackedBoxArray::ConstPtr& msg, Stamp now);
  /// A foreign tracker message of input `source` (InputBridge::foreignBytes, onForeign): its
  /// serialized bytes written to foreignBytes(source, size), then onForeign at `now`.
  std::uint8_t* foreignBytes(int source, std::size_t size) {
    return input_.foreignBytes(source, size);
  }
  void onForeign(int source, std::string_view type, std::string_view md5,
                 std::string_view definition, Stamp now);
  /// InputBridge::foreignFrame.
  std::string_view foreignFrame(int source) const { return input_.foreignFrame(source); }
  /// Input `source` sends a type that cannot be read at all: DEGRADED with `why` until it sends
  /// one that can.
  void refuseType(int source, const std::string& why) { input_.refuseType(source, why); }
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

  /// One cycle at `now`, its report to `out` (may be null). Never throws from the cycle.
  CycleRun run(Stamp now, CycleOutput* out) { return runner_.run(now, this, out); }
  /// A stage outside the cycle (kMarkers) took `ms`.
  void noteTime(CycleStage stage, double ms) { runner_.noteTime(stage, ms); }

  /// Live tuning: Monitor::setParams.
  void setParams(const MonitorParams& params) { monitor_.setParams(params); }
  /// Monitor::addPermanentIssue.
  void addPermanentIssue(const std::string& line) { monitor_.addPermanentIssue(line); }
  /// A perception front end's status (~perception_status_topics[i]): PerceptionHealth.
  void onPerceptionStatus(int i, Stamp now, bool degraded, const std::vector<std::string>& reasons,
                          double unseen_share) {
    monitor_.perception().onStatus(i, now, degraded, reasons, unseen_share);
  }

  const Monitor& monitor() const { return monitor_; }
  /// The stop latch (reset, mute, joint speeds): Monitor::latch.
  StopLatch& latch() { return monitor_.latch(); }
  const CycleRunner& runner() const { return runner_; }
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
  // CycleFeed
  void reset(Stamp now) override;
  void update(Stamp now) override;
  void failed(const std::string& what) override;

  tf2::BufferCore* tf_;
  Monitor monitor_;
  CycleRunner runner_;
  InputBridge input_;
  RobotTfBridge robot_;
  std::unique_ptr<RobotJointBridge> joints_;
};

}  // namespace workspace_proximity
