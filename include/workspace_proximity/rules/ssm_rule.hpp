#pragma once
/// Speed and separation monitoring after ISO/TS 15066: the protective separation distance, the
/// robot speed it allows, and the speed scale a controller applies, with hysteresis. ROS-free.
///
/// For a robot body and a tracked object at distance d (bare shapes, 0 when they overlap), the
/// object approaching at v_h (its velocity along the direction from its nearest point to the
/// robot's, at least 0 and at least its label's minimum), and the robot moving at v_r:
///   S_p(v_r) = v_h (T_r + T_s) + v_r T_r + v_r T_s / 2 + C + Z_d + Z_r
/// with T_r the reaction time, T_s the stopping time, C the intrusion distance, Z_d and Z_r the
/// sensor's and the robot's position uncertainties. The largest v_r >= 0 with S_p(v_r) <= d is
///   v_allowed = (d - v_h (T_r + T_s) - C - Z_d - Z_r) / (T_r + T_s / 2), at least 0,
/// and the pair's scale is min(1, v_allowed / v_max). The cycle's scale is the smallest over all
/// monitored pairs (1 with none). A pair at or beyond S_p(v_max) allows full speed.

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "workspace_proximity/body.hpp"
#include "workspace_proximity/rules/stamp.hpp"
#include "workspace_proximity/rules/stop_latch.hpp"

namespace workspace_proximity {

/// The rule's constants (the ~ssm/ parameters). Times in s, distances in m, speeds in m/s.
struct SsmParams {
  bool enabled = true;
  std::vector<std::string> labels;   ///< object labels monitored; empty: every object label
  double reaction_time = 0.1;        ///< T_r
  double stopping_time = 0.3;        ///< T_s
  double intrusion_distance = 0.1;   ///< C
  double sensor_uncertainty = 0.1;   ///< Z_d
  double robot_uncertainty = 0.02;   ///< Z_r
  double robot_max_speed = 1.0;      ///< v_max: the speed scale 1 means
  double max_increase_rate = 0.5;    ///< 1/s: the output rises at most this much per second
  double hold_time = 0.5;            ///< s the raw scale must stay above the output before it rises
  double degraded_scale = 0.0;       ///< the scale at most while the prediction is DEGRADED
  // After a stop (stop_latch.hpp).
  std::string restart = "automatic";  ///< "automatic" | "manual": a stop holds until ~reset
  double min_stop_time = 0.0;         ///< s the scale stays 0 after a stop (both modes)
  int stop_category = 2;              ///< 2: hold; 1: hold, then the halt at standstill
  double standstill_speed = 0.01;     ///< rad/s or m/s: every joint below this stands still
  double standstill_time = 0.5;       ///< s of standstill before the halt (category 1)
  double max_mute_time = 0.0;         ///< s a mute lasts at most; 0: ~mute is refused
  // Outputs wired by the ROS bridge (names only here).
  std::vector<std::string> stop_trajectory_topics;  ///< empty JointTrajectory on each at a stop
  std::vector<std::string> stop_event_topics;       ///< "stop" (std_msgs/String) on each at a stop
  std::string cmd_vel_in;   ///< Twist commands to scale ("" = no filter)
  std::string cmd_vel_out;  ///< the scaled commands
  std::string halt_service;  ///< std_srvs/Trigger called for the halt (category 1), or ""
  std::string halt_topic;    ///< std_msgs/Empty published for the halt (category 1), or ""
};

/// One cycle's verdict of the rule, read by every output (speed_scale, safety_status,
/// speed_override, stop actions, the Twist filter, markers, diagnostics, the replay).
struct SsmVerdict {
  bool enabled = false;       ///< ~ssm/enabled; nothing below means anything otherwise
  /// The scale the robot may use, in [0, 1]: the raw scale, at most ~ssm/degraded_scale while
  /// the prediction is DEGRADED, after the hysteresis (SpeedScaleFilter).
  double speed_scale = 0.0;
  /// The rule itself: the smallest pairScale() over the monitored pairs within reach, 1 with
  /// none (degraded_scale after a failed cycle, when nothing is known).
  double raw_scale = 1.0;
  bool degraded = false;      ///< the cycle's status is DEGRADED (the scale is capped)
  int pairs = 0;              ///< monitored robot-object pairs within reach this cycle
  /// The limiting pair: the monitored pair with the smallest d - S_p(v_max) (the one that sets
  /// raw_scale, or the nearest to doing so when raw_scale is 1). Only with `limited`.
  bool limited = false;
  BodyHandle robot;           ///< its robot body (named by the world until the next predict)
  BodyHandle object;          ///< its tracked object
  double separation = std::numeric_limits<double>::infinity();  ///< d, m
  double required_separation = 0.0;  ///< S_p(v_max) for its approach speed, m
  double approach_speed = 0.0;       ///< v_h, m/s
  Eigen::Vector3d point_robot = Eigen::Vector3d::Zero();   ///< nearest points now, fixed frame
  Eigen::Vector3d point_object = Eigen::Vector3d::Zero();
  std::string reason;         ///< one line: why the scale is what it is
  /// Monitored pairs within their S_p(v_max) this cycle, muted ones included (a reset or a
  /// mute is refused while any is).
  int within = 0;
  int muted_pairs = 0;        ///< monitored pairs within reach left out of the scale: muted
  /// The stop latch after this cycle and its events (SsmCycle's, valid until the next cycle;
  /// null before the first or while disabled).
  const LatchState* latch = nullptr;
  const LatchEvents* latch_events = nullptr;
  /// Per world body slot: 1 for a track muted this cycle (SsmCycle's; null before the first).
  const std::vector<std::uint8_t>* muted_slots = nullptr;
};

/// S_p(v_r), m.
double protectiveSeparation(const SsmParams& p, double approach_speed, double robot_speed);
/// The largest robot speed (m/s, >= 0) whose protective separation fits in `distance`.
double allowedRobotSpeed(const SsmParams& p, double distance, double approach_speed);
/// min(1, allowedRobotSpeed / robot_max_speed), in [0, 1].
double pairScale(const SsmParams& p, double distance, double approach_speed);

/// The scale a controller gets: drops at once, rises at most `max_increase_rate` per second and
/// only after the raw scale has stayed above the output for `hold_time`. Starts at 0 (nothing
/// is known before the first cycle).
class SpeedScaleFilter {
 public:
  explicit SpeedScaleFilter(const SsmParams& p) : rate_(p.max_increase_rate), hold_(p.hold_time) {}
  void setParams(const SsmParams& p) {
    rate_ = p.max_increase_rate;
    hold_ = p.hold_time;
  }
  /// The output at `now` for the raw scale `raw` (in [0, 1]).
  double update(Stamp now, double raw);
  double output() const { return output_; }
  /// Forgets the history (after the clock went back): the output drops to 0.
  void reset() { *this = SpeedScaleFilter(rate_, hold_); }

 private:
  SpeedScaleFilter(double rate, double hold) : rate_(rate), hold_(hold) {}
  double rate_;
  double hold_;
  double output_ = 0.0;
  Stamp last_ = 0;          // previous update
  Stamp above_since_ = -1;  // since when raw > output without a break, -1: not above
};

}  // namespace workspace_proximity
