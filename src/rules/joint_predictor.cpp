#include "workspace_proximity/rules/joint_predictor.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace workspace_proximity {
namespace {

// Knots closer than this (s) are one breakpoint.
constexpr double kSameTime = 1e-6;
// A horizon of 0 still gets a twist (for the closing speed now): the motion over this long.
constexpr double kShortestSpan = 1e-3;

bool turning(JointType type) { return type != JointType::kPrismatic; }

// A continuous joint's positions may wrap: the difference taken the short way round.
double jointDifference(const KinematicJoint& joint, double a, double b) {
  double d = a - b;
  if (joint.type == JointType::kContinuous) d = std::remainder(d, 2.0 * M_PI);
  return d;
}

std::string format(const char* fmt, const std::string& name, double value) {
  char buffer[256];
  std::snprintf(buffer, sizeof buffer, fmt, name.c_str(), value);
  return buffer;
}

}  // namespace

JointPredictor::JointPredictor(std::shared_ptr<const KinematicModel> model,
                               const JointPredictorParams& params)
    : model_(std::move(model)), params_(params) {
  if (!model_) throw std::invalid_argument("JointPredictor: no kinematic model");
  const std::size_t joints = model_->joints().size();
  readings_.resize(joints);
  joint_ok_.resize(joints);
  joint_why_.resize(joints);
  velocity_ok_.resize(joints);
  knots_.resize(joints);
  for (std::vector<Knot>& k : knots_) k.reserve(4);
  speeds_.resize(joints);
  q_.resize(joints);
  const std::size_t most = static_cast<std::size_t>(Limits::kMaxSegments) + 1;
  breaks_.reserve(2 * joints + 2);
  keyframes_.reserve(most);
  merged_.reserve(most);
  link_poses_.resize(most * std::max<std::size_t>(model_->links().size(), 1));
}

int JointPredictor::addBody(int link, const Eigen::Isometry3d& offset, double radius) {
  if (link < 0 || link >= static_cast<int>(model_->links().size())) {
    throw std::invalid_argument("JointPredictor::addBody: no such link");
  }
  const KinematicLink& l = model_->links()[static_cast<std::size_t>(link)];
  Body b;
  b.link = link;
  b.offset = offset;
  b.radius = radius;
  // From a joint's axis point to the body's farthest point: to the link origin, then to the
  // shape's centre, then its bounding radius.
  const double tail = offset.translation().norm() + radius;
  b.root_lever = l.root_reach + tail;
  for (double r : l.reach) b.lever.push_back(r + tail);
  b.path.segments.reserve(static_cast<std::size_t>(Limits::kMaxSegments));
  bodies_.push_back(std::move(b));
  const std::size_t most = static_cast<std::size_t>(Limits::kMaxSegments) + 1;
  segment_second_.resize(most * bodies_.size());
  segment_speed_.resize(most * bodies_.size());
  segment_turn_.resize(most * bodies_.size());
  return static_cast<int>(bodies_.size()) - 1;
}

void JointPredictor::observe(int joint, Stamp stamp, double position, double velocity) {
  if (joint < 0 || joint >= static_cast<int>(readings_.size()) || !std::isfinite(position)) return;
  Reading& r = readings_[static_cast<std::size_t>(joint)];
  if (r.seen && stamp < r.stamp) return;  // older than what we have
  if (std::isfinite(velocity)) {
    r.velocity = velocity;
    r.velocity_known = true;
  } else if (r.seen && stamp > r.stamp && secondsBetween(r.stamp, stamp) <= params_.state_timeout) {
    // Not measured: the finite difference with the previous reading.
    const KinematicJoint& j = model_->joints()[static_cast<std::size_t>(joint)];
    r.velocity = jointDifference(j, position, r.position) / secondsBetween(r.stamp, stamp);
    r.velocity_known = true;
  } else if (!(r.seen && stamp == r.stamp)) {
    r.velocity_known = false;  // the first reading, or one after a long gap
  }
  r.seen = true;
  r.stamp = stamp;
  r.position = position;
}

