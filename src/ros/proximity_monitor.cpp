#include "workspace_proximity/ros/proximity_monitor.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <thread>

#include "workspace_proximity/rules/config_fingerprint.hpp"
#include <workspace_proximity/PerceptionStatus.h>

#include "workspace_proximity/ros/conversions.hpp"
#include "workspace_proximity/ros/diagnostics_bridge.hpp"
#include "workspace_proximity/ros/reconfigure_bridge.hpp"
#include "workspace_proximity/ros/robot_description.hpp"

namespace workspace_proximity {
namespace {

// Resolved input topics: ~input_topics, or the single default topic.
std::vector<std::string> inputTopics(const ros::NodeHandle& nh, const MonitorParams& params) {
  std::vector<std::string> topics = params.input_topics;
  if (topics.empty()) topics.push_back("tracked_objects");
  for (std::string& t : topics) t = nh.resolveName(t);
  return topics;
}

}  // namespace

ProximityMonitor::ProximityMonitor(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh,
                                   const MonitorParams& params)
    : nh_(nh),
      params_(params),
      tf_buffer_(MonitorBridges::tfCacheTime(params)),
      tf_listener_(tf_buffer_),
      markers_(params.fixed_frame, params.marker_lifetime),
      trigger_(params.rate),
      diagnostics_(nh_, private_nh) {
  const std::vector<std::string> topics = inputTopics(nh_, params_);
  if (params_.use_robot_description) nh_.getParam(params_.robot_description_param, urdf_);
  fingerprint_ = configFingerprint(params_, urdf_);
  // First: a log that cannot be opened stops the node before it publishes anything.
  if (!params_.audit_log.empty()) {
    audit_log_ = std::make_unique<AuditLog>(params_.audit_log, fingerprint_);
    audit_trail_ = std::make_unique<AuditTrail>(audit_log_.get());
  }
  RobotDescription robot = loadRobotBodies(nh_, params_);
  if (params_.require_all_links && !robot.unmodelled.empty()) {
    // Asked not to run with part of the robot missing: refuse, naming every element.
    for (const std::string& line : robot.unmodelled) ROS_FATAL("proximity_monitor: %s", line.c_str());
    throw std::runtime_error(std::to_string(robot.unmodelled.size()) +
                             " URDF collision elements cannot be modelled and ~require_all_links "
                             "is true: " + robot.unmodelled.front());
  }
  bridges_ = std::make_unique<MonitorBridges>(params_, std::move(robot.bodies), topics,
                                                !params_.input_topics.empty(), &tf_buffer_,
                                                &rejection_log_);
  // A link that cannot be modelled is never dropped silently: DEGRADED (and a diagnostics
  // WARN) with its reason for as long as the node runs.
  for (const std::string& line : robot.unmodelled) {
    ROS_WARN("proximity_monitor: %s; status DEGRADED while the node runs", line.c_str());
    bridges_->addPermanentIssue(line);
  }
  enableJoints();
  contacts_ = std::make_unique<ContactPublisher>(nh_, params_.fixed_frame);
  if (params_.ssm.enabled) {
    ssm_ = std::make_unique<SsmPublisher>(nh_, params_.fixed_frame, params_.ssm);
    ssm_->setFingerprint(fingerprint_);
    ros::NodeHandle latch_nh(private_nh);
    latch_ = std::make_unique<LatchBridge>(nh_, latch_nh, params_.ssm, &bridges_->latch(),
                                           &latch_mutex_);
    if (!params_.ssm.cmd_vel_in.empty()) {
      twist_filter_ = std::make_unique<TwistFilter>(nh_, params_.ssm.cmd_vel_in,
                                                    params_.ssm.cmd_vel_out, params_.rate);
    }
  }
  input_trigger_ = params_.cycle_trigger == "input";
  handoff_ = std::chrono::duration<double>(params_.safety_handoff);
  if (!params_.trigger_source.empty()) {
    const std::string wanted = nh_.resolveName(params_.trigger_source);
    for (std::size_t i = 0; i < topics.size(); ++i) {
      if (topics[i] == wanted) trigger_source_ = static_cast<int>(i);
    }
  }
  // Advertised even when ~publish_markers is false, so live tuning can turn markers on.
  markers_pub_ = nh_.advertise<visualization_msgs::MarkerArray>("markers", 10);
  topics_ = topics;
  inputs_.resize(topics.size());
  for (std::size_t i = 0; i < topics.size(); ++i) {
    // Any type: learnt from the publisher at connection, dispatched per message. Queue of 1:
    // only the newest array of each source is worth predicting from.
    inputs_[i].any = nh_.subscribe<topic_tools::ShapeShifter>(
        topics[i], 1,
        [this, i](const topic_tools::ShapeShifter::ConstPtr& msg) {
          onAnyMessage(static_cast<int>(i), *msg);
        },
        ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
  }
  // Perception front ends' health (issue 23): a degraded or silent one makes the status
  // DEGRADED (Monitor::perception, perception_health.hpp).
  for (std::size_t i = 0; i < params_.perception_status_topics.size(); ++i) {
    subscribers_.push_back(nh_.subscribe<PerceptionStatus>(
        params_.perception_status_topics[i], 2,
        [this, i](const PerceptionStatus::ConstPtr& msg) {
          bridges_->onPerceptionStatus(static_cast<int>(i), toStamp(ros::Time::now()),
                                       msg->degraded, msg->reasons, msg->unseen_share);
        }));
  }
  diagnostics_.setHardwareID("workspace_proximity");
  diagnostics_.add("proximity monitor", [this](diagnostic_updater::DiagnosticStatusWrapper& s) {
    diagnose(*bridges_, toStamp(ros::Time::now()), fingerprint_, &s);
    s.add("audit log", params_.audit_log.empty() ? std::string("off") : params_.audit_log);
    if (audit_log_ != nullptr && audit_log_->failed()) {
      s.add("audit log lines lost", audit_log_->failures());
    }
  });
  // Timer trigger: a cycle every period. Input trigger: arrays run the cycles, and a one-shot
  // timer, re-armed after every cycle, runs one when a period passes without (the floor: silence
  // is still published).
  timer_ = nh_.createTimer(ros::Duration(1.0 / params_.rate),
                           [this](const ros::TimerEvent&) {
                             if (input_trigger_) {
                               onFloorTimer(ros::Time::now());
                             } else {
                               cycle(ros::Time::now());
                             }
                           },
                           input_trigger_, true);
  // Markers are built half a period after the cycle that predicted them, so that their
  // cost (and their megabyte on the wire) never delays the contacts of the next cycle or
  // coincides with this one's delivery. One-shot, re-armed by the cycle when markers are due.
  marker_timer_ = nh_.createTimer(
      ros::Duration(MarkerSchedule::delay(params_.rate)),
      [this](const ros::TimerEvent&) { publishMarkers(); }, true, false);
  reconfigure_ = std::make_unique<dynamic_reconfigure::Server<ProximityMonitorConfig>>(
      reconfigure_mutex_, private_nh);
  // The server starts from the parameter server's flat names; start it from the values in
  // force instead (labels come from ~labels), then listen.
  reconfigure_->updateConfig(toConfig(params_));
  reconfigure_->setCallback(
      [this](ProximityMonitorConfig& config, std::uint32_t level) { reconfigure(config, level); });
  ROS_INFO("proximity_monitor: %d robot bodies, %zu input topics, fixed frame '%s', %.1f Hz "
           "(%s), horizon %.2f s, speed and separation monitoring %s, config fingerprint %s%s%s",
           bridges_->monitor().robot().size(), topics.size(), params_.fixed_frame.c_str(),
           params_.rate,
           input_trigger_ ? ("cycles on arrays of " + topics[trigger_source_]).c_str() : "timer",
           params_.horizon, params_.ssm.enabled ? "on" : "off", fingerprint_.c_str(),
           audit_log_ ? ", audit log " : "", params_.audit_log.c_str());
  audit(audit_kind::kStart,
        "proximity_monitor started: " + std::to_string(bridges_->monitor().robot().size()) +
            " robot bodies, " + std::to_string(topics.size()) + " input topics, speed and "
            "separation monitoring " + (params_.ssm.enabled ? "on" : "off"));
}

void ProximityMonitor::audit(const char* kind, const std::string& reason) {
  if (audit_log_ == nullptr) return;
  audit_log_->write(toStamp(ros::Time::now()), kind, reason);
  checkAudit();
}

void ProximityMonitor::checkAudit() {
  if (audit_issue_ || !audit_log_->failed()) return;
  audit_issue_ = true;
  ROS_ERROR("proximity_monitor: %s; status DEGRADED while the node runs",
            audit_log_->error().c_str());
  if (bridges_ != nullptr) bridges_->addPermanentIssue(audit_log_->error());
}

void ProximityMonitor::onAnyMessage(int i, const topic_tools::ShapeShifter& msg) {
  Input& input = inputs_[static_cast<std::size_t>(i)];
  const ros::Time now = ros::Time::now();
  const std::string& type = msg.getDataType();
  // Only this build's TrackedBoxArray switches to the typed subscription; an older version of
  // it (v1, before the per-box errors) goes through the foreign decoder like any tracker's
  // type, and an md5 the catalogue does not know is refused there by name.
  if (type == ros::message_traits::datatype<TrackedBoxArray>() &&
      msg.getMD5Sum() == ros::message_traits::md5sum<TrackedBoxArray>()) {
    if (input.typed) {
      return;  // the typed subscription has it (both hear the topic until the switch ends)
    } else {
      // This one copied; the typed subscription takes every later one as the publisher sent it.
      bridges_->onArray(i, msg.instantiate<TrackedBoxArray>(), toStamp(now));
      subscribeTyped(i);
    }
  } else {
    ros::serialization::OStream stream(bridges_->foreignBytes(i, msg.size()), msg.size());
    msg.write(stream);
    bridges_->onForeign(i, type, msg.getMD5Sum(), msg.getMessageDefinition(), toStamp(now));
  }
  if (input_trigger_ && i == trigger_source_) onTriggerArray(now);
}

void ProximityMonitor::onArray(int i, const TrackedBoxArray::ConstPtr& msg) {
  const ros::Time now = ros::Time::now();
  if (!msg->header.stamp.isZero() && msg->header.stamp <= now) {
    // The array's stamp to here: its publisher's serialisation, the wire, deserialisation and
    // the callback queue (and how much older than its publication the tracker stamped it).
    bridges_->noteTime(CycleStage::kTransit, (now - msg->header.stamp).toSec() * 1e3);
  }
  bridges_->onArray(i, msg, toStamp(now));
  if (input_trigger_ && i == trigger_source_) onTriggerArray(now);
}

void ProximityMonitor::subscribeTyped(int i) {
  Input& input = inputs_[static_cast<std::size_t>(i)];
  input.typed = nh_.subscribe<TrackedBoxArray>(
      topics_[static_cast<std::size_t>(i)], 1,
      [this, i](const TrackedBoxArray::ConstPtr& msg) { onArray(i, msg); }, ros::VoidConstPtr(),
      ros::TransportHints().tcpNoDelay());
  input.retire_any = true;
  ROS_INFO("proximity_monitor: %s carries %s", topics_[static_cast<std::size_t>(i)].c_str(),
           ros::message_traits::datatype<TrackedBoxArray>());
}

void ProximityMonitor::retireAnySubscribers() {
  for (Input& input : inputs_) {
    if (!input.retire_any) continue;
    input.any.shutdown();
    input.retire_any = false;
  }
}

void ProximityMonitor::enableJoints() {
  std::string urdf;
  if (params_.use_joint_states && params_.use_robot_description) {
    nh_.getParam(params_.robot_description_param, urdf);
  }
  const std::shared_ptr<const KinematicModel> model = MonitorBridges::jointModel(params_, urdf);
  if (!model) return;
  const int bodies = bridges_->enableJoints(model);
  // Queue of a few: every reading counts for the finite differences when velocity is empty.
  subscribers_.push_back(nh_.subscribe<sensor_msgs::JointState>(
      "joint_states", 10,
      [this](const sensor_msgs::JointState::ConstPtr& msg) {
        bridges_->onJointState(*msg, toStamp(ros::Time::now()));
      },
      ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay()));
  if (!params_.trajectory_topic.empty()) {
    subscribers_.push_back(nh_.subscribe<trajectory_msgs::JointTrajectory>(
        params_.trajectory_topic, 5, [this](const trajectory_msgs::JointTrajectory::ConstPtr& msg) {
          bridges_->onTrajectory(*msg, toStamp(ros::Time::now()));
        }));
  }
  ROS_INFO("proximity_monitor: %d robot bodies on %zu joint-driven links posed from joint_states "
           "(%zu joints, root '%s')%s%s",
           bodies, model->links().size(), model->joints().size(), model->root().c_str(),
           params_.trajectory_topic.empty() ? "" : ", planned trajectories on ",
           params_.trajectory_topic.empty() ? "" : nh_.resolveName(params_.trajectory_topic).c_str());
}

ProximityMonitor::~ProximityMonitor() {
  if (audit_log_ != nullptr) {
    audit_log_->write(toStamp(ros::Time::now()), audit_kind::kShutdown, "proximity_monitor stops");
  }
  const std::uint64_t cycles = bridges_ ? bridges_->monitor().status().cycles : 0;
  if (cycles > 0) {
    std::printf("proximity_monitor: %llu cycles; stage times over the last %zu: %s\n",
                static_cast<unsigned long long>(cycles),
                std::min<std::size_t>(cycles, CycleTiming::kWindow),
                bridges_->runner().timing().summary().c_str());
    std::fflush(stdout);
  }
}

void ProximityMonitor::cycle(const ros::Time& now) {
  retireAnySubscribers();  // the any-type subscriptions a typed one replaced
  // Reset, failure and timing are the runner's; the outputs are safety(), contacts(), rest().
  // The latch's requests wait for the cycle (and the cycle for them).
  std::unique_lock<std::mutex> latch_lock(latch_mutex_);
  const CycleRun run = bridges_->run(toStamp(now), this);
  latch_lock.unlock();
  if (!run.failed) diagnostics_.update();
  if (input_trigger_) armFloor();
}

void ProximityMonitor::safety(const CycleReport& report, const ProximityWorld& world,
                              const CycleRun& /*run*/) {
  // First: what a controller acts on never waits for the contacts' message.
  publishSsm(report, world);
}

void ProximityMonitor::handOff() {
  // roscpp writes a published message from its poll thread, not from here, and the reader's
  // own poll and spinner threads then wake in turn. A kernel that queues them on this busy core
  // (the benchmark VM's packs woken tasks onto busy vCPUs) makes them wait behind the contacts'
  // prediction for up to a scheduler slice. A yield lets the first run, not the two after it;
  // leaving the core idle for ~safety_handoff lets all three (1 000 objects, 2 vCPUs: speed_scale
  // p99 1.17-2.04 -> 0.95-1.33 ms, session 28; the yield alone: 1.8 -> 1.3-1.6 ms, session 10).
  if (handoff_.count() > 0.0 && ssm_ != nullptr &&
      (twist_filter_ != nullptr || ssm_->listened())) {
    std::this_thread::sleep_for(handoff_);
  } else {
    std::this_thread::yield();
  }
}

void ProximityMonitor::contacts(const CycleReport& report, const ProximityWorld& world) {
  bridges_->noteTime(CycleStage::kSerialise, contacts_->publish(report, world));
}

void ProximityMonitor::rest(const CycleReport& report, const ProximityWorld& /*world*/,
                            const CycleRun& run) {
  // diagnostic_updater publishes once its next time (set from the old clock) is reached:
  // after a jump back publish now, which also restarts its period from the new clock.
  if (run.reset && !run.failed) diagnostics_.force_update();
  if (audit_trail_ != nullptr) {
    // Transitions only (two flags compared): nothing written on an ordinary cycle.
    audit_trail_->cycle(report);
    checkAudit();
  }
  if (!run.failed) scheduleMarkers(toTime(report.stamp));
}

void ProximityMonitor::publishSsm(const CycleReport& report, const ProximityWorld& world) {
  if (ssm_ == nullptr) return;
  ssm_->publish(report, world);
  if (twist_filter_ != nullptr) twist_filter_->update(report.ssm.speed_scale, toTime(report.stamp));
}

void ProximityMonitor::onTriggerArray(const ros::Time& now) {
  if (trigger_.onArray(toStamp(now))) cycle(now);
}

void ProximityMonitor::onFloorTimer(const ros::Time& now) {
  trigger_.onFloor(toStamp(now));
  cycle(now);
}

void ProximityMonitor::armFloor() {
  timer_.stop();
  timer_.setPeriod(ros::Duration(trigger_.period()));
  timer_.start();
}

void ProximityMonitor::reconfigure(ProximityMonitorConfig& config, std::uint32_t /*level*/) {
  MonitorParams next;
  std::vector<std::string> errors;
  if (!checkConfig(params_, config, &next, &errors)) {
    std::string why;
    for (const std::string& e : errors) {
      ROS_ERROR("proximity_monitor: reconfigure refused: %s", e.c_str());
      why += (why.empty() ? "" : "; ") + e;
    }
    audit(audit_kind::kParamsRefused, why);
    config = toConfig(params_);  // published back: the values in force
    return;
  }
  // What changed, for the audit trail (dynamic_reconfigure also calls with nothing changed).
  const std::string fingerprint = configFingerprint(next, urdf_);
  if (fingerprint != fingerprint_) {
    std::string what;
    if (audit_log_ != nullptr) {
      for (const std::string& c : configChanges(params_, next, urdf_)) {
        what += (what.empty() ? "" : "; ") + c;
      }
    }
    ROS_INFO("proximity_monitor: parameters changed, config fingerprint %s -> %s",
             fingerprint_.c_str(), fingerprint.c_str());
    const std::string old = fingerprint_;
    fingerprint_ = fingerprint;
    if (ssm_ != nullptr) ssm_->setFingerprint(fingerprint_);
    if (audit_log_ != nullptr) {
      audit_log_->setFingerprint(fingerprint_);
      audit(audit_kind::kParams, what + "; fingerprint " + old + " -> " + fingerprint_);
    }
  }
  const bool rate_changed = next.rate != params_.rate;
  params_ = next;
  bridges_->setParams(params_);
  trigger_.setRate(params_.rate);
  markers_.setLifetime(params_.marker_lifetime);
  if (rate_changed) {
    if (!input_trigger_) timer_.setPeriod(ros::Duration(1.0 / params_.rate));  // else: next armFloor
    marker_timer_.setPeriod(ros::Duration(MarkerSchedule::delay(params_.rate)));
    if (twist_filter_ != nullptr) twist_filter_->setRate(params_.rate);
  }
  config = toConfig(params_);
}

void ProximityMonitor::scheduleMarkers(const ros::Time& now) {
  // Nobody watching (no RViz): building thousands of markers would be wasted work.
  if (!params_.publish_markers || markers_pub_.getNumSubscribers() == 0) return;
  if (!marker_schedule_.due(toStamp(now), params_.marker_rate, params_.rate)) return;
  marker_timer_.stop();
  // Re-arms the one-shot.
  marker_timer_.setPeriod(ros::Duration(MarkerSchedule::delay(params_.rate)));
  marker_timer_.start();
}

void ProximityMonitor::publishMarkers() {
  const auto start = std::chrono::steady_clock::now();
  const Monitor& monitor = bridges_->monitor();
  try {
    markers_.build(monitor.report(), monitor.world(), &markers_msg_);
  } catch (const std::exception& e) {
    ROS_ERROR_THROTTLE(1.0, "proximity_monitor: markers failed: %s", e.what());
    return;
  }
  markers_pub_.publish(markers_msg_);
  bridges_->noteTime(CycleStage::kMarkers, std::chrono::duration<double, std::milli>(
                                                std::chrono::steady_clock::now() - start)
                                                .count());
}

}  // namespace workspace_proximity
