#include "workspace_proximity/rules/param_table.hpp"

#include <stdexcept>

namespace workspace_proximity {
namespace {

constexpr Tuning kLive = Tuning::kLive;
constexpr Tuning kStartup = Tuning::kStartup;
constexpr Tuning kWiring = Tuning::kWiring;

// The ranges are dynamic_reconfigure's sliders and stay inside the core's Limits. Rows that
// are no number have no range (0, 0).
#define WP_M(path) WP_PARAM_MEMBER(path)
constexpr ParamRow kParams[] = {
    // name, member, tuning, min, max, at_most, unit, note, doc
    {"fixed_frame", WP_M(fixed_frame), kWiring, 0, 0, nullptr, "", "",
     "frame of the prediction, the events and the markers"},
    {"rate", WP_M(rate), kLive, 0.1, 1000.0, nullptr, "Hz", "", "prediction cycles"},
    {"horizon", WP_M(horizon), kLive, 0.0, 60.0, nullptr, "s", "",
     "how far ahead contacts are predicted"},
    {"track_timeout", WP_M(track_timeout), kLive, 0.001, 3600.0, nullptr, "s", "",
     "tracks whose stamp is older than this are dropped (END for their pairs)"},
    {"stale_after", WP_M(stale_after), kLive, 0.0, 3600.0, "track_timeout", "s",
     "(at most ~track_timeout)", "pairs involving a track older than this are marked stale"},
    {"source_timeout", WP_M(source_timeout), kLive, 0.001, 3600.0, nullptr, "s", "",
     "without an array from an input topic this long: status DEGRADED"},
    {"max_future", WP_M(max_future), kStartup, 0.0, 60.0, nullptr, "s", "",
     "arrays stamped further ahead of the node's clock are dropped"},
    {"max_tracks", WP_M(max_tracks), kStartup, 1, 1000000, nullptr, "tracks", "",
     "tracked objects kept at most; beyond it the ones nearest the robot win"},
    {"broad_phase_lead", WP_M(broad_phase_lead), kStartup, 0.0, 64.0, nullptr, "updates", "",
     "the broad phase's bounds lead each box by this many cycles of its own motion; 0: off"},
    {"pair_threads", WP_M(pair_threads), kStartup, 1, 16, nullptr, "threads", "",
     "threads for the per-pair stages (contact window, narrow phase) from 2 048 pairs on"},
    {"safety_handoff", WP_M(safety_handoff), kStartup, 0.0, 0.01, nullptr, "s", "",
     "the cycle leaves its core this long after the safety outputs, before the contacts"},
    {"input_topics", WP_M(input_topics), kWiring, 0, 0, nullptr, "", "",
     "TrackedBoxArray topics; empty: the single topic tracked_objects"},
    {"perception_status_topics", WP_M(perception_status_topics), kWiring, 0, 0, nullptr, "", "",
     "PerceptionStatus topics of perception front ends; a degraded or silent one: DEGRADED"},
    {"skeleton_marker_topics", WP_M(skeleton_marker_topics), kWiring, 0, 0, nullptr, "", "",
     "input topics whose MarkerArrays are Azure Kinect body-tracking skeletons (K4ABT joints)"},
    {"cycle_trigger", WP_M(cycle_trigger), kWiring, 0, 0, nullptr, "", "",
     "when a cycle runs: 'timer' (every 1 / rate s) or 'input' (on an array of trigger_source)"},
    {"trigger_source", WP_M(trigger_source), kWiring, 0, 0, nullptr, "", "",
     "the input topic whose arrays trigger a cycle; empty: the first"},
    {"use_robot_description", WP_M(use_robot_description), kWiring, 0, 0, nullptr, "", "",
     "take robot bodies from the URDF"},
    {"robot_description_param", WP_M(robot_description_param), kWiring, 0, 0, nullptr, "", "",
     "the parameter holding the URDF"},
    {"robot_bodies", WP_M(robot_bodies), kWiring, 0, 0, nullptr, "", "",
     "extra robot boxes: name, frame, size, optional offset"},
    {"require_all_links", WP_M(require_all_links), kWiring, 0, 0, nullptr, "", "",
     "refuse to start when a URDF collision element cannot be modelled"},
    {"robot_margin", WP_M(robot_margin), kLive, 0.0, 10.0, nullptr, "m", "",
     "added around every robot body"},
    {"velocity_window", WP_M(velocity_window), kStartup, 0.005, 2.0, nullptr, "s", "",
     "tf history for robot link velocities"},
    {"tf_timeout", WP_M(tf_timeout), kStartup, 0.001, 3600.0, nullptr, "s", "",
     "a robot link whose newest transform (or joint state) is older is not used"},
    {"use_joint_states", WP_M(use_joint_states), kWiring, 0, 0, nullptr, "", "",
     "pose links moved by URDF joints from joint_states; false: every link from tf"},
    {"trajectory_topic", WP_M(trajectory_topic), kWiring, 0, 0, nullptr, "", "",
     "JointTrajectory topic of the robot's planned motion; empty: none"},
    {"trajectory_tolerance", WP_M(trajectory_tolerance), kStartup, 0.0, 100.0, nullptr,
     "rad or m", "", "a planned trajectory the joint states contradict by more is dropped"},
    {"joint_path_tolerance", WP_M(joint_path_tolerance), kStartup, 0.0001, 1.0, nullptr, "m", "",
     "joint-space keyframes keep each straight segment this close to the links' true arcs"},
    {"ignore_pairs", WP_M(ignore_pairs), kStartup, 0, 0, nullptr, "", "",
     "pairs of selectors not to check"},
    {"check_pairs", WP_M(check_pairs), kStartup, 0, 0, nullptr, "", "",
     "pairs of selectors to check even if ignored before"},
    {"labels", WP_M(labels), kLive, 0, 0, nullptr, "", "",
     "settings per label (labelTable()); default: for labels not listed"},
    {"robot_thresholds", WP_M(robot_thresholds), kLive, 0, 0, nullptr, "", "",
     "level thresholds of robot bodies (labelTable() without the track-only settings)"},
    {"publish_markers", WP_M(publish_markers), kLive, 0, 0, nullptr, "", "",
     "publish markers (while someone subscribes)"},
    {"marker_lifetime", WP_M(marker_lifetime), kLive, 0.01, 3600.0, nullptr, "s", "",
     "markers vanish this long after the last refresh"},
    {"marker_rate", WP_M(marker_rate), kLive, 0.1, 1000.0, nullptr, "Hz", "",
     "markers are published at most this often"},
    {"audit_log", WP_M(audit_log), kWiring, 0, 0, nullptr, "", "",
     "CSV file of the audit trail (stops, DEGRADED, parameter changes), appended; empty: none"},
    // ~ssm/: speed and separation monitoring (ssm_rule.hpp).
    {"ssm/enabled", WP_M(ssm.enabled), kWiring, 0, 0, nullptr, "", "",
     "compute and publish the speed scale"},
    {"ssm/labels", WP_M(ssm.labels), kStartup, 0, 0, nullptr, "", "",
     "object labels monitored; empty: every object label"},
    {"ssm/reaction_time", WP_M(ssm.reaction_time), kLive, 0.0, 10.0, nullptr, "s", "",
     "T_r: from a change in the scene to the robot reacting"},
    {"ssm/stopping_time", WP_M(ssm.stopping_time), kLive, 0.0, 10.0, nullptr, "s", "",
     "T_s: the robot's stopping time"},
    {"ssm/intrusion_distance", WP_M(ssm.intrusion_distance), kLive, 0.0, 10.0, nullptr, "m", "",
     "C: intrusion distance"},
    {"ssm/sensor_uncertainty", WP_M(ssm.sensor_uncertainty), kLive, 0.0, 10.0, nullptr, "m", "",
     "Z_d: the tracker's position uncertainty"},
    {"ssm/robot_uncertainty", WP_M(ssm.robot_uncertainty), kLive, 0.0, 10.0, nullptr, "m", "",
     "Z_r: the robot's position uncertainty"},
    {"ssm/robot_max_speed", WP_M(ssm.robot_max_speed), kLive, 0.001, 100.0, nullptr, "m/s", "",
     "v_max: the robot speed a speed scale of 1 means"},
    {"ssm/max_increase_rate", WP_M(ssm.max_increase_rate), kLive, 0.001, 1000.0, nullptr, "1/s",
     "", "the speed scale rises at most this fast"},
    {"ssm/hold_time", WP_M(ssm.hold_time), kLive, 0.0, 3600.0, nullptr, "s", "",
     "the raw scale must stay higher this long before the scale rises"},
    {"ssm/degraded_scale", WP_M(ssm.degraded_scale), kLive, 0.0, 1.0, nullptr, "",
     "(a speed scale)", "the speed scale at most while the prediction is DEGRADED"},
    // After a stop (stop_latch.hpp).
    {"ssm/restart", WP_M(ssm.restart), kStartup, 0, 0, nullptr, "", "",
     "'automatic' or 'manual': after a stop the scale stays 0 until ~reset is accepted"},
    {"ssm/min_stop_time", WP_M(ssm.min_stop_time), kStartup, 0.0, 3600.0, nullptr, "s", "",
     "the scale stays 0 at least this long after a stop (both restart modes)"},
    {"ssm/stop_category", WP_M(ssm.stop_category), kStartup, 1, 2, nullptr, "", "(1 or 2)",
     "2: hold; 1: hold, then the halt once the robot stands still"},
    {"ssm/standstill_speed", WP_M(ssm.standstill_speed), kStartup, 0.0001, 100.0, nullptr,
     "rad/s or m/s", "", "every joint slower than this stands still (category 1)"},
    {"ssm/standstill_time", WP_M(ssm.standstill_time), kStartup, 0.0, 60.0, nullptr, "s", "",
     "standstill this long after a stop before the halt (category 1)"},
    {"ssm/max_mute_time", WP_M(ssm.max_mute_time), kStartup, 0.0, 3600.0, nullptr, "s", "",
     "a mute (~mute) lasts at most this long; 0: muting refused"},
    {"ssm/stop_trajectory_topics", WP_M(ssm.stop_trajectory_topics), kWiring, 0, 0, nullptr, "",
     "", "an empty JointTrajectory on each at a stop"},
    {"ssm/stop_event_topics", WP_M(ssm.stop_event_topics), kWiring, 0, 0, nullptr, "", "",
     "\"stop\" (std_msgs/String) on each at a stop"},
    {"ssm/cmd_vel_in", WP_M(ssm.cmd_vel_in), kWiring, 0, 0, nullptr, "", "",
     "Twist commands to scale; empty: no filter"},
    {"ssm/cmd_vel_out", WP_M(ssm.cmd_vel_out), kWiring, 0, 0, nullptr, "", "",
     "where the scaled commands go"},
    {"ssm/halt_service", WP_M(ssm.halt_service), kWiring, 0, 0, nullptr, "", "",
     "std_srvs/Trigger called for the halt (category 1); empty: none"},
    {"ssm/halt_topic", WP_M(ssm.halt_topic), kWiring, 0, 0, nullptr, "", "",
     "std_msgs/Empty published for the halt (category 1); empty: none"},
    // ~detection_tracker/: the multi-object tracker of detection inputs and obstacle_detector
    // (foreign_detections.hpp). Read when an input's tracker is made (its first message).
    {"detection_tracker/gate_chi2", WP_M(detection_tracker.gate_chi2), kWiring, 0.1, 1000.0,
     nullptr, "", "(squared Mahalanobis distance)",
     "a detection farther from a track's predicted centre is not that track's (16.27: 99.9 %)"},
    {"detection_tracker/gate_distance", WP_M(detection_tracker.gate_distance), kWiring, 0.01,
     100.0, nullptr, "m", "", "a detection farther from a track's predicted centre is not that track's"},
    {"detection_tracker/confirm_hits", WP_M(detection_tracker.confirm_hits), kWiring, 1, 100,
     nullptr, "detections", "", "detections that confirm a new track (1: at once)"},
    {"detection_tracker/max_misses", WP_M(detection_tracker.max_misses), kWiring, 1, 1000, nullptr,
     "messages", "", "messages in a row without its detection that delete a track"},
    {"detection_tracker/timeout", WP_M(detection_tracker.timeout), kWiring, 0.001, 3600.0, nullptr,
     "s", "", "a track without a detection this long is deleted"},
    {"detection_tracker/known_velocity_error", WP_M(detection_tracker.known_velocity_error),
     kWiring, 0.001, 100.0, nullptr, "m/s", "",
     "a track's velocity counts as known once its 3 sigma error is at most this"},
};
#undef WP_M

constexpr LabelRow kLabels[] = {
    // key, member, tuning, track_only, min, max, at_most, unit, note, doc
    {"margin", &LabelSettings::margin, kLive, true, 0.0, 10.0, nullptr, "m", "",
     "added around the tracked box"},
    {"warning_time", &LabelSettings::warning_time, kLive, false, 0.0, 60.0, nullptr, "s", "",
     "time to contact at or below: WARNING"},
    {"critical_time", &LabelSettings::critical_time, kLive, false, 0.0, 60.0, "warning_time", "s",
     "", "time to contact at or below: CRITICAL"},
    {"warning_distance", &LabelSettings::warning_distance, kLive, false, 0.0, 100.0, nullptr, "m",
     "", "distance at or below: WARNING"},
    {"critical_distance", &LabelSettings::critical_distance, kLive, false, 0.0, 100.0,
     "warning_distance", "m", "", "distance at or below: CRITICAL"},
    {"position_error", &LabelSettings::position_error, kLive, true, 0.0, 10.0, nullptr, "m", "",
     "the tracker's position error, added to the margin"},
    {"velocity_error", &LabelSettings::velocity_error, kLive, true, 0.0, 100.0, nullptr, "m/s", "",
     "the tracker's velocity error e: the margin grows by e s"},
    {"max_accel", &LabelSettings::max_accel, kLive, true, 0.0, 1000.0, nullptr, "m/s^2", "",
     "the largest acceleration a: the margin grows by a s^2 / 2"},
    {"max_speed", &LabelSettings::max_speed, kLive, true, 0.0, 100.0, nullptr, "m/s",
     "(0: no speed cap)", "the largest speed v_max: the growth stays within (v_max + |v|) s"},
    {"ssm_min_speed", &LabelSettings::ssm_min_speed, kLive, true, 0.0, 20.0, nullptr, "m/s", "",
     "speed and separation: the approach speed assumed at least (1.6: walking)"},
    {"ssm_min_speed_measured", &LabelSettings::ssm_min_speed_measured, kLive, true, 0.0, 20.0,
     nullptr, "m/s", "(20: ssm_min_speed for life)",
     "speed and separation: once the velocity is known the floor is min(ssm_min_speed, this)"},
    {"size_x", &LabelSettings::size_x, kStartup, true, 0.01, 100.0, nullptr, "m", "",
     "x extent of a track whose message gives no size (foreign people tracks)"},
    {"size_y", &LabelSettings::size_y, kStartup, true, 0.01, 100.0, nullptr, "m", "",
     "y extent of a track whose message gives no size"},
    {"size_z", &LabelSettings::size_z, kStartup, true, 0.01, 100.0, nullptr, "m", "",
     "z extent (height) of a track whose message gives no size"},
};

}  // namespace

ParamRows<ParamRow> paramTable() { return {kParams, sizeof(kParams) / sizeof(kParams[0])}; }

ParamRows<LabelRow> labelTable() { return {kLabels, sizeof(kLabels) / sizeof(kLabels[0])}; }

const ParamRow* findParam(const std::string& name) {
  for (const ParamRow& row : kParams) {
    if (name == row.name) return &row;
  }
  return nullptr;
}

const LabelRow* findLabelSetting(const std::string& key) {
  for (const LabelRow& row : kLabels) {
    if (key == row.key) return &row;
  }
  return nullptr;
}

double numberOf(const ParamRow& row, const MonitorParams& p) {
  // The accessors take a mutable struct (one accessor serves reading and writing); nothing
  // is written here.
  MonitorParams& q = const_cast<MonitorParams&>(p);
  if (row.member.type == ParamType::kNumber) return row.member.number(q);
  if (row.member.type == ParamType::kInteger) return row.member.integer(q);
  throw std::logic_error(std::string("~") + row.name + " is not a number");
}

void keepWiring(const MonitorParams& built, MonitorParams* next) {
  for (const ParamRow& row : kParams) {
    if (row.tuning == Tuning::kWiring) row.member.copy(built, *next);
  }
}

}  // namespace workspace_proximity