std::string JointPredictor::setPlan(JointPlan plan, Stamp now) {
  const std::vector<KinematicJoint>& joints = model_->joints();
  const std::size_t n = plan.joints.size();
  if (n == 0) return "it names no joint";
  for (std::size_t i = 0; i < n; ++i) {
    const int j = plan.joints[i];
    if (j < 0 || j >= static_cast<int>(joints.size())) return "a joint is not a movable joint of the robot model";
    for (std::size_t k = 0; k < i; ++k) {
      if (plan.joints[k] == j) return "joint '" + joints[static_cast<std::size_t>(j)].name + "' is listed twice";
    }
  }
  const std::size_t points = plan.times.size();
  if (points == 0) return "it has no points";
  if (plan.positions.size() != points * n) return "a point's positions do not match its joint names";
  for (std::size_t k = 0; k < points; ++k) {
    if (!std::isfinite(plan.times[k]) || plan.times[k] < 0.0) return "a point's time_from_start is negative or not finite";
    if (k > 0 && !(plan.times[k] > plan.times[k - 1])) return "its times are not strictly increasing";
  }
  for (double q : plan.positions) {
    if (!std::isfinite(q)) return "a position is not finite";
  }
  if (secondsBetween(plan.start, now) > plan.times.back()) {
    return format("it has ended (%s%.3f s ago)", "", secondsBetween(plan.start, now) - plan.times.back());
  }
  for (std::size_t k = 0; k < points; ++k) {
    for (std::size_t i = 0; i < n; ++i) {
      const KinematicJoint& j = joints[static_cast<std::size_t>(plan.joints[i])];
      double& q = plan.positions[k * n + i];
      if (j.limited) q = std::min(std::max(q, j.lower), j.upper);
    }
  }
  plan_ = std::move(plan);
  has_plan_ = true;
  return std::string();
}

void JointPredictor::reset() {
  for (Reading& r : readings_) r = Reading();
  has_plan_ = false;
}

double JointPredictor::planPosition(int p, double since_start) const {
  const std::size_t n = plan_.joints.size();
  const std::vector<double>& t = plan_.times;
  const auto at = [&](std::size_t k) { return plan_.positions[k * n + static_cast<std::size_t>(p)]; };
  if (since_start <= t.front()) return at(0);
  for (std::size_t k = 1; k < t.size(); ++k) {
    if (since_start <= t[k]) {
      const double s = (since_start - t[k - 1]) / (t[k] - t[k - 1]);
      return at(k - 1) + s * (at(k) - at(k - 1));
    }
  }
  return at(t.size() - 1);
}

void JointPredictor::checkPlan(Stamp now) {
  if (!has_plan_) return;
  if (secondsBetween(plan_.start, now) > plan_.times.back()) {
    has_plan_ = false;  // followed to its end: the readings take over
    plan_completed_ = true;
    return;
  }
  // The robot must be following it: every reading since its first point near the plan.
  for (std::size_t p = 0; p < plan_.joints.size(); ++p) {
    const int j = plan_.joints[p];
    const Reading& r = readings_[static_cast<std::size_t>(j)];
    if (!r.seen) continue;
    const double since = secondsBetween(plan_.start, r.stamp);
    if (since < plan_.times.front()) continue;
    const KinematicJoint& joint = model_->joints()[static_cast<std::size_t>(j)];
    const double off = std::abs(jointDifference(joint, r.position, planPosition(static_cast<int>(p), since)));
    if (off > params_.trajectory_tolerance) {
      char buffer[256];
      std::snprintf(buffer, sizeof buffer,
                    "joint '%s' is %.3f %s from the planned trajectory (more than "
                    "~trajectory_tolerance = %.3f): the robot is not following it",
                    joint.name.c_str(), off, turning(joint.type) ? "rad" : "m",
                    params_.trajectory_tolerance);
      plan_event_ = buffer;
      has_plan_ = false;
      return;
    }
  }
}

void JointPredictor::velocityKnots(int joint, double q_now, double velocity, double until,
                                   std::vector<Knot>* out) const {
  out->push_back(Knot{0.0, q_now});
  if (velocity == 0.0 || !(until > 0.0)) return;
  const KinematicJoint& j = model_->joints()[static_cast<std::size_t>(joint)];
  if (j.limited) {
    // It stops at its limit (extended to where it is, if a reading overshoots).
    const double position = readings_[static_cast<std::size_t>(joint)].position;
    const double limit = velocity > 0.0 ? std::max(j.upper, position) : std::min(j.lower, position);
    const double hit = (limit - q_now) / velocity;
    if (!(hit > 0.0)) return;  // at the limit already: it stays
    if (hit < until) {
      out->push_back(Knot{hit, limit});
      return;
    }
  }
  out->push_back(Knot{until, q_now + velocity * until});
}

