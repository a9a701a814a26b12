#pragma once
/// The robot predicted from its joints, without ROS: joint readings (positions, velocities) and
/// an optional planned trajectory in, a keyframed path per robot body out.
///
/// Over the horizon every joint moves at its reported velocity (a finite difference of its
/// last two readings when none is reported) and stops at its limit; a planned trajectory, while
/// one is in force, replaces that for its joints: linear between its points from the current
/// position on, holding the last point. Between the merged breakpoints of all joints (limit
/// stops, trajectory points) every joint moves at a constant rate. There the bodies are sampled
/// at keyframes (forward kinematics of the model) and joined by straight segments (constant
/// twist: the centre on the chord, turning at the mean rate), and each segment's margin gets a
/// bound on how far any point of the body can be from its true position:
///   delta = dt^2 / 8 (A + rho W^2),
/// dt the segment's duration, rho the shape's bounding radius, W the body's angular speed bound
/// (sum of the turning joints' speeds, plus the root's), and A a bound on the acceleration of
/// any point of the body: for the joints i of its chain (the root's motion first, as a sliding
/// then a turning joint), speeds s_i and lever arms L_i (reach from joint i's axis point to the
/// body's farthest point),
///   A = sum over turning i of s_i (2 W_<i L_i + U_>=i) + sum over sliding i of s_i W_<i,
///   U_>=i = sum over turning m >= i of s_m L_m + sum over sliding m >= i of s_m,
/// W_<i the turning speeds before i. (A point's chord error is at most dt^2 / 8 times its
/// largest acceleration; the rigid interpolation differs from the points' chords by at most
/// rho theta^2 / 8, theta <= W dt the turn over the segment.) Keyframes are spaced so that delta
/// stays within ~path_tolerance where the segment budget allows; the bound is added whatever
/// it is, so the prediction stays conservative. A segment that must span several breakpoints
/// (more breakpoints than the budget) gets the first-order bound V dt / 2 + rho (W dt)^2 / 8,
/// V = U_>=0 the speed bound.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "workspace_proximity/rules/kinematic_model.hpp"
#include "workspace_proximity/rules/stamp.hpp"
#include "workspace_proximity/motion_path.hpp"

namespace workspace_proximity {

struct JointPredictorParams {
  /// s: a joint whose newest reading is older than this is unknown (the node's ~tf_timeout).
  double state_timeout = 0.5;
  /// rad or m: a trajectory that a joint's reading contradicts by more is dropped.
  double trajectory_tolerance = 0.1;
  /// m: keyframes are spaced so that each segment stays within this of the true motion
  /// (where max_segments allows; the bound is added to the margin whatever it is).
  double path_tolerance = 0.01;
  /// Keyframed segments per body at most (1 .. Limits::kMaxSegments).
  int max_segments = 16;
};

/// A planned trajectory in the model's joint indices.
struct JointPlan {
  Stamp start = 0;                ///< when its times start (absolute)
  std::vector<int> joints;        ///< joints it drives (indices into the model's joints)
  std::vector<double> times;      ///< s after `start`, one per point, >= 0, strictly increasing
  std::vector<double> positions;  ///< rad or m, points x joints (row per point)
};

enum class JointPathState : std::uint8_t {
  kMoving = 0,   ///< posed, with its predicted path
  kStale = 1,    ///< posed where it is now, but its motion is not known (`why`)
  kUnknown = 2,  ///< cannot be posed (`why`): a joint of its chain never read, or too old
};

/// One body's prediction.
struct JointBodyPath {
  JointPathState state = JointPathState::kUnknown;
  std::string why;
  /// kMoving: the keyframed path (the first segment's pose is the pose now). kStale: one
  /// segment, the pose now, without velocity.
  std::vector<MotionSegment> segments;
};

class JointPredictor {
 public:
  /// `model` must not be null.
  JointPredictor(std::shared_ptr<const KinematicModel> model, const JointPredictorParams& params);

  const KinematicModel& model() const { return *model_; }
  const JointPredictorParams& params() const { return params_; }
  void setParams(const JointPredictorParams& params) { params_ = params; }

  /// A body attached to model link `link` (index into model().links()) at `offset` (the
  /// shape's pose in the link frame), `radius` m its shape's bounding radius. Returns its index.
  int addBody(int link, const Eigen::Isometry3d& offset, double radius);
  int bodyCount() const { return static_cast<int>(bodies_.size()); }

