#pragma once
/// Parameters of the proximity_monitor node, as a plain struct checked before anything is
/// built. Reading them from the parameter server lives in ros_params.hpp; this file has no
/// ROS dependency so the checks are unit-testable. The members' initializers are the
/// defaults; names on the parameter server, ranges, units and which can change while the node
/// runs are the rows of param_table.hpp.

#include <map>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "workspace_proximity/body.hpp"
#include "workspace_proximity/rules/ssm_rule.hpp"
#include "workspace_proximity/pair_rules.hpp"

namespace workspace_proximity {

/// Per-label settings. Times in seconds, distances and margin in metres.
struct LabelSettings {
  double margin = 0.10;            ///< added around the tracked box
  double warning_time = 1.0;       ///< time_to_contact at or below -> WARNING
  double critical_time = 0.4;      ///< time_to_contact at or below -> CRITICAL
  double warning_distance = 0.5;   ///< distance at or below -> WARNING
  double critical_distance = 0.2;  ///< distance at or below -> CRITICAL
  /// m/s, speed and separation monitoring: the approach speed v_h assumed at least (1.6 is the
  /// standard's walking speed for people whose motion is not measured); 0: as tracked.
  double ssm_min_speed = 0.0;
  /// m/s: once a track's velocity is known (measured, with its tracker's own error), its
  /// approach-speed floor is min(ssm_min_speed, this). The default (20, the range's top) keeps
  /// ssm_min_speed for the track's whole life; 0 makes ssm_min_speed hold only while the
  /// velocity is unknown (issue 23: the `unknown` label of cloud_tracker's tracks).
  double ssm_min_speed_measured = 20.0;

  // How far a track of this label can stray from its constant-velocity prediction (every one
  // 0 by default: no growth, today's prediction). The margin grows as
  //   m(s) = margin + position_error + R(s),  R(s) = min(e s + a s^2 / 2, (v_max + |v|) s)
  // s seconds after the track's measurement stamp (track_growth.hpp); v_max = 0: no cap.
  // Not used for the robot (robot_thresholds).
  double position_error = 0.0;  ///< m, tracker position error, added to the margin
  double velocity_error = 0.0;  ///< e, m/s, tracker velocity error
  double max_accel = 0.0;       ///< a, m/s^2, largest acceleration of an object of this label
  double max_speed = 0.0;       ///< v_max, m/s, largest speed of such an object; 0: no speed cap

  // The box of a track whose message gives no size (a foreign people tracker's point): full
  // extents in the message's frame, a person upright by default. TrackedBoxArray gives its own.
  double size_x = 0.6;  ///< m
  double size_y = 0.6;  ///< m
  double size_z = 1.8;  ///< m
};

/// A robot body declared in ~robot_bodies or taken from the URDF.
struct RobotBodySpec {
  std::string name;   ///< body id
  std::string frame;  ///< tf frame it is attached to
  Shape shape;
  Eigen::Isometry3d offset = Eigen::Isometry3d::Identity();  ///< shape pose in `frame`
};

/// The multi-object tracker (multi_object_tracker.hpp) of detection inputs (vision_msgs,
/// jsk BoundingBoxArray, MarkerArray, PoseArray) and obstacle_detector (~detection_tracker/).
/// Defaults: TrackerParams' (test_param_table checks the two agree).
struct DetectionTrackerSettings {
  double gate_chi2 = 16.27;    ///< squared Mahalanobis distance gate (3 dof: 99.9 %)
  double gate_distance = 2.0;  ///< m, metric gate on |detection - predicted centre|
  int confirm_hits = 2;        ///< detections that confirm a new track (1: at once)
  int max_misses = 3;          ///< frames in a row without a detection that delete a track
  double timeout = 1.0;        ///< s since its last detection that deletes a track
  double known_velocity_error = 1.0;  ///< m/s, 3 sigma: a track's velocity is known at or below
};

struct MonitorParams {
  std::string fixed_frame = "world";
  double rate = 30.0;           ///< Hz
  double horizon = 2.0;         ///< s
  double track_timeout = 0.5;   ///< s
  std::vector<std::string> input_topics;  ///< empty: the single topic "tracked_objects"
  /// Perception front ends' PerceptionStatus topics (cloud_tracker's perception_status): a
  /// degraded or silent one makes the status DEGRADED (perception_health.hpp).
  std::vector<std::string> perception_status_topics;
  /// Input topics (as input_topics lists them) whose visualization_msgs/MarkerArray is read as
  /// Azure Kinect body-tracking skeletons (one SPHERE per K4ABT joint), not as detections.
  std::vector<std::string> skeleton_marker_topics;
  double stale_after = 0.25;    ///< s; pairs with a track older than this are marked stale
  double source_timeout = 1.0;  ///< s without an array from a source -> DEGRADED
  double max_future = 0.5;      ///< s; arrays stamped further ahead of the clock are dropped
  int max_tracks = 2000;        ///< tracked objects kept at most (nearest to the robot win)
  /// Updates of each box's own motion that the broad phase's enlarged bounds lead by
  /// (SweepAndPruneConfig::coast_updates; 0: coasting off). 16, twice the core's default: runs
  /// of steady motion then last long enough to be spread over the updates before their end,
  /// which lowers the cycle's tail (bench/results/NOTES.md section 22).
  double broad_phase_lead = 16.0;
  /// Threads for the per-pair stages of each prediction (WorldConfig::pair_threads: the
  /// contact window and narrow phase of every broad-phase pair), used from 2 048 pairs on.
  /// 1 (the cycle's thread alone) by default: on the benchmark machine (a 2-vCPU VM) a worker
  /// woken every 33 ms made the node no faster (bench/results/NOTES.md section 23); on a
  /// machine with idle cores 2 or more shorten the stages (1.6-1.8 times on two threads when
  /// cycles follow each other at once, as in a replay).
  int pair_threads = 1;
  /// s; after the safety outputs are published (speed_scale, speed_override, safety_status,
  /// the stop actions), the cycle sleeps this long before it predicts the contacts, so that
  /// the threads that deliver them (roscpp's poll thread, a controller's threads woken onto
  /// the monitor's core) run first instead of waiting up to a scheduler slice behind the
  /// prediction. Only while the safety outputs have a subscriber; 0: the cycle only yields.
  /// 200 us: at 1 000 objects on the 2-vCPU benchmark VM the speed_scale p99 was 0.95-1.33 ms
  /// in 16 runs of 16, against 1.17-2.04 ms with the yield alone; 50 us did not help, 100 us
  /// did (bench/results/safety_latency.md, session 28).
  double safety_handoff = 0.0002;
  /// When a cycle runs: "timer" (every 1 / rate s) or "input" (as soon as an array of
  /// `trigger_source` arrives, at most `rate` times a second, and at least every 1 / rate s).
  std::string cycle_trigger = "timer";
  /// The input topic whose arrays trigger a cycle (as listed in input_topics, or
  /// "tracked_objects"); empty: the first input topic.
  std::string trigger_source;