void JointPredictor::buildKnots(Stamp now, double span) {
  const std::vector<KinematicJoint>& joints = model_->joints();
  for (std::size_t j = 0; j < joints.size(); ++j) {
    std::vector<Knot>& out = knots_[j];
    out.clear();
    const Reading& r = readings_[j];
    if (!joint_ok_[j]) {
      out.push_back(Knot{0.0, r.seen ? r.position : 0.0});
      continue;
    }
    // Where it is now: the reading moved on by its velocity (latency), within its limits.
    const double velocity = velocity_ok_[j] ? r.velocity : 0.0;
    double q_now = r.position + velocity * secondsBetween(r.stamp, now);
    if (joints[j].limited) {
      q_now = std::min(std::max(q_now, std::min(joints[j].lower, r.position)),
                       std::max(joints[j].upper, r.position));
    }
    int p = -1;
    if (has_plan_) {
      for (std::size_t k = 0; k < plan_.joints.size(); ++k) {
        if (plan_.joints[k] == static_cast<int>(j)) p = static_cast<int>(k);
      }
    }
    if (p < 0) {
      velocityKnots(static_cast<int>(j), q_now, velocity, span, &out);
      continue;
    }
    // Planned: as it moves until the plan starts, then straight to each point by its time.
    const double start_in = secondsBetween(now, plan_.start);
    if (start_in > 0.0) {
      velocityKnots(static_cast<int>(j), q_now, velocity, std::min(start_in, span), &out);
    } else if (-start_in >= plan_.times.front()) {
      // Past its first point: where the plan has it now. The reading (and its velocity) may
      // be from before a change of speed the plan made since, and would put the arm behind.
      out.push_back(Knot{0.0, planPosition(p, -start_in)});
    } else {
      out.push_back(Knot{0.0, q_now});  // on its way to the first point, from where it is
    }
    const std::size_t n = plan_.joints.size();
    for (std::size_t k = 0; k < plan_.times.size() && out.back().t < span; ++k) {
      const double t = start_in + plan_.times[k];
      if (t <= out.back().t) continue;
      const double q = plan_.positions[k * n + static_cast<std::size_t>(p)];
      if (t > span) {
        const Knot last = out.back();
        out.push_back(Knot{span, last.q + (q - last.q) * (span - last.t) / (t - last.t)});
      } else {
        out.push_back(Knot{t, q});
      }
    }
  }
}

double JointPredictor::positionAt(int joint, double t) const {
  const std::vector<Knot>& k = knots_[static_cast<std::size_t>(joint)];
  if (t <= k.front().t) return k.front().q;
  for (std::size_t i = 1; i < k.size(); ++i) {
    if (t <= k[i].t) return k[i - 1].q + (k[i].q - k[i - 1].q) * (t - k[i - 1].t) / (k[i].t - k[i - 1].t);
  }
  return k.back().q;
}

void JointPredictor::bounds(const Body& b, const std::vector<double>& speed, const BodyMotion& base,
                            double* second, double* speed_bound, double* turn_bound) const {
  const KinematicLink& link = model_->links()[static_cast<std::size_t>(b.link)];
  const std::vector<KinematicJoint>& joints = model_->joints();
  const std::size_t n = link.chain.size();
  // The root's motion is the first two joints of every chain: sliding at |v|, then turning
  // at |w| about an axis through the root's origin (the constant twist of BodyMotion).
  const double root_slide = base.linear_velocity.norm();
  const double root_turn = base.angular_velocity.norm();
  // Backwards: U_>=i, and the sum over turning i of s_i U_>=i.
  double suffix = 0.0, acceleration = 0.0;
  for (std::size_t k = n; k-- > 0;) {
    const double s = speed[static_cast<std::size_t>(link.chain[k])];
    const bool turns = turning(joints[static_cast<std::size_t>(link.chain[k])].type);
    suffix += turns ? s * b.lever[k] : s;
    if (turns) acceleration += s * suffix;
  }
  suffix += root_turn * b.root_lever;
  acceleration += root_turn * suffix;
  suffix += root_slide;
  // Forwards: the terms with W_<i.
  double before = root_turn;  // the sliding root sees no turn before it; the turning root none
  for (std::size_t k = 0; k < n; ++k) {
    const double s = speed[static_cast<std::size_t>(link.chain[k])];
    if (turning(joints[static_cast<std::size_t>(link.chain[k])].type)) {
      acceleration += 2.0 * s * before * b.lever[k];
      before += s;
    } else {
      acceleration += s * before;
    }
  }
  *second = acceleration + b.radius * before * before;
  *speed_bound = suffix;
  *turn_bound = before;
}

