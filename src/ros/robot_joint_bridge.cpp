#include "workspace_proximity/ros/robot_joint_bridge.hpp"

#include <cmath>
#include <limits>

#include <ros/console.h>

#include "workspace_proximity/ros/conversions.hpp"

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

RobotJointBridge::RobotJointBridge(Monitor* monitor, RobotTfBridge* tf_bridge,
                                   std::shared_ptr<const KinematicModel> model)
    : monitor_(monitor),
      tf_bridge_(tf_bridge),
      predictor_(std::move(model), predictorParams(monitor->params())) {
  const RobotBodies& robot = monitor_->robot();
  for (int i = 0; i < robot.size(); ++i) {
    const RobotBodySpec& spec = robot.spec(i);
    const int link = predictor_.model().linkIndex(spec.frame);
    if (link < 0) continue;  // fixed to the root, or on another frame: tf
    predictor_.addBody(link, spec.offset, spec.shape.boundingRadius());
    robot_index_.push_back(i);
    tf_bridge_->setClaimed(i, true);
  }
}

void RobotJointBridge::onJointState(const sensor_msgs::JointState& msg, Stamp now) {
  const Stamp stamp = msg.header.stamp.isZero() ? now : toStamp(msg.header.stamp);
  const bool velocities = msg.velocity.size() == msg.name.size();
  for (std::size_t k = 0; k < msg.name.size() && k < msg.position.size(); ++k) {
    const int j = predictor_.model().jointIndex(msg.name[k]);
    if (j < 0) continue;
    predictor_.observe(j, stamp, msg.position[k],
                       velocities ? msg.velocity[k] : std::numeric_limits<double>::quiet_NaN());
  }
  ++counters_.joint_states;
}

void RobotJointBridge::onTrajectory(const trajectory_msgs::JointTrajectory& msg, Stamp now) {
  JointPlan plan;
  plan.start = msg.header.stamp.isZero() ? now : toStamp(msg.header.stamp);
  std::string why;
  for (const std::string& name : msg.joint_names) {
    const int j = predictor_.model().jointIndex(name);
    if (j < 0) {
      why = "joint '" + name + "' is not a movable joint of the robot model";
      break;
    }
    plan.joints.push_back(j);
  }
  if (why.empty()) {
    for (const trajectory_msgs::JointTrajectoryPoint& point : msg.points) {
      if (point.positions.size() != msg.joint_names.size()) {
        why = "a point's positions do not match its joint names";
        break;
      }
      plan.times.push_back(point.time_from_start.toSec());
      plan.positions.insert(plan.positions.end(), point.positions.begin(), point.positions.end());
    }
  }
  if (why.empty()) why = predictor_.setPlan(std::move(plan), now);
  if (!why.empty()) {
    ++counters_.trajectories_ignored;
    counters_.last_trajectory_problem = "trajectory ignored: " + why;
    ROS_WARN_THROTTLE(5.0, "proximity_monitor: planned trajectory ignored: %s", why.c_str());
    return;
  }
  ++counters_.trajectories;
}

void RobotJointBridge::update(Stamp now, double horizon) {
  RobotBodies& robot = monitor_->robot();
  // Live tuning (~tf_timeout) applies from the next cycle, as for tf.
  predictor_.setParams(predictorParams(monitor_->params()));
  // The root frame from tf: everything the joints move rides on it.
  BodyMotion base;
  std::string why, stale;
  const bool root_ok = tf_bridge_->frameMotion(predictor_.model().root(), Eigen::Isometry3d::Identity(),
                                               now, &base, &why, &stale) &&
                       base.valid();
  if (!root_ok) {
    for (int i : robot_index_) {
      robot.markUnknown(i, "root frame '" + predictor_.model().root() + "' not posed: " + why);
    }
    return;
  }
  predictor_.predict(now, horizon, base);
  if (!predictor_.planEvent().empty()) {
    ++counters_.trajectories_dropped;
    counters_.last_trajectory_problem = "trajectory dropped: " + predictor_.planEvent();
    ROS_WARN_THROTTLE(5.0, "proximity_monitor: planned trajectory dropped: %s",
                      predictor_.planEvent().c_str());
  }
  for (int b = 0; b < predictor_.bodyCount(); ++b) {
    const int i = robot_index_[static_cast<std::size_t>(b)];
    const JointBodyPath& path = predictor_.body(b);
    if (path.state == JointPathState::kUnknown) {
      robot.markUnknown(i, path.why);
      ROS_WARN_THROTTLE(5.0, "proximity_monitor: robot body '%s' not posed: %s",
                        robot.spec(i).name.c_str(), path.why.c_str());
      continue;
    }
    const std::string& reason = path.state == JointPathState::kStale ? path.why : stale;
    if (!robot.posePath(i, path.segments.data(), static_cast<int>(path.segments.size()), reason)) {
      ROS_WARN_THROTTLE(5.0, "proximity_monitor: robot body '%s': %s", robot.spec(i).name.c_str(),
                        robot.why(i).c_str());
    }
  }
}

}  // namespace workspace_proximity