  bool use_robot_description = true;
  std::string robot_description_param = "robot_description";
  std::vector<RobotBodySpec> robot_bodies;
  /// Refuse to start when a URDF collision element cannot be modelled (otherwise the status
  /// stays DEGRADED naming it for as long as the node runs).
  bool require_all_links = false;
  double robot_margin = 0.02;     ///< m
  double velocity_window = 0.1;   ///< s of tf history for robot link velocities
  double tf_timeout = 0.5;        ///< s; older robot transforms (and joint states) are not used

  /// Links moved by URDF joints are posed from sensor_msgs/JointState on joint_states with
  /// forward kinematics (only when a URDF is loaded); false: every link from tf.
  bool use_joint_states = true;
  /// trajectory_msgs/JointTrajectory topic of the robot's planned motion; "" = none.
  std::string trajectory_topic;
  /// rad or m: a planned trajectory the joint states contradict by more is dropped.
  double trajectory_tolerance = 0.1;
  /// m: joint-space keyframes are spaced so that each straight segment stays within this of
  /// the links' true arcs (where 16 segments allow; the bound is added to the margin anyway).
  double joint_path_tolerance = 0.01;

  std::vector<std::pair<std::string, std::string>> ignore_pairs;
  std::vector<std::pair<std::string, std::string>> check_pairs;

  std::map<std::string, LabelSettings> labels;  ///< always has "default" after reading
  LabelSettings robot_thresholds;               ///< margin unused: robot_margin applies

  bool publish_markers = true;
  double marker_lifetime = 0.5;  ///< s
  /// Hz, markers are published at most this often (every cycle when >= rate): RViz needs
  /// far fewer than the prediction, and 1 000 bodies' markers cost as much as a prediction.
  double marker_rate = 10.0;
  /// The audit trail's CSV file (audit_log.hpp), appended; "" = none.
  std::string audit_log;

  SsmParams ssm;  ///< speed and separation monitoring (~ssm/)
  DetectionTrackerSettings detection_tracker;  ///< ~detection_tracker/

  MonitorParams();
  /// Settings for a label ("default" when not listed).
  const LabelSettings& label(const std::string& name) const;
};

/// Every problem found, one message per problem naming the parameter and the allowed range.
/// Empty means the parameters are usable.
std::vector<std::string> validate(const MonitorParams& params);

/// `next` with the wiring of `built` (frames, topics, the robot's bodies, where the outputs
/// go: the Tuning::kWiring rows of param_table.hpp), which a running monitor keeps while its
/// rules change.
void keepWiring(const MonitorParams& built, MonitorParams* next);

/// Pair rules: the default (robot-robot skipped), then ignore_pairs (deny), then check_pairs
/// (allow). Throws std::invalid_argument on a bad selector (validate() reports those too).
PairRules makePairRules(const MonitorParams& params);

}  // namespace workspace_proximity