void JointPredictor::placeKeyframes(double span, const BodyMotion& base) {
  // Every joint's knots, merged: between two breaks every joint moves at a constant rate.
  breaks_.clear();
  breaks_.push_back(0.0);
  for (const std::vector<Knot>& knots : knots_) {
    for (const Knot& k : knots) {
      if (k.t > 0.0 && k.t < span) breaks_.push_back(k.t);
    }
  }
  breaks_.push_back(span);
  std::sort(breaks_.begin(), breaks_.end());
  std::size_t kept = 1;
  for (std::size_t i = 1; i < breaks_.size(); ++i) {
    if (breaks_[i] - breaks_[kept - 1] > kSameTime) breaks_[kept++] = breaks_[i];
  }
  breaks_.resize(kept);
  breaks_.back() = span;
  if (breaks_.size() < 2) breaks_.push_back(span);  // a span shorter than kSameTime

  const std::size_t intervals = breaks_.size() - 1;
  const std::size_t bodies = bodies_.size();
  const int budget = std::max(1, std::min(params_.max_segments, Limits::kMaxSegments));
  // Intervals beyond the budget are merged into the last segment.
  const std::size_t full = intervals > static_cast<std::size_t>(budget) ? static_cast<std::size_t>(budget) - 1 : intervals;

  // Keyframes per interval from the bound: dt^2 / 8 * K <= tolerance.
  keyframes_.clear();
  merged_.clear();
  int wanted_extra = 0;
  const int room = budget - static_cast<int>(full) - (full < intervals ? 1 : 0);
  for (int pass = 0; pass < 2; ++pass) {
    for (std::size_t i = 0; i < full; ++i) {
      const double length = breaks_[i + 1] - breaks_[i];
      for (std::size_t j = 0; j < speeds_.size(); ++j) {
        speeds_[j] = std::abs(positionAt(static_cast<int>(j), breaks_[i + 1]) -
                              positionAt(static_cast<int>(j), breaks_[i])) / length;
      }
      double worst = 0.0;
      std::size_t first_segment = keyframes_.size();
      for (std::size_t b = 0; b < bodies; ++b) {
        double second, speed, turn;
        bounds(bodies_[b], speeds_, base, &second, &speed, &turn);
        worst = std::max(worst, second);
        segment_second_[first_segment * bodies + b] = second;  // scratch in the first pass
        segment_speed_[first_segment * bodies + b] = speed;
        segment_turn_[first_segment * bodies + b] = turn;
      }
      int n = 1;
      if (worst > 0.0 && params_.path_tolerance > 0.0) {
        n = static_cast<int>(std::ceil(length * std::sqrt(worst / (8.0 * params_.path_tolerance))));
        n = std::max(1, std::min(n, budget));
      } else if (worst > 0.0) {
        n = budget;
      }
      if (pass == 0) {
        wanted_extra += n - 1;
        continue;
      }
      // Second pass: share the room left by the budget in proportion.
      if (wanted_extra > room) n = 1 + static_cast<int>(std::floor((n - 1) * static_cast<double>(room) / wanted_extra));
      for (int k = 0; k < n; ++k) {
        const std::size_t s = keyframes_.size();
        keyframes_.push_back(breaks_[i] + length * k / n);
        merged_.push_back(0);
        for (std::size_t b = 0; b < bodies; ++b) {
          segment_second_[s * bodies + b] = segment_second_[first_segment * bodies + b];
          segment_speed_[s * bodies + b] = segment_speed_[first_segment * bodies + b];
          segment_turn_[s * bodies + b] = segment_turn_[first_segment * bodies + b];
        }
      }
    }
    if (pass == 0) keyframes_.clear();
  }
  if (full < intervals) {
    // One segment over the remaining breaks: the largest speeds there, first-order bound.
    const std::size_t s = keyframes_.size();
    keyframes_.push_back(breaks_[full]);
    merged_.push_back(1);
    for (std::size_t b = 0; b < bodies; ++b) {
      segment_speed_[s * bodies + b] = 0.0;
      segment_turn_[s * bodies + b] = 0.0;
    }
    for (std::size_t i = full; i < intervals; ++i) {
      const double length = breaks_[i + 1] - breaks_[i];
      for (std::size_t j = 0; j < speeds_.size(); ++j) {
        speeds_[j] = std::abs(positionAt(static_cast<int>(j), breaks_[i + 1]) -
                              positionAt(static_cast<int>(j), breaks_[i])) / length;
      }
      for (std::size_t b = 0; b < bodies; ++b) {
        double second, speed, turn;
        bounds(bodies_[b], speeds_, base, &second, &speed, &turn);
        segment_speed_[s * bodies + b] = std::max(segment_speed_[s * bodies + b], speed);
        segment_turn_[s * bodies + b] = std::max(segment_turn_[s * bodies + b], turn);
      }
    }
  }
  keyframes_.push_back(span);
}

