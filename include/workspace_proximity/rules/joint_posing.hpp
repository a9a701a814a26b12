#pragma once
/// The rules of posing robot bodies from the joints, without ROS (RobotJointBridge feeds it
/// the messages' contents and the root frame's motion from tf):
///   - it claims every robot body whose frame is a link the model's joints move;
///   - joint states: joints the model does not know are skipped; a velocity array shorter or
///     longer than the names means "not measured"; stamp 0 means the arrival;
///   - a planned trajectory: refused whole (the one in force stays) when a joint is not a
///     movable joint of the model, a point's positions do not match its names, or the
///     predictor refuses it; counted;
///   - each cycle: with the root frame not posed every claimed body is unknown; otherwise the
///     predictor's path poses each body (stale with its own reason, or the root's), and a body
///     it cannot predict is unknown with the reason.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "workspace_proximity/rules/joint_predictor.hpp"
#include "workspace_proximity/rules/monitor.hpp"

namespace workspace_proximity {

/// What posing from the joints reports to the diagnostics.
struct JointBridgeCounters {
  std::uint64_t joint_states = 0;          ///< messages used
  std::uint64_t trajectories = 0;          ///< accepted
  std::uint64_t trajectories_ignored = 0;  ///< refused on arrival (bad or ended)
  std::uint64_t trajectories_dropped = 0;  ///< contradicted by the joint states
  std::string last_trajectory_problem;     ///< why the last one was refused or dropped
};

/// A planned trajectory as received (trajectory_msgs/JointTrajectory's contents).
struct PlannedTrajectory {
  Stamp start = 0;  ///< header stamp, ns; 0: starts on arrival
  std::vector<std::string> joint_names;
  std::vector<double> times;                   ///< per point: time from the start, s
  std::vector<std::vector<double>> positions;  ///< per point: one per joint name, rad or m
};

/// `trajectory` in `model`'s joint indices (its start 0: `now`) into `plan`: "" when it
/// converts, else why not (a joint the model does not move, a point that does not match the
/// names). The predictor's setPlan checks the rest.
std::string toJointPlan(const KinematicModel& model, const PlannedTrajectory& trajectory, Stamp now,
                        JointPlan* plan);

/// What a cycle of JointPosing::update has to say (the bridge logs it, throttled).
struct JointPosingLog {
  bool plan_dropped = false;  ///< the plan was dropped (counters() says why)
  int unknown = -1;           ///< first claimed body not posed (index into claimed()), or -1
  int refused = -1;           ///< first claimed body whose path the core refused, or -1
};

class JointPosing {
 public:
  /// Claims every robot body of `monitor` (borrowed) on a link of `model`.
  JointPosing(Monitor* monitor, std::shared_ptr<const KinematicModel> model);

  /// The robot bodies it poses (indices into Monitor::robot()), in its own order.
  const std::vector<int>& claimed() const { return robot_index_; }

  /// A joint state arrived at `now`: per name, a position and (when `velocities` has one per
  /// name) a velocity; `stamp` 0 means `now`.
  void onJointState(const std::vector<std::string>& names, const std::vector<double>& positions,
                    const std::vector<double>& velocities, Stamp stamp, Stamp now);
  /// A planned trajectory arrived at `now`. Returns "" when it is in force, else why it was
  /// refused (counted).
  std::string onTrajectory(PlannedTrajectory trajectory, Stamp now);
  /// Poses the claimed bodies at `now` over the monitor's horizon, riding on the root frame's
  /// motion `base`; null when tf could not pose the root (`root_why`). `root_stale`: why the
  /// root's motion is not known yet ("" when it is).
  JointPosingLog update(Stamp now, const BodyMotion* base, const std::string& root_why,
                        const std::string& root_stale);
  /// Forgets readings and the plan (after the clock went back).
  void reset() { predictor_.reset(); }

  const JointBridgeCounters& counters() const { return counters_; }
  const JointPredictor& predictor() const { return predictor_; }

 private:
  Monitor* monitor_;
  JointPredictor predictor_;
  std::vector<int> robot_index_;  // per predictor body: the robot body
  JointBridgeCounters counters_;
};

}  // namespace workspace_proximity
