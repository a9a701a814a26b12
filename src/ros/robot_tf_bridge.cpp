#include "workspace_proximity/ros/robot_tf_bridge.hpp"

#include <ros/console.h>
#include <tf2/exceptions.h>
#include <tf2_eigen/tf2_eigen.h>

#include "workspace_proximity/rules/format.hpp"
#include "workspace_proximity/ros/conversions.hpp"

namespace workspace_proximity {

RobotTfBridge::RobotTfBridge(Monitor* monitor, tf2::BufferCore* tf)
    : monitor_(monitor), tf_(tf), params_(monitor->params()) {}

void RobotTfBridge::update(Stamp now) {
  const RobotBodies& robot = monitor_->robot();
  for (int i = 0; i < robot.size(); ++i) {
    if (static_cast<std::size_t>(i) < claimed_.size() && claimed_[static_cast<std::size_t>(i)] != 0) continue;
    const RobotBodySpec& spec = robot.spec(i);
    BodyMotion motion;
    std::string why, stale;
    if (!motionOf(i, now, &motion, &why, &stale) || !motion.valid()) {
      ++tf_failures_;
      monitor_->markRobotUnknown(i, why);
      ROS_WARN_THROTTLE(5.0, "proximity_monitor: robot body '%s' (frame '%s') not posed: %s",
                        spec.name.c_str(), spec.frame.c_str(), robot.why(i).c_str());
      continue;
    }
    // "Posed again" after an outage, not after the start-up wait for a velocity.
    const bool was_stale = robot.present(i) && robot.stale(i) &&
                           robot.why(i).rfind("velocity not known", 0) != 0;
    if (!monitor_->poseRobot(i, motion, stale)) {
      ROS_WARN_THROTTLE(5.0, "proximity_monitor: robot body '%s': %s", spec.name.c_str(),
                        robot.why(i).c_str());
    } else if (was_stale && stale.empty()) {
      ROS_INFO("proximity_monitor: robot body '%s' is posed again", spec.name.c_str());
    }
  }
}

void RobotTfBridge::setClaimed(int i, bool claimed) {
  claimed_.resize(static_cast<std::size_t>(monitor_->robot().size()), 0);
  claimed_[static_cast<std::size_t>(i)] = claimed ? 1 : 0;
}

bool RobotTfBridge::motionOf(int i, Stamp now, BodyMotion* motion, std::string* why,
                             std::string* stale) {
  const RobotBodySpec& spec = monitor_->robot().spec(i);
  return frameMotion(spec.frame, spec.offset, now, motion, why, stale);
}

bool RobotTfBridge::frameMotion(const std::string& frame, const Eigen::Isometry3d& offset,
                                Stamp now, BodyMotion* motion, std::string* why,
                                std::string* stale) {
  if (frame == params_.fixed_frame) {
    // The fixed frame itself: standing still by definition.
    *motion = BodyMotion();
    motion->position = offset.translation();
    motion->orientation = Eigen::Quaterniond(offset.linear()).normalized();
    return true;
  }
  geometry_msgs::TransformStamped latest;
  try {
    latest = tf_->lookupTransform(params_.fixed_frame, frame, ros::Time(0));
  } catch (const tf2::TransformException& e) {
    *why = e.what();
    return false;
  }
  const Eigen::Isometry3d pose1 = tf2::transformToEigen(latest) * offset;
  motion->position = pose1.translation();
  motion->orientation = Eigen::Quaterniond(pose1.linear()).normalized();
  motion->linear_velocity.setZero();
  motion->angular_velocity.setZero();
  const Stamp t1 = toStamp(latest.header.stamp);
  if (t1 == 0) return true;  // a static chain: no motion, never stale

  const double age = secondsBetween(t1, now);
  if (-age > params_.max_future) {
    // Stamped ahead of the clock: left over from before the clock jumped back (a publisher
    // that saw the jump after our reset). tf2 refuses data older than its newest entry by
    // more than the cache time, so the fresh transforms would never be used: drop it all.
    tf_->clear();
    *why = format("latest transform is stamped %.3f s ahead of the clock; tf history cleared", -age);
    return false;
  }
  if (age > params_.tf_timeout) {
    *why = format("latest transform is %.3f s old", age);
    return false;
  }
  // Velocity by finite difference over the last velocity_window seconds of tf history.
  const Stamp t0 = t1 - nanoseconds(params_.velocity_window);
  try {
    const Eigen::Isometry3d pose0 =
        tf2::transformToEigen(tf_->lookupTransform(params_.fixed_frame, frame, toTime(t0))) *
        offset;
    const double dt = secondsBetween(t0, t1);
    motion->linear_velocity = (pose1.translation() - pose0.translation()) / dt;
    const Eigen::AngleAxisd turn(pose1.linear() * pose0.linear().transpose());
    motion->angular_velocity = turn.axis() * (turn.angle() / dt);
  } catch (const tf2::TransformException&) {
    // Not enough history yet (at start-up, after a reset): the link may be moving, so it must
    // not read as standing still. Posed where tf last saw it, stale until the window fills.
    *stale = format("velocity not known yet (less than ~velocity_window = %.3f s of tf history)",
                    params_.velocity_window);
  }
  *motion = motion->advanced(age);
  return true;
}

}  // namespace workspace_proximity
