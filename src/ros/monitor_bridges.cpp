#include "workspace_proximity/ros/monitor_bridges.hpp"

#include <algorithm>
#include <chrono>
#include <exception>

#include <ros/console.h>

#include "workspace_proximity/ros/kdl_robot_model.hpp"

namespace workspace_proximity {

ros::Duration MonitorBridges::tfCacheTime(const MonitorParams& params) {
  // The robot's velocity needs ~velocity_window of history behind the newest transform, and
  // arrays are looked up at their stamps: keep a good margin beyond both.
  return ros::Duration(std::max(10.0, 4.0 * params.velocity_window));
}

std::shared_ptr<const KinematicModel> MonitorBridges::jointModel(const MonitorParams& params,
                                                                  const std::string& urdf_xml) {
  if (!params.use_joint_states || !params.use_robot_description || urdf_xml.empty()) return nullptr;
  std::shared_ptr<KdlRobotModel> model;
  try {
    model = std::make_shared<KdlRobotModel>(urdf_xml);
  } catch (const std::exception& e) {
    // The collision bodies parsed, so this is KDL refusing the tree: the links keep tf.
    ROS_ERROR("proximity_monitor: no forward kinematics (%s); every robot link from tf", e.what());
    return nullptr;
  }
  if (model->links().empty()) return nullptr;  // nothing moves: tf gives every link
  return model;
}

MonitorBridges::MonitorBridges(const MonitorParams& params, std::vector<RobotBodySpec> robot,
                                 const std::vector<std::string>& topics, bool qualify,
                                 tf2::BufferCore* tf, RejectionSink* sink)
    : tf_(tf),
      monitor_(params, std::move(robot), topics, qualify, sink),
      runner_(&monitor_),
      input_(&monitor_, tf, params.fixed_frame),
      robot_(&monitor_, tf) {}

void MonitorBridges::onArray(int source, const TrackedBoxArray::ConstPtr& msg, Stamp now) {
  const auto start = std::chrono::steady_clock::now();
  if (input_.onArray(source, msg, now)) {
    // Used (or dropped) on arrival: work done ahead of the cycle.
    runner_.noteTime(CycleStage::kArrival, std::chrono::duration<double, std::milli>(
                                               std::chrono::steady_clock::now() - start)
                                               .count());
  }
}

void MonitorBridges::onForeign(int source, std::string_view type, std::string_view md5,
                               std::string_view definition, Stamp now) {
  const auto start = std::chrono::steady_clock::now();
  if (input_.onForeign(source, type, md5, definition, now)) {
    runner_.noteTime(CycleStage::kArrival, std::chrono::duration<double, std::milli>(
                                               std::chrono::steady_clock::now() - start)
                                               .count());
  }
}

int MonitorBridges::enableJoints(std::shared_ptr<const KinematicModel> model) {
  joints_ = std::make_unique<RobotJointBridge>(&monitor_, &robot_, std::move(model));
  return joints_->bodyCount();
}

void MonitorBridges::reset(Stamp now) {
  // A clock that jumps back (bag loop, simulation reset) invalidates every stamp we hold:
  // the monitor drops its tracks (their pairs END) and robot poses; here the waiting arrays,
  // the tf history and the joint readings go.
  ROS_WARN("proximity_monitor: clock jumped back by %.3f s; resetting tracks, robot poses and "
           "the tf buffer",
           secondsBetween(now, monitor_.status().last_cycle));
  input_.reset();
  tf_->clear();
  if (joints_) joints_->reset();
}

void MonitorBridges::update(Stamp now) {
  input_.takePending(now);
  robot_.update(now);
  if (joints_) joints_->update(now);
}

void MonitorBridges::failed(const std::string& what) {
  ROS_ERROR_THROTTLE(1.0, "proximity_monitor: cycle failed: %s", what.c_str());
}

}  // namespace workspace_proximity
