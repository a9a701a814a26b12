#pragma once
/// Robot bodies posed from the joint states: every robot body on a link that URDF joints move
/// follows the joint predictor's keyframed path (forward kinematics of the joints' predicted
/// motion, or of a planned trajectory), its root frame posed from tf. The other bodies keep
/// the tf path (RobotTfBridge). sensor_msgs/JointState and trajectory_msgs/JointTrajectory
/// in; needs no master. The rules are JointPosing's (rules layer); this bridge converts the
/// messages, poses the root frame from tf and logs.

#include <memory>

#include <sensor_msgs/JointState.h>
#include <trajectory_msgs/JointTrajectory.h>

#include "workspace_proximity/rules/joint_posing.hpp"
#include "workspace_proximity/rules/monitor.hpp"
#include "workspace_proximity/ros/robot_tf_bridge.hpp"

namespace workspace_proximity {

class RobotJointBridge {
 public:
  /// Claims from `tf_bridge` every robot body of `monitor` whose frame is a link of `model`.
  /// Borrowed: monitor, tf_bridge.
  RobotJointBridge(Monitor* monitor, RobotTfBridge* tf_bridge,
                   std::shared_ptr<const KinematicModel> model);

  /// Robot bodies it poses.
  int bodyCount() const { return static_cast<int>(posing_.claimed().size()); }

  /// A joint state arrived at `now` (header stamp 0: `now`). Joints the model does not know
  /// are skipped; an empty or short velocity array means "not measured".
  void onJointState(const sensor_msgs::JointState& msg, Stamp now);
  /// A planned trajectory arrived at `now` (header stamp 0: starts now). A bad one is ignored
  /// (the one in force stays) with a throttled warning; counted in counters().
  void onTrajectory(const trajectory_msgs::JointTrajectory& msg, Stamp now);
  /// Poses the claimed bodies at `now` over the monitor's horizon.
  void update(Stamp now);
  /// Forgets readings and the plan (after the clock went back).
  void reset() { posing_.reset(); }

  const JointBridgeCounters& counters() const { return posing_.counters(); }
  const JointPredictor& predictor() const { return posing_.predictor(); }

 private:
  const Monitor* monitor_;
  RobotTfBridge* tf_bridge_;
  JointPosing posing_;
};

}  // namespace workspace_proximity
