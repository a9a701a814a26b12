#pragma once
/// The proximity_monitor node: wires the monitor and its bridges (MonitorBridges) to ROS.
/// Subscriptions feed its input bridge, tf2_ros its robot bridge, a timer (or, with ~cycle_trigger:
/// input, the arrival of an array) runs the cycle, and the cycle's report goes to the contact
/// publisher, the speed and separation outputs, the marker builder and the diagnostics:
///   arrays -> InputBridge -> Monitor (TrackTable) ; tf -> RobotTfBridge -> Monitor (RobotBodies)
///   timer | array (CycleTrigger) -> MonitorBridges::run (CycleRunner) -> CycleReport
///     -> speed_scale + safety_status + speed_override (+ stops, Twist filter) first,
///     -> then contacts, markers (MarkerSchedule), /diagnostics
/// The rules below the wiring are ROS-free: CycleRunner (reset, failure, timing), CycleTrigger
/// (~cycle_trigger: input), MarkerSchedule (~marker_rate).

#include <chrono>
#include <memory>
#include <mutex>
#include <vector>

#include <diagnostic_updater/diagnostic_updater.h>
#include <boost/thread/recursive_mutex.hpp>
#include <dynamic_reconfigure/server.h>
#include <ros/ros.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>
#include <topic_tools/shape_shifter.h>
#include <visualization_msgs/MarkerArray.h>

#include "workspace_proximity/rules/audit_log.hpp"
#include "workspace_proximity/rules/audit_trail.hpp"
#include "workspace_proximity/rules/cycle_runner.hpp"
#include "workspace_proximity/rules/cycle_trigger.hpp"
#include "workspace_proximity/rules/marker_schedule.hpp"
#include "workspace_proximity/ros/contact_publisher.hpp"
#include "workspace_proximity/ros/latch_bridge.hpp"
#include "workspace_proximity/ros/marker_builder.hpp"
#include "workspace_proximity/ros/monitor_bridges.hpp"
#include "workspace_proximity/ros/rejection_log.hpp"
#include "workspace_proximity/ros/ssm_publisher.hpp"
#include "workspace_proximity/ros/twist_filter.hpp"
#include <workspace_proximity/ProximityMonitorConfig.h>

namespace workspace_proximity {

class ProximityMonitor : private CycleOutput {
 public:
  /// Builds the monitor, robot bodies, subscriptions, publishers and the cycle timer.
  /// `params` must have passed validate(). Throws std::runtime_error on a URDF that does
  /// not parse, AuditLogError on an ~audit_log that cannot be opened.
  ProximityMonitor(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh,
                   const MonitorParams& params);

  /// Logs the stage timing summary of the last cycles (and "shutdown" in the audit log).
  ~ProximityMonitor();

  /// One prediction cycle at `now` (the timer calls this). Never throws.
  void cycle(const ros::Time& now);

 private:
  // Robot links moved by URDF joints from joint_states (~use_joint_states with a URDF).
  void enableJoints();
  // Input topic i: any type (topic_tools::ShapeShifter), dispatched on its type name and md5.
  // A TrackedBoxArray switches the topic to a typed subscription, so a nodelet publisher in
  // the same manager hands its arrays over without serialisation as before; foreign types
  // are decoded from their bytes (InputBridge::onForeign).
  void onAnyMessage(int i, const topic_tools::ShapeShifter& msg);
  void subscribeTyped(int i);
  void onArray(int i, const TrackedBoxArray::ConstPtr& msg);
  // Ends the any-type subscriptions that a typed one replaced (outside their own callbacks).
  void retireAnySubscribers();
  // CycleOutput: the speed and separation outputs first (speed_scale, safety_status,
  // speed_override, stop actions, the Twist filter); then the contacts; then, unless the cycle
  // failed, the markers' schedule. /diagnostics comes after the cycle (cycle()).
  void safety(const CycleReport& report, const ProximityWorld& world, const CycleRun& run) override;
  void handOff() override;
  void contacts(const CycleReport& report, const ProximityWorld& world) override;
  void rest(const CycleReport& report, const ProximityWorld& world, const CycleRun& run) override;
  void publishSsm(const CycleReport& report, const ProximityWorld& world);
  // ~cycle_trigger: input. An array of the trigger source arrived: a cycle now, unless
  // CycleTrigger's bucket is empty (then the floor timer takes it, within a period).
  void onTriggerArray(const ros::Time& now);
  // The floor timer (input trigger): a cycle a period after the last one (CycleTrigger::onFloor).
  void onFloorTimer(const ros::Time& now);
  void armFloor();  // the one-shot floor timer: a cycle one period after the last
  void scheduleMarkers(const ros::Time& now);  // arms marker_timer_ when markers are due
  void publishMarkers();                        // marker_timer_: half a period after a cycle
  // dynamic_reconfigure: a checked change applies from the next cycle; an invalid one is
  // refused (the config is set back to the values in force) with the reasons logged.
  void reconfigure(ProximityMonitorConfig& config, std::uint32_t level);
  // ~audit_log: a line now (nothing without a log), and a lost line made a lasting DEGRADED
  // reason (the trail has a gap: unknown is never clear).
  void audit(const char* kind, const std::string& reason);
  void checkAudit();

  ros::NodeHandle nh_;
  MonitorParams params_;
  std::string urdf_;         // the URDF text the robot bodies came from ("" = none)
  std::string fingerprint_;  // of params_ and urdf_ (config_fingerprint.hpp)
  std::unique_ptr<AuditLog> audit_log_;      // null without ~audit_log
  std::unique_ptr<AuditTrail> audit_trail_;  // the cycles' transitions into audit_log_
  bool audit_issue_ = false;                 // a lost line is already a DEGRADED reason
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  RejectionLog rejection_log_;
  std::unique_ptr<MonitorBridges> bridges_;
  std::unique_ptr<ContactPublisher> contacts_;
  std::unique_ptr<SsmPublisher> ssm_;        // null with ~ssm/enabled: false
  std::unique_ptr<TwistFilter> twist_filter_;  // null without ~ssm/cmd_vel_in
  std::mutex latch_mutex_;                     // the cycle and the latch's requests
  std::unique_ptr<LatchBridge> latch_;         // ~reset, ~mute; null with ~ssm/enabled: false
  MarkerBuilder markers_;
  visualization_msgs::MarkerArray markers_msg_;  // reused
  ros::Publisher markers_pub_;
  std::vector<ros::Subscriber> subscribers_;
  struct Input {
    ros::Subscriber any;    // ShapeShifter: until a TrackedBoxArray makes it typed
    ros::Subscriber typed;  // TrackedBoxArray
    bool retire_any = false;
  };
  std::vector<Input> inputs_;  // one per input topic
  std::vector<std::string> topics_;
  ros::Timer timer_;       // timer trigger: every period; input trigger: one-shot floor
  bool input_trigger_ = false;
  std::chrono::duration<double> handoff_{0.0};  // ~safety_handoff (start-up only)
  int trigger_source_ = 0;  // index of the trigger topic
  CycleTrigger trigger_;    // the input trigger's token bucket and floor
  ros::Timer marker_timer_;
  MarkerSchedule marker_schedule_;
  diagnostic_updater::Updater diagnostics_;
  boost::recursive_mutex reconfigure_mutex_;  // the server's (updateConfig is called on it)
  std::unique_ptr<dynamic_reconfigure::Server<ProximityMonitorConfig>> reconfigure_;
};

}  // namespace workspace_proximity