  /// Joint `joint`'s reading at `stamp`: its position and velocity (NaN when not measured: the
  /// finite difference with the previous reading, if that is at most state_timeout older).
  /// A reading older than the joint's newest is ignored.
  void observe(int joint, Stamp stamp, double position, double velocity);

  /// A planned trajectory from now on. Returns "" when accepted (it replaces the one in force),
  /// otherwise why it was refused (the one in force stays): joints out of range or listed
  /// twice, no points, point sizes that do not match, non-finite positions, times negative or
  /// not strictly increasing, or already ended at `now`. Positions beyond a joint's limits
  /// are clamped to them.
  std::string setPlan(JointPlan plan, Stamp now);
  void clearPlan() { has_plan_ = false; }
  bool hasPlan() const { return has_plan_; }

  /// Forgets every reading and the plan (after the clock went back).
  void reset();

  /// Predicts every body at `now` over [0, horizon] (s); the root frame is at `base` (its pose
  /// now and twist, in the fixed frame). Checks the plan first: dropped when a joint's
  /// reading contradicts it by more than trajectory_tolerance (planEvent() says so), or when
  /// it has ended. Allocation-free once sized (a longer plan than before grows the buffers).
  void predict(Stamp now, double horizon, const BodyMotion& base);

  const JointBodyPath& body(int i) const { return bodies_[static_cast<std::size_t>(i)].path; }
  /// rad or m: joint `joint`'s position at the last predict()'s `now`, as it posed the bodies
  /// (the reading moved on by its velocity within its limits, or the plan's position).
  double jointPosition(int joint) const { return knots_[static_cast<std::size_t>(joint)].front().q; }
  /// Why the plan was dropped by the last predict() (contradicted), "" otherwise.
  const std::string& planEvent() const { return plan_event_; }
  /// The plan ended in the last predict() (it was followed to its end).
  bool planCompleted() const { return plan_completed_; }
  /// Keyframed segments of the last predict().
  int segmentCount() const { return static_cast<int>(keyframes_.size()) - 1; }

 private:
  struct Reading {
    bool seen = false;
    Stamp stamp = 0;
    double position = 0.0;
    double velocity = 0.0;
    bool velocity_known = false;
  };
  struct Body {
    int link = -1;
    Eigen::Isometry3d offset = Eigen::Isometry3d::Identity();
    double radius = 0.0;
    // Lever arms (m) of the root's turn and of each chain joint, to the body's farthest point.
    double root_lever = 0.0;
    std::vector<double> lever;
    JointBodyPath path;
  };
  // A joint's motion over the horizon: piecewise linear through its knots, held after the last.
  struct Knot {
    double t;
    double q;
  };

  void checkPlan(Stamp now);
  double planPosition(int p, double since_start) const;
  void buildKnots(Stamp now, double horizon);
  void velocityKnots(int joint, double q_now, double velocity, double until, std::vector<Knot>* out) const;
  double positionAt(int joint, double t) const;
  void placeKeyframes(double horizon, const BodyMotion& base);
  // Acceleration bound A + rho W^2 (second order) or the speed bound V and W for body b with
  // the joint speeds `speed` (per model joint) and the root's twist.
  void bounds(const Body& b, const std::vector<double>& speed, const BodyMotion& base, double* second,
              double* speed_bound, double* turn_bound) const;
  void buildPaths(const BodyMotion& base);

  std::shared_ptr<const KinematicModel> model_;
  JointPredictorParams params_;
  std::vector<Reading> readings_;
  std::vector<Body> bodies_;
  JointPlan plan_;
  bool has_plan_ = false;
  std::string plan_event_;
  bool plan_completed_ = false;

  // Per cycle, reused.
  std::vector<std::uint8_t> joint_ok_;   // per joint: reading usable
  std::vector<std::string> joint_why_;   // per joint: why not (or "velocity not known")
  std::vector<std::uint8_t> velocity_ok_;
  std::vector<std::vector<Knot>> knots_;  // per joint
  std::vector<double> breaks_;           // merged knot times
  std::vector<double> keyframes_;        // keyframe times
  std::vector<std::uint8_t> merged_;     // per keyframed segment: spans several breaks
  std::vector<double> speeds_;           // per joint, scratch
  std::vector<double> q_;                // per joint, scratch
  std::vector<Eigen::Isometry3d> link_poses_;  // keyframes x links
  std::vector<double> segment_second_, segment_speed_, segment_turn_;  // per segment x body
};

}  // namespace workspace_proximity
