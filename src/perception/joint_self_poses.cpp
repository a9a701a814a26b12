#include "workspace_proximity/perception/joint_self_poses.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace workspace_proximity {
namespace perception {
namespace {

// b - a for joint `joint`: the short way round for a continuous joint (positions may wrap).
double difference(const KinematicJoint& joint, double b, double a) {
  const double d = b - a;
  return joint.type == JointType::kContinuous ? std::remainder(d, 2.0 * M_PI) : d;
}

std::string format(const char* fmt, const std::string& name, double value) {
  char buffer[256];
  std::snprintf(buffer, sizeof buffer, fmt, name.c_str(), value);
  return buffer;
}

}  // namespace

JointSelfPoses::JointSelfPoses(std::shared_ptr<const KinematicModel> model,
                               const std::vector<RobotBodySpec>& robot,
                               const JointPredictorParams& params, int history)
    : predictor_(std::move(model), params), history_(std::max(2, history)) {
  const KinematicModel& m = predictor_.model();
  const std::size_t joints = m.joints().size();
  readings_.resize(joints * static_cast<std::size_t>(history_));
  first_.assign(joints, 0);
  count_.assign(joints, 0);
  q_.assign(joints, 0.0);
  speed_.assign(joints, 0.0);
  gap_.assign(joints, 0.0);
  predicted_.assign(joints, 0);
  joint_why_.resize(joints);
  poses_.resize(std::max<std::size_t>(m.links().size(), 1));
  link_of_.assign(robot.size(), -1);
  shape_.resize(robot.size());
  offset_.resize(robot.size());
  lever_.resize(robot.size());
  why_.resize(robot.size());
  for (std::size_t i = 0; i < robot.size(); ++i) {
    const int link = m.linkIndex(robot[i].frame);
    if (link < 0) continue;  // fixed to the root, or on another frame: tf
    link_of_[i] = link;
    shape_[i] = robot[i].shape;
    offset_[i] = robot[i].offset;
    // From a joint's axis point to the shape's farthest point: to the link origin, then to the
    // shape's centre, then its bounding radius (the predictor's lever arms).
    const KinematicLink& l = m.links()[static_cast<std::size_t>(link)];
    const double tail = robot[i].offset.translation().norm() + robot[i].shape.boundingRadius();
    for (std::size_t k = 0; k < l.chain.size(); ++k) {
      const bool slides = m.joints()[static_cast<std::size_t>(l.chain[k])].type == JointType::kPrismatic;
      lever_[i].push_back(slides ? 1.0 : l.reach[k] + tail);
    }
    ++claimed_;
  }
}

const JointSelfPoses::Reading& JointSelfPoses::reading(int joint, int k) const {
  const std::size_t j = static_cast<std::size_t>(joint);
  const int slot = (first_[j] + k) % history_;
  return readings_[j * static_cast<std::size_t>(history_) + static_cast<std::size_t>(slot)];
}

void JointSelfPoses::onJointState(const std::vector<std::string>& names,
                                  const std::vector<double>& positions,
                                  const std::vector<double>& velocities, Stamp stamp, Stamp now) {
  if (stamp == 0) stamp = now;
  const bool measured = velocities.size() == names.size();
  for (std::size_t k = 0; k < names.size() && k < positions.size(); ++k) {
    const int j = predictor_.model().jointIndex(names[k]);
    if (j < 0 || !std::isfinite(positions[k])) continue;
    const double v = measured ? velocities[k] : std::numeric_limits<double>::quiet_NaN();
    predictor_.observe(j, stamp, positions[k], v);
    const std::size_t ju = static_cast<std::size_t>(j);
    int& n = count_[ju];
    if (n > 0 && stamp < reading(j, n - 1).stamp) continue;  // older than the newest: ignored
    if (n > 0 && stamp == reading(j, n - 1).stamp) --n;      // the same instant again: replaced
    if (n == history_) {  // full: drop the oldest
      first_[ju] = (first_[ju] + 1) % history_;
      --n;
    }
    const int slot = (first_[ju] + n) % history_;
    readings_[ju * static_cast<std::size_t>(history_) + static_cast<std::size_t>(slot)] =
        Reading{stamp, positions[k], std::isfinite(v) ? v : std::numeric_limits<double>::quiet_NaN()};
    ++n;
  }
}

std::string JointSelfPoses::onTrajectory(const PlannedTrajectory& trajectory, Stamp now) {
  JointPlan plan;
  std::string why = toJointPlan(predictor_.model(), trajectory, now, &plan);
  if (why.empty()) why = predictor_.setPlan(std::move(plan), now);
  return why;
}

void JointSelfPoses::reset() {
  predictor_.reset();
  std::fill(first_.begin(), first_.end(), 0);
  std::fill(count_.begin(), count_.end(), 0);
}

std::string JointSelfPoses::jointAt(int j, Stamp stamp, double* q, double* speed, double* gap) const {
  const KinematicJoint& joint = predictor_.model().joints()[static_cast<std::size_t>(j)];
  const double timeout = predictor_.params().state_timeout;
  const int n = count(j);
  if (n == 0) return "no joint state for joint '" + joint.name + "' yet";
  const Reading& newest = reading(j, n - 1);
  if (stamp >= newest.stamp) {
    // After the newest reading: the predictor's motion model (predict() already ran at stamp).
    const double age = secondsBetween(newest.stamp, stamp);
    if (age > timeout) {
      return format("joint state of '%s' is %.3f s older than the frame's stamp (more than ~tf_timeout)",
                    joint.name, age);
    }
    double v = newest.velocity;
    if (!std::isfinite(v) && n >= 2) {
      // Not measured: the finite difference with the previous reading, as the predictor does.
      const Reading& before = reading(j, n - 2);
      const double dt = secondsBetween(before.stamp, newest.stamp);
      if (dt > 0.0 && dt <= timeout) v = difference(joint, newest.position, before.position) / dt;
    }
    if (!std::isfinite(v)) return "velocity of joint '" + joint.name + "' not known yet";
    *q = predictor_.jointPosition(j);
    *gap = age;
    // At least the model's own speed to get there (a plan may move it faster than the reading).
    *speed = std::abs(v);
    if (age > 0.0) *speed = std::max(*speed, std::abs(difference(joint, *q, newest.position)) / age);
    return std::string();
  }
  if (stamp < reading(j, 0).stamp) {
    return format("joint '%s': the frame's stamp is %.3f s before the oldest joint state kept",
                  joint.name, secondsBetween(stamp, reading(j, 0).stamp));
  }
  // Between two readings: the last one at or before the stamp, and the next.
  int k = n - 2;
  while (k > 0 && reading(j, k).stamp > stamp) --k;
  const Reading& a = reading(j, k);
  const Reading& b = reading(j, k + 1);
  const double span = secondsBetween(a.stamp, b.stamp);
  if (span > timeout) {
    return format("joint '%s' had no state for %.3f s around the frame's stamp (more than ~tf_timeout)",
                  joint.name, span);
  }
  const double d = secondsBetween(a.stamp, stamp);
  const double e = secondsBetween(stamp, b.stamp);
  const double step = difference(joint, b.position, a.position);
  *q = span > 0.0 ? a.position + step * (d / span) : b.position;
  // Whatever it did in between at most this fast, it is within speed x gap of the line.
  double s = span > 0.0 ? std::abs(step) / span : 0.0;
  if (std::isfinite(a.velocity)) s = std::max(s, std::abs(a.velocity));
  if (std::isfinite(b.velocity)) s = std::max(s, std::abs(b.velocity));
  *speed = s;
  *gap = span > 0.0 ? 2.0 * d * e / span : 0.0;
  return std::string();
}

int JointSelfPoses::poseAt(Stamp stamp, const Eigen::Isometry3d& root, SelfLink* links) {
  const KinematicModel& m = predictor_.model();
  const std::size_t joints = m.joints().size();
  // The predictor's motion model at the stamp, for the joints read before it.
  bool any_after = false;
  for (std::size_t j = 0; j < joints; ++j) {
    const int n = count(static_cast<int>(j));
    predicted_[j] = n > 0 && stamp >= reading(static_cast<int>(j), n - 1).stamp ? 1 : 0;
    any_after = any_after || predicted_[j] != 0;
  }
  if (any_after) predictor_.predict(stamp, 0.0, BodyMotion());
  for (std::size_t j = 0; j < joints; ++j) {
    const int ji = static_cast<int>(j);
    joint_why_[j] = jointAt(ji, stamp, &q_[j], &speed_[j], &gap_[j]);
    if (!joint_why_[j].empty()) {
      // Not used by any body posed below; somewhere for the forward kinematics to start.
      q_[j] = count(ji) > 0 ? reading(ji, count(ji) - 1).position : 0.0;
      speed_[j] = gap_[j] = 0.0;
    }
  }
  if (!m.links().empty()) m.forward(q_.data(), poses_.data());
  int posed = 0;
  for (std::size_t i = 0; i < link_of_.size(); ++i) {
    why_[i].clear();
    if (link_of_[i] < 0) continue;
    const KinematicLink& l = m.links()[static_cast<std::size_t>(link_of_[i])];
    double speed = 0.0, gap = 0.0;
    for (std::size_t k = 0; k < l.chain.size(); ++k) {
      const std::size_t j = static_cast<std::size_t>(l.chain[k]);
      if (!joint_why_[j].empty()) {
        why_[i] = joint_why_[j];
        break;
      }
      speed += speed_[j] * lever_[i][k];
      gap = std::max(gap, gap_[j]);
    }
    if (!why_[i].empty()) continue;
    SelfLink& out = links[i];
    out.shape = shape_[i];
    out.pose = root * poses_[static_cast<std::size_t>(link_of_[i])] * offset_[i];
    out.speed = speed;
    out.gap = gap;
    ++posed;
  }
  return posed;
}

}  // namespace perception
}  // namespace workspace_proximity
