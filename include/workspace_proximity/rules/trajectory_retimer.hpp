#pragma once
/// trajectory_relay's rule, without ROS: a planned joint trajectory executed at a varying speed
/// scale by a controller that only takes whole trajectories (ROS 1's joint_trajectory_controller:
/// a new trajectory replaces the old one, and it holds at the end of the last one it got).
///
/// The plan is held in flat arrays (times, positions, velocities, accelerations; point-major,
/// joint-minor) with capacities set up front. Progress is the planned time reached, s (s). Each
/// tick the progress advances by the scale the previous chunk ran at times the wall time since
/// it, then a chunk of the REMAINDER is built for the new scale:
///   - scale > 0: the state at s (on the plan's own spline: linear between positions only,
///     cubic with velocities, quintic with accelerations) at wall time 0, the plan's points
///     after s, and the state at s + scale * horizon (or the plan's end), planned time s_i at
///     wall time (s_i - s) / scale, velocities times scale, accelerations times scale^2. A
///     controller that interpolates the chunk the same way traces the same polynomials, so the
///     path in joint space is the plan's and only its timing changes.
///   - scale 0: a hold: one point, the state at s with zero velocity and acceleration, reached
///     after `hold_time` s.
///   - the plan's end reached: nothing more to send (the last chunk ended at the final point,
///     where the controller holds).
/// A silent relay therefore leaves the controller at most one horizon of motion.
/// Nothing is allocated after construction.

#include <cstddef>
#include <string>
#include <vector>

namespace workspace_proximity {

struct TrajectoryRetimerCapacity {
  /// Joints a plan may name at most.
  int max_joints = 32;
  /// Points a plan may have at most.
  int max_points = 10000;
};

/// Why a plan was refused (the previous plan, if any, stays).
enum class PlanRejection {
  kNone,
  kNoJoints,            // no joint names
  kTooManyJoints,       // more joints than the capacity
  kNoPoints,            // no points
  kTooManyPoints,       // more points than the capacity
  kSizeMismatch,        // a point's positions (or velocities, accelerations) do not match the joints
  kMixedDerivatives,    // velocities (or accelerations) on some points but not all
  kNotFinite,           // a NaN or infinite value
  kFirstTimeNotZero,    // the first point is not at time_from_start 0
  kTimesNotIncreasing,  // time_from_start not strictly increasing
};

/// A readable name of the rejection, for logs and diagnostics.
const char* planRejectionName(PlanRejection r);

/// What a tick asks the node to send.
enum class ChunkKind {
  kNothing,  // no plan, or its end reached: send nothing
  kMotion,   // a re-timed part of the remainder
  kHold,     // scale 0: stand still where the progress is
};

/// One chunk to send: `count` points, each with `joints` values per array (flat, point-major).
/// Velocities and accelerations are filled as the plan has them (has_velocities,
/// has_accelerations); at a hold, velocities (and accelerations) are zero when the plan has them.
struct RetimedChunk {
  ChunkKind kind = ChunkKind::kNothing;
  int count = 0;
  int joints = 0;
  bool has_velocities = false;
  bool has_accelerations = false;
  std::vector<double> times;          ///< s of wall time from the chunk's start
  std::vector<double> positions;      ///< rad or m
  std::vector<double> velocities;     ///< rad/s or m/s
  std::vector<double> accelerations;  ///< rad/s^2 or m/s^2
};

class TrajectoryRetimer {
 public:
  /// `horizon`: s of wall time a chunk covers at most (~chunk, > 0). `hold_time`: s after which
  /// a hold's point is reached (> 0; the relay uses its period).
  TrajectoryRetimer(const TrajectoryRetimerCapacity& capacity, double horizon, double hold_time);

  /// Starts loading a plan of `joints` joints and `points` points (replaces the current one once
  /// finished). Then setPoint() for every point in order, then finishPlan().
  /// `has_velocities`/`has_accelerations`: whether the points carry them.
  PlanRejection beginPlan(int joints, int points, bool has_velocities, bool has_accelerations);
  /// Point `index`: its time (s from the plan's start) and `joints` values each (velocities and
  /// accelerations ignored when the plan has none; may be null then).
  void setPoint(int index, double time, const double* positions, const double* velocities,
                const double* accelerations);
  /// Checks the points; on success the plan replaces the previous one with progress 0 and the
  /// scale of the last chunk 0. On failure the previous plan stays in force.
  PlanRejection finishPlan();
  /// Drops the plan (nothing to send until the next one).
  void clear();

  /// One tick `dt` s of wall time after the previous one (0 for the first after a plan):
  /// advances the progress by the previous chunk's scale, then builds the chunk for `scale`
  /// (clamped to [0, 1]; NaN counts as 0). The chunk is valid until the next call.
  const RetimedChunk& tick(double dt, double scale);

  bool hasPlan() const { return loaded_; }
  int joints() const { return joints_; }
  /// Progress: planned time reached, s.
  double progress() const { return s_; }
  /// The plan's duration, s of planned time.
  double duration() const { return loaded_ ? times_[count_ - 1] : 0.0; }
  bool finished() const { return loaded_ && s_ >= duration(); }
  /// The plan's state at planned time `s` (clamped to the plan): positions, and the derivatives
  /// with respect to planned time (zero when the plan has none), `joints()` values each.
  void stateAt(double s, double* positions, double* velocities, double* accelerations) const;

 private:
  int segmentAt(double s) const;  // index i of the segment [t_i, t_i+1] holding s
  void appendState(double s, double wall_time, double scale, bool hold);

  TrajectoryRetimerCapacity capacity_;
  double horizon_;
  double hold_time_;

  // The plan in force.
  bool loaded_ = false;
  int joints_ = 0;
  int count_ = 0;
  bool has_vel_ = false;
  bool has_acc_ = false;
  std::vector<double> times_;
  std::vector<double> pos_;
  std::vector<double> vel_;
  std::vector<double> acc_;
  // The plan being loaded (swapped in by finishPlan).
  int next_joints_ = 0;
  int next_count_ = 0;
  bool next_has_vel_ = false;
  bool next_has_acc_ = false;
  std::vector<double> next_times_;
  std::vector<double> next_pos_;
  std::vector<double> next_vel_;
  std::vector<double> next_acc_;

  double s_ = 0.0;           // progress, s of planned time
  double last_scale_ = 0.0;  // the scale the last chunk was sent at
  RetimedChunk chunk_;
  // Scratch for one state.
  std::vector<double> q_, dq_, ddq_;
};

}  // namespace workspace_proximity
