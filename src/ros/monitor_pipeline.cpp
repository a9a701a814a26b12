#include "workspace_proximity/ros/monitor_pipeline.hpp"

#include <ros/console.h>

namespace workspace_proximity {

MonitorPipeline::MonitorPipeline(const MonitorParams& params, std::vector<RobotBodySpec> robot,
                                 const std::vector<std::string>& topics, bool qualify,
                                 tf2::BufferCore* tf, RejectionSink* sink)
    : tf_(tf),
      monitor_(params, std::move(robot), topics, qualify, sink),
      input_(&monitor_, tf, params.fixed_frame),
      robot_(&monitor_, tf) {}

int MonitorPipeline::enableJoints(std::shared_ptr<const KinematicModel> model) {
  joints_ = std::make_unique<RobotJointBridge>(&monitor_, &robot_, std::move(model));
  return joints_->bodyCount();
}

const CycleReport& MonitorPipeline::cycle(Stamp now, StageClock* clock, bool* reset) {
  *reset = monitor_.clockWentBack(now);
  if (*reset) {
    // A clock that jumps back (bag loop, simulation reset) invalidates every stamp we hold:
    // drop the tracks (their pairs END), the robot's poses, waiting arrays and the tf history.
    ROS_WARN("proximity_monitor: clock jumped back by %.3f s; resetting tracks, robot poses and "
             "the tf buffer",
             secondsBetween(now, monitor_.lastCycle()));
    monitor_.reset();
    input_.reset();
    tf_->clear();
    if (joints_) joints_->reset();
  }
  input_.takePending(now);
  robot_.update(now);
  if (joints_) joints_->update(now, monitor_.params().horizon);
  return monitor_.cycle(now, clock);
}

}  // namespace workspace_proximity
