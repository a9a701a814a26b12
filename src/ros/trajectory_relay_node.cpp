// trajectory_relay: pause and resume for a controller without speed scaling (ROS 1's
// joint_trajectory_controller). The planned trajectory in, the monitor's speed_scale in, and the
// remainder of the plan re-timed by the scale out to the controller's command topic, in short
// replacement chunks (TrajectoryRetimer, rules layer). A silent speed_scale counts as 0 (hold);
// a dead relay leaves the controller at most one chunk of motion.

#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include <ros/ros.h>
#include <std_msgs/Float64.h>
#include <trajectory_msgs/JointTrajectory.h>

#include "workspace_proximity/ros/node_main.hpp"
#include "workspace_proximity/rules/trajectory_retimer.hpp"

namespace {

using workspace_proximity::ChunkKind;
using workspace_proximity::PlanRejection;
using workspace_proximity::RetimedChunk;
using workspace_proximity::TrajectoryRetimer;
using workspace_proximity::TrajectoryRetimerCapacity;

struct RelayParams {
  std::string trajectory_topic = "planned_trajectory";
  std::string speed_scale_topic = "speed_scale";
  std::string command_topic = "/arm_controller/command";
  double rate = 20.0;           // Hz
  double chunk = 0.3;           // s
  double scale_timeout = 0.1;   // s: 3 periods of the monitor at its default 30 Hz
  int max_points = 10000;
  int max_joints = 32;
};

// Reads and checks the parameters; an empty string when they are fine, else the first error,
// naming the parameter.
// One parameter, kept at its default when absent; false when it is set but of another type.
template <typename T>
bool readOne(const ros::NodeHandle& pnh, const std::string& name, T& value) {
  if (!pnh.hasParam(name)) return true;
  return pnh.getParam(name, value);
}

// Numbers written without a decimal point arrive as ints: read either.
bool readNumber(const ros::NodeHandle& pnh, const std::string& name, double& value) {
  if (!pnh.hasParam(name)) return true;
  if (pnh.getParam(name, value)) return true;
  int i = 0;
  if (!pnh.getParam(name, i)) return false;
  value = i;
  return true;
}

std::string readParams(const ros::NodeHandle& pnh, RelayParams& p) {
  for (auto [name, value] : {std::make_pair("trajectory_topic", &p.trajectory_topic),
                             std::make_pair("speed_scale_topic", &p.speed_scale_topic),
                             std::make_pair("command_topic", &p.command_topic)}) {
    if (!readOne(pnh, name, *value)) return std::string("~") + name + " must be a string";
  }
  for (auto [name, value] : {std::make_pair("rate", &p.rate), std::make_pair("chunk", &p.chunk),
                             std::make_pair("scale_timeout", &p.scale_timeout)}) {
    if (!readNumber(pnh, name, *value)) return std::string("~") + name + " must be a number";
  }
  for (auto [name, value] : {std::make_pair("max_points", &p.max_points),
                             std::make_pair("max_joints", &p.max_joints)}) {
    if (!readOne(pnh, name, *value)) return std::string("~") + name + " must be an integer";
  }
  if (p.trajectory_topic.empty()) return "~trajectory_topic must name the planned trajectory's topic";
  if (p.speed_scale_topic.empty()) return "~speed_scale_topic must not be empty";
  if (p.command_topic.empty()) return "~command_topic must name the controller's command topic";
  for (auto [name, value] : {std::make_pair("trajectory_topic", &p.trajectory_topic),
                             std::make_pair("speed_scale_topic", &p.speed_scale_topic),
                             std::make_pair("command_topic", &p.command_topic)}) {
    std::string why;
    if (!ros::names::validate(*value, why)) {
      return std::string("~") + name + " is not a valid topic name: " + why;
    }
  }
  if (p.command_topic == p.trajectory_topic ||
      ros::names::resolve(p.command_topic) == ros::names::resolve(p.trajectory_topic)) {
    return "~command_topic and ~trajectory_topic must differ (the relay would read its own chunks)";
  }
  if (!(p.rate >= 1.0 && p.rate <= 1000.0)) return "~rate must be in [1, 1000] Hz";
  if (!(p.chunk > 1.0 / p.rate && p.chunk <= 10.0)) {
    return "~chunk must be longer than one period (1 / ~rate) and at most 10 s";
  }
  if (!(p.scale_timeout > 0.0 && p.scale_timeout <= 10.0)) return "~scale_timeout must be in (0, 10] s";
  if (p.max_points < 2 || p.max_points > 1000000) return "~max_points must be in [2, 1000000]";
  if (p.max_joints < 1 || p.max_joints > 1000) return "~max_joints must be in [1, 1000]";
  // The plan's storage is set up at start (several arrays of max_points x max_joints doubles).
  if (static_cast<long long>(p.max_points) * p.max_joints > 1000000LL) {
    return "~max_points x ~max_joints must be at most 1000000";
  }
  return "";
}

class TrajectoryRelay {
 public:
  TrajectoryRelay(ros::NodeHandle& nh, const RelayParams& p)
      : params_(p),
        retimer_(TrajectoryRetimerCapacity{p.max_joints, p.max_points}, p.chunk, 1.0 / p.rate) {
    command_pub_ = nh.advertise<trajectory_msgs::JointTrajectory>(p.command_topic, 2);
    plan_sub_ = nh.subscribe(p.trajectory_topic, 2, &TrajectoryRelay::onPlan, this);
    scale_sub_ = nh.subscribe(p.speed_scale_topic, 1, &TrajectoryRelay::onScale, this,
                              ros::TransportHints().tcpNoDelay());
    timer_ = nh.createTimer(ros::Duration(1.0 / p.rate), &TrajectoryRelay::onTick, this);
    ROS_INFO("trajectory_relay: %s re-timed by %s -> %s, %.0f Hz, chunks of %.3g s",
             plan_sub_.getTopic().c_str(), scale_sub_.getTopic().c_str(),
             command_pub_.getTopic().c_str(), p.rate, p.chunk);
  }

