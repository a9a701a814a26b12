#pragma once
/// Robot bodies posed from the joint states: every robot body on a link that URDF joints move
/// follows the joint predictor's keyframed path (forward kinematics of the joints' predicted
/// motion, or of a planned trajectory), its root frame posed from tf. The other bodies keep
/// the tf path (RobotTfBridge). sensor_msgs/JointState and trajectory_msgs/JointTrajectory
/// in; needs no master.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <sensor_msgs/JointState.h>
#include <trajectory_msgs/JointTrajectory.h>

#include "workspace_proximity/monitor/joint_predictor.hpp"
#include "workspace_proximity/monitor/monitor.hpp"
#include "workspace_proximity/ros/robot_tf_bridge.hpp"

namespace workspace_proximity {

/// What the joint bridge reports to the diagnostics.
struct JointBridgeCounters {
  std::uint64_t joint_states = 0;          ///< messages used
  std::uint64_t trajectories = 0;          ///< accepted
  std::uint64_t trajectories_ignored = 0;  ///< refused on arrival (bad or ended)
  std::uint64_t trajectories_dropped = 0;  ///< contradicted by the joint states
  std::string last_trajectory_problem;     ///< why the last one was refused or dropped
};

class RobotJointBridge {
 public:
  /// Claims from `tf_bridge` every robot body of `monitor` whose frame is a link of `model`.
  /// Borrowed: monitor, tf_bridge.
  RobotJointBridge(Monitor* monitor, RobotTfBridge* tf_bridge,
                   std::shared_ptr<const KinematicModel> model);

  /// Robot bodies it poses.
  int bodyCount() const { return static_cast<int>(robot_index_.size()); }

  /// A joint state arrived at `now` (header stamp 0: `now`). Joints the model does not know
  /// are skipped; an empty or short velocity array means "not measured".
  void onJointState(const sensor_msgs::JointState& msg, Stamp now);
  /// A planned trajectory arrived at `now` (header stamp 0: starts now). A bad one is ignored
  /// (the one in force stays) with a throttled warning; counted in counters().
  void onTrajectory(const trajectory_msgs::JointTrajectory& msg, Stamp now);
  /// Poses the claimed bodies at `now` over `horizon` s.
  void update(Stamp now, double horizon);
  /// Forgets readings and the plan (after the clock went back).
  void reset() { predictor_.reset(); }

  const JointBridgeCounters& counters() const { return counters_; }
  const JointPredictor& predictor() const { return predictor_; }

 private:
  Monitor* monitor_;
  RobotTfBridge* tf_bridge_;
  JointPredictor predictor_;
  std::vector<int> robot_index_;  // per predictor body: the robot body
  JointBridgeCounters counters_;
};

}  // namespace workspace_proximity
