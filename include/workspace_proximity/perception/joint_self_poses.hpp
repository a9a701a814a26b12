#pragma once
/// The robot's links for the self-filter at a cloud's stamp, posed from the joints the way the
/// monitor poses them (issue 23): the monitor's KinematicModel (forward kinematics) and
/// JointPredictor (its motion model: joint velocities within limits, or a planned trajectory).
/// ROS-free; cloud_tracker feeds it the joint_states and trajectories and poses the root frame
/// from tf.
///
/// Per joint, at the cloud's stamp t:
///   - t between two kept readings a <= t <= b (at most the predictor's state_timeout apart):
///     the position interpolated between them (the short way round for a continuous joint);
///     speed bound s = max(|v_a|, |v_b|, |chord|) (the velocities that were measured), gap
///     g = 2 d e / (d + e), d = t - a, e = b - t: however the joint moved in between at most
///     that fast, it is within s g of the interpolation (and g <= 2 min(d, e));
///   - t at or after the newest reading: the predictor's position at t (its motion model, as
///     the monitor's), s = max(|velocity|, |predicted - read| / (t - read)), g = t - read;
///   - otherwise (never read, newest reading older than state_timeout, velocity not known, t
///     before the oldest kept reading, readings too far apart): no pose, why says which joint.
/// A link's growth is padding + speed x gap, with speed = sum over its chain of s_i L_i (L_i
/// the lever from joint i's axis point to the link shape's farthest point, as the predictor
/// bounds it; 1 for a sliding joint) and gap = the largest g_i: every point of the true link is
/// within that of the posed one (moving joint i by delta moves no point farther than L_i delta).
/// Allocation-free after construction, except for a planned trajectory's own storage.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "workspace_proximity/perception/self_filter.hpp"
#include "workspace_proximity/rules/joint_posing.hpp"
#include "workspace_proximity/rules/joint_predictor.hpp"
#include "workspace_proximity/rules/kinematic_model.hpp"
#include "workspace_proximity/rules/monitor_params.hpp"

namespace workspace_proximity {
namespace perception {

class JointSelfPoses {
 public:
  /// Claims every body of `robot` whose frame is a link of `model` (not null) that a joint
  /// moves. `params.state_timeout`: the monitor's ~tf_timeout. `history`: readings kept per
  /// joint (at least 2).
  JointSelfPoses(std::shared_ptr<const KinematicModel> model, const std::vector<RobotBodySpec>& robot,
                 const JointPredictorParams& params, int history = 64);

  const KinematicModel& model() const { return predictor_.model(); }
  /// Whether robot body i (index into the `robot` given) is posed from the joints.
  bool claims(int i) const { return link_of_[static_cast<std::size_t>(i)] >= 0; }
  int claimedCount() const { return claimed_; }

  /// A joint state: per name a position and, when `velocities` has one per name, a velocity
  /// (otherwise not measured). `stamp` 0 means `now`. Joints the model does not know are
  /// skipped; a reading older than the joint's newest is ignored (as the predictor does).
  void onJointState(const std::vector<std::string>& names, const std::vector<double>& positions,
                    const std::vector<double>& velocities, Stamp stamp, Stamp now);
  /// A planned trajectory (the monitor's ~trajectory_topic): "" when in force, else why not.
  std::string onTrajectory(const PlannedTrajectory& trajectory, Stamp now);
  /// Forgets every reading and the plan.
  void reset();

  /// Poses every claimed body at `stamp`, its root frame at `root` (fixed frame at `stamp`):
  /// links[i] (indexed as `robot`) gets its shape, pose, speed and gap; a body that cannot be
  /// posed is left untouched and why(i) says why ("" when posed). Returns the number posed.
  int poseAt(Stamp stamp, const Eigen::Isometry3d& root, SelfLink* links);
  const std::string& why(int i) const { return why_[static_cast<std::size_t>(i)]; }

 private:
  struct Reading {
    Stamp stamp = 0;
    double position = 0.0;
    double velocity = 0.0;  // NaN: not measured
  };
  // The joint's readings, oldest first, in a ring of `history_`.
  const Reading& reading(int joint, int k) const;
  int count(int joint) const { return count_[static_cast<std::size_t>(joint)]; }
  // Joint j at `stamp`: position, speed bound, gap; "" or why not.
  std::string jointAt(int j, Stamp stamp, double* q, double* speed, double* gap) const;

  JointPredictor predictor_;
  int history_;
  std::vector<Reading> readings_;   // joints x history_
  std::vector<int> first_;          // per joint: ring index of the oldest
  std::vector<int> count_;          // per joint
  std::vector<int> link_of_;        // per robot body: model link, or -1
  std::vector<Shape> shape_;        // per robot body
  std::vector<Eigen::Isometry3d> offset_;  // per robot body
  std::vector<std::vector<double>> lever_;  // per robot body: per chain joint, m (1 for sliding)
  std::vector<int> body_of_;        // per predictor body: robot body
  std::vector<std::string> why_;    // per robot body
  int claimed_ = 0;
  // Per poseAt, reused.
  std::vector<double> q_, speed_, gap_;
  std::vector<std::uint8_t> predicted_;  // per joint: after its newest reading
  std::vector<std::string> joint_why_;
  std::vector<Eigen::Isometry3d> poses_;  // per model link
};

}  // namespace perception
}  // namespace workspace_proximity