 private:
  void onScale(const std_msgs::Float64ConstPtr& msg) {
    scale_ = msg->data;
    scale_received_ = ros::Time::now();
  }

  void onPlan(const trajectory_msgs::JointTrajectoryConstPtr& msg) {
    // Stamp 0: start now; a later stamp: the plan waits for it (as a controller's would).
    pending_ = msg;
    pending_start_ = msg->header.stamp.isZero() ? ros::Time::now() : msg->header.stamp;
  }

  // The pending plan into the retimer; a bad one is refused by name and the one in force stays.
  void loadPending() {
    const trajectory_msgs::JointTrajectory& m = *pending_;
    if (m.points.empty()) {
      // As joint_trajectory_controller reads it: an empty trajectory cancels; the controller
      // gets one too and holds where it is.
      retimer_.clear();
      trajectory_msgs::JointTrajectory stop;
      stop.header.stamp = ros::Time::now();
      stop.joint_names = m.joint_names;
      command_pub_.publish(stop);
      ROS_INFO("trajectory_relay: plan cancelled (an empty trajectory)");
      pending_.reset();
      return;
    }
    const int joints = static_cast<int>(m.joint_names.size());
    const int points = static_cast<int>(m.points.size());
    bool vel = points > 0 && !m.points[0].velocities.empty();
    bool acc = points > 0 && !m.points[0].accelerations.empty();
    PlanRejection rej = PlanRejection::kNone;
    for (const auto& pt : m.points) {
      if (pt.velocities.empty() == vel || pt.accelerations.empty() == acc) {
        rej = PlanRejection::kMixedDerivatives;
      } else if (static_cast<int>(pt.positions.size()) != joints ||
                 (vel && static_cast<int>(pt.velocities.size()) != joints) ||
                 (acc && static_cast<int>(pt.accelerations.size()) != joints)) {
        rej = PlanRejection::kSizeMismatch;
      }
    }
    if (rej == PlanRejection::kNone) rej = retimer_.beginPlan(joints, points, vel, acc);
    if (rej == PlanRejection::kNone) {
      for (int i = 0; i < points; ++i) {
        const auto& pt = m.points[i];
        retimer_.setPoint(i, pt.time_from_start.toSec(), pt.positions.data(),
                          vel ? pt.velocities.data() : nullptr,
                          acc ? pt.accelerations.data() : nullptr);
      }
      rej = retimer_.finishPlan();
    }
    if (rej != PlanRejection::kNone) {
      ROS_WARN("trajectory_relay: planned trajectory refused: %s%s",
               workspace_proximity::planRejectionName(rej),
               retimer_.hasPlan() ? " (the previous plan goes on)" : "");
    } else {
      joint_names_ = m.joint_names;
      last_tick_ = ros::Time();  // the first tick of a plan advances nothing
      announced_end_ = false;
      ROS_INFO("trajectory_relay: new plan, %d joints, %d points, %.3f s", joints, points,
               retimer_.duration());
    }
    pending_.reset();
  }

