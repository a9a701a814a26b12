#include "workspace_proximity/ros/robot_joint_bridge.hpp"

#include <ros/console.h>

#include "workspace_proximity/ros/conversions.hpp"

namespace workspace_proximity {

RobotJointBridge::RobotJointBridge(Monitor* monitor, RobotTfBridge* tf_bridge,
                                   std::shared_ptr<const KinematicModel> model)
    : monitor_(monitor), tf_bridge_(tf_bridge), posing_(monitor, std::move(model)) {
  for (int i : posing_.claimed()) tf_bridge_->setClaimed(i, true);
}

void RobotJointBridge::onJointState(const sensor_msgs::JointState& msg, Stamp now) {
  posing_.onJointState(msg.name, msg.position, msg.velocity, toStamp(msg.header.stamp), now);
}

void RobotJointBridge::onTrajectory(const trajectory_msgs::JointTrajectory& msg, Stamp now) {
  PlannedTrajectory plan;
  plan.start = toStamp(msg.header.stamp);
  plan.joint_names = msg.joint_names;
  for (const trajectory_msgs::JointTrajectoryPoint& point : msg.points) {
    plan.times.push_back(point.time_from_start.toSec());
    plan.positions.push_back(point.positions);
  }
  const std::string why = posing_.onTrajectory(std::move(plan), now);
  if (!why.empty()) {
    ROS_WARN_THROTTLE(5.0, "proximity_monitor: planned trajectory ignored: %s", why.c_str());
  }
}

void RobotJointBridge::update(Stamp now) {
  // The root frame from tf: everything the joints move rides on it.
  const JointPredictor& predictor = posing_.predictor();
  BodyMotion base;
  std::string why, stale;
  const bool root_ok = tf_bridge_->frameMotion(predictor.model().root(),
                                               Eigen::Isometry3d::Identity(), now, &base, &why,
                                               &stale) &&
                       base.valid();
  const JointPosingLog log = posing_.update(now, root_ok ? &base : nullptr, why, stale);
  // The first of each kind: the warnings are throttled per line, as one per body would be.
  if (log.plan_dropped) {
    ROS_WARN_THROTTLE(5.0, "proximity_monitor: planned trajectory dropped: %s",
                      predictor.planEvent().c_str());
  }
  const RobotBodies& robot = monitor_->robot();
  if (log.unknown >= 0) {
    const int i = posing_.claimed()[static_cast<std::size_t>(log.unknown)];
    ROS_WARN_THROTTLE(5.0, "proximity_monitor: robot body '%s' not posed: %s",
                      robot.spec(i).name.c_str(), predictor.body(log.unknown).why.c_str());
  }
  if (log.refused >= 0) {
    const int i = posing_.claimed()[static_cast<std::size_t>(log.refused)];
    ROS_WARN_THROTTLE(5.0, "proximity_monitor: robot body '%s': %s", robot.spec(i).name.c_str(),
                      robot.why(i).c_str());
  }
}

}  // namespace workspace_proximity
