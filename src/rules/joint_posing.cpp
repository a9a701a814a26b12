#include "workspace_proximity/rules/joint_posing.hpp"

#include <limits>

namespace workspace_proximity {
namespace {

JointPredictorParams predictorParams(const MonitorParams& p) {
  JointPredictorParams out;
  out.state_timeout = p.tf_timeout;
  out.trajectory_tolerance = p.trajectory_tolerance;
  out.path_tolerance = p.joint_path_tolerance;
  return out;
}

}  // namespace

JointPosing::JointPosing(Monitor* monitor, std::shared_ptr<const KinematicModel> model)
    : monitor_(monitor), predictor_(std::move(model), predictorParams(monitor->params())) {
  const RobotBodies& robot = monitor_->robot();
  for (int i = 0; i < robot.size(); ++i) {
    const RobotBodySpec& spec = robot.spec(i);
    const int link = predictor_.model().linkIndex(spec.frame);
    if (link < 0) continue;  // fixed to the root, or on another frame: tf
    predictor_.addBody(link, spec.offset, spec.shape.boundingRadius());
    robot_index_.push_back(i);
  }
}

void JointPosing::onJointState(const std::vector<std::string>& names,
                               const std::vector<double>& positions,
                               const std::vector<double>& velocities, Stamp stamp, Stamp now) {
  if (stamp == 0) stamp = now;
  const bool measured = velocities.size() == names.size();
  for (std::size_t k = 0; k < names.size() && k < positions.size(); ++k) {
    const int j = predictor_.model().jointIndex(names[k]);
    if (j < 0) continue;
    predictor_.observe(j, stamp, positions[k],
                       measured ? velocities[k] : std::numeric_limits<double>::quiet_NaN());
  }
  ++counters_.joint_states;
}

std::string toJointPlan(const KinematicModel& model, const PlannedTrajectory& trajectory, Stamp now,
                        JointPlan* plan) {
  plan->start = trajectory.start == 0 ? now : trajectory.start;
  for (const std::string& name : trajectory.joint_names) {
    const int j = model.jointIndex(name);
    if (j < 0) return "joint '" + name + "' is not a movable joint of the robot model";
    plan->joints.push_back(j);
  }
  for (std::size_t p = 0; p < trajectory.positions.size(); ++p) {
    const std::vector<double>& point = trajectory.positions[p];
    if (point.size() != trajectory.joint_names.size() || p >= trajectory.times.size()) {
      return "a point's positions do not match its joint names";
    }
    plan->times.push_back(trajectory.times[p]);
    plan->positions.insert(plan->positions.end(), point.begin(), point.end());
  }
  return std::string();
}

std::string JointPosing::onTrajectory(PlannedTrajectory trajectory, Stamp now) {
  JointPlan plan;
  std::string why = toJointPlan(predictor_.model(), trajectory, now, &plan);
  if (why.empty()) why = predictor_.setPlan(std::move(plan), now);
  if (!why.empty()) {
    ++counters_.trajectories_ignored;
    counters_.last_trajectory_problem = "trajectory ignored: " + why;
    return why;
  }
  ++counters_.trajectories;
  return why;
}

JointPosingLog JointPosing::update(Stamp now, const BodyMotion* base, const std::string& root_why,
                                   const std::string& root_stale) {
  JointPosingLog log;
  // Live tuning (~tf_timeout) applies from the next cycle, as for tf.
  predictor_.setParams(predictorParams(monitor_->params()));
  if (base == nullptr) {
    // Everything the joints move rides on the root frame: nothing of it can be posed.
    for (int i : robot_index_) {
      monitor_->markRobotUnknown(
          i, "root frame '" + predictor_.model().root() + "' not posed: " + root_why);
    }
    return log;
  }
  predictor_.predict(now, monitor_->params().horizon, *base);
  if (!predictor_.planEvent().empty()) {
    ++counters_.trajectories_dropped;
    counters_.last_trajectory_problem = "trajectory dropped: " + predictor_.planEvent();
    log.plan_dropped = true;
  }
  for (int b = 0; b < predictor_.bodyCount(); ++b) {
    const int i = robot_index_[static_cast<std::size_t>(b)];
    const JointBodyPath& path = predictor_.body(b);
    if (path.state == JointPathState::kUnknown) {
      monitor_->markRobotUnknown(i, path.why);
      if (log.unknown < 0) log.unknown = b;
      continue;
    }
    const std::string& reason = path.state == JointPathState::kStale ? path.why : root_stale;
    if (!monitor_->poseRobotPath(i, path.segments.data(), static_cast<int>(path.segments.size()),
                                 reason) &&
        log.refused < 0) {
      log.refused = b;
    }
  }
  return log;
}

}  // namespace workspace_proximity
