#include "workspace_proximity/rules/trajectory_retimer.hpp"

#include <algorithm>
#include <cmath>

namespace workspace_proximity {

const char* planRejectionName(PlanRejection r) {
  switch (r) {
    case PlanRejection::kNone: return "none";
    case PlanRejection::kNoJoints: return "no joint names";
    case PlanRejection::kTooManyJoints: return "more joints than the relay's capacity";
    case PlanRejection::kNoPoints: return "no points";
    case PlanRejection::kTooManyPoints: return "more points than the relay's capacity (~max_points)";
    case PlanRejection::kSizeMismatch: return "a point's positions, velocities or accelerations do not match the joint names";
    case PlanRejection::kMixedDerivatives: return "velocities or accelerations on some points but not on all";
    case PlanRejection::kNotFinite: return "a value is NaN or infinite";
    case PlanRejection::kFirstTimeNotZero: return "the first point's time_from_start is not 0";
    case PlanRejection::kTimesNotIncreasing: return "time_from_start does not strictly increase";
  }
  return "unknown";
}

TrajectoryRetimer::TrajectoryRetimer(const TrajectoryRetimerCapacity& capacity, double horizon,
                                     double hold_time)
    : capacity_(capacity), horizon_(horizon), hold_time_(hold_time) {
  const std::size_t values =
      static_cast<std::size_t>(capacity.max_joints) * static_cast<std::size_t>(capacity.max_points);
  for (std::vector<double>* v : {&pos_, &vel_, &acc_, &next_pos_, &next_vel_, &next_acc_}) {
    v->assign(values, 0.0);
  }
  times_.assign(capacity.max_points, 0.0);
  next_times_.assign(capacity.max_points, 0.0);
  // A chunk: the state at s, the plan's points, the state at its end.
  const std::size_t chunk_points = static_cast<std::size_t>(capacity.max_points) + 2;
  chunk_.times.assign(chunk_points, 0.0);
  chunk_.positions.assign(chunk_points * capacity.max_joints, 0.0);
  chunk_.velocities.assign(chunk_points * capacity.max_joints, 0.0);
  chunk_.accelerations.assign(chunk_points * capacity.max_joints, 0.0);
  q_.assign(capacity.max_joints, 0.0);
  dq_.assign(capacity.max_joints, 0.0);
  ddq_.assign(capacity.max_joints, 0.0);
}

PlanRejection TrajectoryRetimer::beginPlan(int joints, int points, bool has_velocities,
                                           bool has_accelerations) {
  next_joints_ = 0;
  next_count_ = 0;
  if (joints <= 0) return PlanRejection::kNoJoints;
  if (joints > capacity_.max_joints) return PlanRejection::kTooManyJoints;
  if (points <= 0) return PlanRejection::kNoPoints;
  if (points > capacity_.max_points) return PlanRejection::kTooManyPoints;
  next_joints_ = joints;
  next_count_ = points;
  next_has_vel_ = has_velocities;
  // Accelerations only refine a cubic: without velocities they are not used.
  next_has_acc_ = has_velocities && has_accelerations;
  return PlanRejection::kNone;
}

void TrajectoryRetimer::setPoint(int index, double time, const double* positions,
                                 const double* velocities, const double* accelerations) {
  if (index < 0 || index >= next_count_) return;
  next_times_[index] = time;
  const std::size_t base = static_cast<std::size_t>(index) * next_joints_;
  for (int j = 0; j < next_joints_; ++j) {
    next_pos_[base + j] = positions[j];
    next_vel_[base + j] = next_has_vel_ ? velocities[j] : 0.0;
    next_acc_[base + j] = next_has_acc_ ? accelerations[j] : 0.0;
  }
}

PlanRejection TrajectoryRetimer::finishPlan() {
  if (next_count_ <= 0) return PlanRejection::kNoPoints;
  const std::size_t values = static_cast<std::size_t>(next_count_) * next_joints_;
  for (std::size_t k = 0; k < values; ++k) {
    if (!std::isfinite(next_pos_[k]) || !std::isfinite(next_vel_[k]) ||
        !std::isfinite(next_acc_[k])) {
      return PlanRejection::kNotFinite;
    }
  }
  for (int i = 0; i < next_count_; ++i) {
    if (!std::isfinite(next_times_[i])) return PlanRejection::kNotFinite;
  }
  // Planned time 0 is the plan's start: a first point later than that would leave the motion
  // from wherever the arm is to it undefined.
  if (next_times_[0] != 0.0) return PlanRejection::kFirstTimeNotZero;
  for (int i = 1; i < next_count_; ++i) {
    if (!(next_times_[i] > next_times_[i - 1])) return PlanRejection::kTimesNotIncreasing;
  }
  std::swap(times_, next_times_);
  std::swap(pos_, next_pos_);
  std::swap(vel_, next_vel_);
  std::swap(acc_, next_acc_);
  joints_ = next_joints_;
  count_ = next_count_;
  has_vel_ = next_has_vel_;
  has_acc_ = next_has_acc_;
  next_count_ = 0;
  loaded_ = true;
  s_ = 0.0;
  last_scale_ = 0.0;
  return PlanRejection::kNone;
}

void TrajectoryRetimer::clear() {
  loaded_ = false;
  count_ = 0;
  s_ = 0.0;
  last_scale_ = 0.0;
}

int TrajectoryRetimer::segmentAt(double s) const {
  // The last i with times_[i] <= s, at most count_ - 2 (a segment needs two points).
  const auto end = times_.begin() + count_;
  int i = static_cast<int>(std::upper_bound(times_.begin(), end, s) - times_.begin()) - 1;
  return std::max(0, std::min(i, count_ - 2));
}

void TrajectoryRetimer::stateAt(double s, double* q, double* dq, double* ddq) const {
  if (!loaded_) return;
  if (count_ == 1 || s <= 0.0 || s >= times_[count_ - 1]) {
    const int k = (count_ == 1 || s <= 0.0) ? 0 : count_ - 1;
    const std::size_t b = static_cast<std::size_t>(k) * joints_;
    for (int j = 0; j < joints_; ++j) {
      q[j] = pos_[b + j];
      dq[j] = vel_[b + j];
      ddq[j] = acc_[b + j];
    }
    return;
  }
  const int i = segmentAt(s);
  const double T = times_[i + 1] - times_[i];
  const double u = (s - times_[i]) / T;
  const std::size_t b0 = static_cast<std::size_t>(i) * joints_;
  const std::size_t b1 = b0 + joints_;
  for (int j = 0; j < joints_; ++j) {
    const double p0 = pos_[b0 + j], p1 = pos_[b1 + j], h = p1 - p0;
    if (!has_vel_) {
      // Positions only: straight lines between the points (as the controller interpolates them).
      q[j] = p0 + h * u;
      dq[j] = h / T;
      ddq[j] = 0.0;
      continue;
    }
    const double v0 = vel_[b0 + j] * T, v1 = vel_[b1 + j] * T;  // per unit u
    double c[6] = {p0, v0, 0.0, 0.0, 0.0, 0.0};
    if (!has_acc_) {
      // Cubic Hermite.
      c[2] = 3.0 * h - 2.0 * v0 - v1;
      c[3] = -2.0 * h + v0 + v1;
    } else {
      // Quintic Hermite.
      const double a0 = acc_[b0 + j] * T * T, a1 = acc_[b1 + j] * T * T;
      c[2] = 0.5 * a0;
      c[3] = 10.0 * h - 6.0 * v0 - 4.0 * v1 - 1.5 * a0 + 0.5 * a1;
      c[4] = -15.0 * h + 8.0 * v0 + 7.0 * v1 + 1.5 * a0 - a1;
      c[5] = 6.0 * h - 3.0 * v0 - 3.0 * v1 - 0.5 * a0 + 0.5 * a1;
    }
    double p = 0.0, d = 0.0, dd = 0.0;
    for (int k = 5; k >= 0; --k) p = p * u + c[k];
    for (int k = 5; k >= 1; --k) d = d * u + k * c[k];
    for (int k = 5; k >= 2; --k) dd = dd * u + k * (k - 1) * c[k];
    q[j] = p;
    dq[j] = d / T;
    ddq[j] = dd / (T * T);
  }
}

void TrajectoryRetimer::appendState(double s, double wall_time, double scale, bool hold) {
  stateAt(s, q_.data(), dq_.data(), ddq_.data());
  const int n = chunk_.count++;
  chunk_.times[n] = wall_time;
  const std::size_t b = static_cast<std::size_t>(n) * joints_;
  for (int j = 0; j < joints_; ++j) {
    chunk_.positions[b + j] = q_[j];
    // d/dt of q(s(t)) with ds/dt = scale: velocities times scale, accelerations times scale^2.
    chunk_.velocities[b + j] = hold ? 0.0 : dq_[j] * scale;
    chunk_.accelerations[b + j] = hold ? 0.0 : ddq_[j] * scale * scale;
  }
}

const RetimedChunk& TrajectoryRetimer::tick(double dt, double scale) {
  chunk_.count = 0;
  chunk_.kind = ChunkKind::kNothing;
  if (!loaded_) return chunk_;
  if (!(scale > 0.0)) scale = 0.0;  // NaN too
  scale = std::min(scale, 1.0);
  const double end = times_[count_ - 1];
  // The controller ran the last chunk at last_scale_ for dt: that much of the plan is done.
  if (dt > 0.0) s_ = std::min(end, s_ + last_scale_ * dt);
  chunk_.joints = joints_;
  chunk_.has_velocities = has_vel_;
  chunk_.has_accelerations = has_acc_;
  if (s_ >= end) {
    // The last chunk ended at the final point and the controller holds there.
    last_scale_ = 0.0;
    return chunk_;
  }
  last_scale_ = scale;
  if (scale == 0.0) {
    chunk_.kind = ChunkKind::kHold;
    appendState(s_, hold_time_, 0.0, true);
    return chunk_;
  }
  chunk_.kind = ChunkKind::kMotion;
  const double s_end = std::min(end, s_ + scale * horizon_);
  appendState(s_, 0.0, scale, false);
  // The plan's own points strictly inside (s, s_end): copied, re-timed.
  for (int i = segmentAt(s_) + 1; i < count_ && times_[i] < s_end; ++i) {
    if (times_[i] <= s_) continue;
    const int n = chunk_.count++;
    chunk_.times[n] = (times_[i] - s_) / scale;
    const std::size_t b = static_cast<std::size_t>(n) * joints_;
    const std::size_t p = static_cast<std::size_t>(i) * joints_;
    for (int j = 0; j < joints_; ++j) {
      chunk_.positions[b + j] = pos_[p + j];
      chunk_.velocities[b + j] = vel_[p + j] * scale;
      chunk_.accelerations[b + j] = acc_[p + j] * scale * scale;
    }
  }
  appendState(s_end, (s_end - s_) / scale, scale, false);
  return chunk_;
}

}  // namespace workspace_proximity