  double currentScale(const ros::Time& now) const {
    // Never received, silent for longer than ~scale_timeout, or not a number: 0 (hold).
    if (scale_received_.isZero() || (now - scale_received_).toSec() > params_.scale_timeout ||
        !std::isfinite(scale_)) {
      return 0.0;
    }
    return scale_;
  }

  void onTick(const ros::TimerEvent&) {
    const ros::Time now = ros::Time::now();
    if (pending_ && now >= pending_start_) loadPending();
    if (!retimer_.hasPlan()) return;
    double dt = last_tick_.isZero() ? 0.0 : (now - last_tick_).toSec();
    if (dt < 0.0) dt = 0.0;  // the clock went back: count nothing
    last_tick_ = now;
    const double scale = currentScale(now);
    const RetimedChunk& c = retimer_.tick(dt, scale);
    const bool holding = c.kind == ChunkKind::kHold;
    if (holding != holding_) {
      ROS_INFO("trajectory_relay: %s at planned time %.3f s of %.3f s",
               holding ? "paused (speed scale 0 or silent)" : "resumed", retimer_.progress(),
               retimer_.duration());
      holding_ = holding;
    }
    if (c.kind == ChunkKind::kNothing) {
      if (!announced_end_ && retimer_.finished()) {
        ROS_INFO("trajectory_relay: plan done");
        announced_end_ = true;
      }
      return;
    }
    publish(c, now);
  }

  void publish(const RetimedChunk& c, const ros::Time& now) {
    msg_.header.stamp = now;
    msg_.joint_names = joint_names_;
    msg_.points.resize(c.count);
    for (int i = 0; i < c.count; ++i) {
      trajectory_msgs::JointTrajectoryPoint& pt = msg_.points[i];
      const double* q = &c.positions[static_cast<std::size_t>(i) * c.joints];
      const double* v = &c.velocities[static_cast<std::size_t>(i) * c.joints];
      const double* a = &c.accelerations[static_cast<std::size_t>(i) * c.joints];
      pt.positions.assign(q, q + c.joints);
      if (c.has_velocities) pt.velocities.assign(v, v + c.joints); else pt.velocities.clear();
      if (c.has_accelerations) pt.accelerations.assign(a, a + c.joints); else pt.accelerations.clear();
      pt.time_from_start = ros::Duration(c.times[i]);
    }
    command_pub_.publish(msg_);
  }

  RelayParams params_;
  TrajectoryRetimer retimer_;
  ros::Publisher command_pub_;
  ros::Subscriber plan_sub_, scale_sub_;
  ros::Timer timer_;
  trajectory_msgs::JointTrajectoryConstPtr pending_;
  ros::Time pending_start_;
  std::vector<std::string> joint_names_;
  double scale_ = 0.0;
  ros::Time scale_received_;
  ros::Time last_tick_;
  bool holding_ = false;
  bool announced_end_ = false;
  trajectory_msgs::JointTrajectory msg_;  // reused: its vectors keep their capacity
};

}  // namespace

int main(int argc, char** argv) {
  // Line by line: the pause and resume lines reach a piped launch output (scripts/demo) when
  // they happen, not when a buffer fills.
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  ros::init(argc, argv, "trajectory_relay");
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  RelayParams params;
  const std::string error = readParams(pnh, params);
  if (!error.empty()) {
    ROS_FATAL("trajectory_relay: invalid parameter %s", error.c_str());
    return 1;
  }
  return workspace_proximity::runNode("trajectory_relay", [&] {
    TrajectoryRelay relay(nh, params);
    ros::spin();
  });
}