void JointPredictor::buildPaths(const BodyMotion& base) {
  const std::size_t links = model_->links().size();
  const std::size_t frames = keyframes_.size();
  // Forward kinematics at every keyframe.
  for (std::size_t k = 0; k < frames; ++k) {
    for (std::size_t j = 0; j < q_.size(); ++j) q_[j] = positionAt(static_cast<int>(j), keyframes_[k]);
    model_->forward(q_.data(), &link_poses_[k * links]);
  }
  const std::size_t bodies = bodies_.size();
  for (std::size_t b = 0; b < bodies; ++b) {
    Body& body = bodies_[b];
    JointBodyPath& out = body.path;
    out.segments.clear();
    out.why.clear();
    const KinematicLink& link = model_->links()[static_cast<std::size_t>(body.link)];
    out.state = JointPathState::kMoving;
    for (int j : link.chain) {
      if (!joint_ok_[static_cast<std::size_t>(j)]) {
        out.state = JointPathState::kUnknown;
        out.why = joint_why_[static_cast<std::size_t>(j)];
        break;
      }
      if (!velocity_ok_[static_cast<std::size_t>(j)] && out.state == JointPathState::kMoving) {
        out.state = JointPathState::kStale;
        out.why = joint_why_[static_cast<std::size_t>(j)];
      }
    }
    if (out.state == JointPathState::kUnknown) continue;
    const std::size_t segments = out.state == JointPathState::kStale ? 1 : frames - 1;
    Eigen::Isometry3d pose = base.poseAt(keyframes_[0]) * link_poses_[static_cast<std::size_t>(body.link)] * body.offset;
    for (std::size_t k = 0; k < segments; ++k) {
      MotionSegment s;
      s.start = keyframes_[k];
      s.motion.position = pose.translation();
      s.motion.orientation = Eigen::Quaterniond(pose.linear()).normalized();
      if (out.state == JointPathState::kStale) {
        out.segments.push_back(s);  // where it is now, motion unknown
        break;
      }
      const double dt = keyframes_[k + 1] - keyframes_[k];
      const Eigen::Isometry3d next = base.poseAt(keyframes_[k + 1]) *
                                     link_poses_[(k + 1) * links + static_cast<std::size_t>(body.link)] *
                                     body.offset;
      // The chord, and the mean turn about the centre.
      s.motion.linear_velocity = (next.translation() - pose.translation()) / dt;
      const Eigen::AngleAxisd turn(next.linear() * pose.linear().transpose());
      s.motion.angular_velocity = turn.angle() > 0.0 ? Eigen::Vector3d(turn.axis() * (turn.angle() / dt))
                                                     : Eigen::Vector3d::Zero();
      // How far the segment can be from the true motion.
      const double w = segment_turn_[k * bodies + b] * dt;
      s.margin = merged_[k] != 0
                     ? 0.5 * segment_speed_[k * bodies + b] * dt + body.radius * w * w / 8.0
                     : dt * dt / 8.0 * segment_second_[k * bodies + b];
      out.segments.push_back(s);
      pose = next;
    }
  }
}

void JointPredictor::predict(Stamp now, double horizon, const BodyMotion& base) {
  plan_event_.clear();
  plan_completed_ = false;
  checkPlan(now);
  const std::vector<KinematicJoint>& joints = model_->joints();
  for (std::size_t j = 0; j < joints.size(); ++j) {
    const Reading& r = readings_[j];
    joint_ok_[j] = 0;
    velocity_ok_[j] = 0;
    if (!r.seen) {
      // Say how to get out of it: a URDF without a joint_states publisher is a common set-up.
      joint_why_[j] = "no joint state for joint '" + joints[j].name +
                      "' yet (joint_states not published? ~use_joint_states: false poses the links from tf)";
      continue;
    }
    const double age = secondsBetween(r.stamp, now);
    if (age > params_.state_timeout) {
      joint_why_[j] = format("joint state of '%s' is %.3f s old (more than ~tf_timeout)", joints[j].name, age);
      continue;
    }
    joint_ok_[j] = 1;
    velocity_ok_[j] = r.velocity_known ? 1 : 0;
    if (!r.velocity_known) {
      joint_why_[j] = "velocity of joint '" + joints[j].name +
                      "' not known yet (no velocity in joint_states and one reading so far)";
    }
  }
  const double span = horizon > 0.0 ? horizon : kShortestSpan;
  buildKnots(now, span);
  placeKeyframes(span, base);
  buildPaths(base);
}

}  // namespace workspace_proximity
