#include "workspace_proximity/rules/ssm_cycle.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string_view>

#include "workspace_proximity/rules/robot_bodies.hpp"
#include "workspace_proximity/rules/track_table.hpp"

namespace workspace_proximity {
namespace {

bool listed(const std::vector<std::string>& labels, const std::string& label) {
  return labels.empty() || std::find(labels.begin(), labels.end(), label) != labels.end();
}

// The label's least approach speed for this track: ssm_min_speed while its velocity is not
// known; once known (measured, its own error added) at most ssm_min_speed_measured.
double approachFloor(const LabelSettings& label, const TrackErrors& own) {
  return own.velocity_known ? std::min(label.ssm_min_speed, label.ssm_min_speed_measured)
                            : label.ssm_min_speed;
}

// The fastest the object can approach anything: its tracked speed (plus its tracker's own
// velocity error), or its label's minimum. A track without a known velocity has nominal
// velocity 0 here: its label's minimum is its approach speed.
double fastestApproach(const BodyMotion& motion, const LabelSettings& label,
                       const TrackErrors& own) {
  const double error = own.velocity_known ? own.velocity_error : 0.0;
  return std::max(motion.linear_velocity.norm() + error, approachFloor(label, own));
}

// m: how much a track's own position error exceeds the sensor uncertainty Z_d that S_p already
// holds (the label's position_error is for the growth model; Z_d is the site's figure).
double extraUncertainty(const SsmParams& p, const TrackErrors& own) {
  return std::max(0.0, own.position_error - p.sensor_uncertainty);
}

}  // namespace

LatchParams latchParams(const SsmParams& p) {
  LatchParams l;
  l.manual = p.restart == "manual";
  l.min_stop_time = p.min_stop_time;
  l.stop_category = p.stop_category;
  l.standstill_speed = p.standstill_speed;
  l.standstill_time = p.standstill_time;
  l.max_mute_time = p.max_mute_time;
  return l;
}

SsmCycle::SsmCycle(const SsmParams& params)
    : params_(params), filter_(params), latch_(latchParams(params)) {}

void SsmCycle::setParams(const SsmParams& params) {
  params_ = params;
  filter_.setParams(params);
  latch_.setParams(latchParams(params));
}

void SsmCycle::prepare(const TrackTable& tracks, const LabelTable& labels,
                              const RobotBodies& robot, ProximityWorld* world) {
  std::fill(monitored_.begin(), monitored_.end(), 0);
  reach_ = 0.0;
  if (params_.enabled) {
    for (int i = 0; i < tracks.size(); ++i) {
      const Track& t = tracks.track(i);
      if (!listed(params_.labels, t.label)) continue;
      const auto slot = static_cast<std::size_t>(t.handle.index);
      if (slot >= monitored_.size()) monitored_.resize(slot + 1, 0);  // grows with the slots only
      monitored_[slot] = 1;
      const double v_h =
          fastestApproach(world->motion(t.handle), labels.settings(t.settings), t.errors);
      reach_ = std::max(reach_, protectiveSeparation(params_, v_h, params_.robot_max_speed) +
                                    extraUncertainty(params_, t.errors));
    }
  }
  // The core refuses reaches beyond its size limit; such a reach would cover the whole cell.
  reach_ = std::min(reach_, Limits::kMaxSize);
  for (int i = 0; i < robot.size(); ++i) {
    if (robot.present(i)) world->setReach(robot.handle(i), reach_);
  }
}

void SsmCycle::evaluate(Stamp now, const ProximityWorld& world, const TrackTable& tracks,
                               const LabelTable& labels, const RobotBodies& robot, bool degraded,
                               const std::vector<std::string>& status_lines, SsmVerdict* out) {
  if (!startVerdict(1.0, degraded, out)) return;
  latch_.expireMute(now);  // a mute whose time is up lowers the scale in this very cycle
  // Which tracks are muted this cycle (the pairs below and the markers read it).
  std::fill(muted_.begin(), muted_.end(), 0);
  if (latch_.state().muted) {
    for (int i = 0; i < tracks.size(); ++i) {
      const Track& t = tracks.track(i);
      const auto slot = static_cast<std::size_t>(t.handle.index);
      if (!latch_.muted(t.label, world.desc(t.handle).id)) continue;
      if (slot >= muted_.size()) muted_.resize(slot + 1, 0);  // grows with the slots only
      muted_[slot] = 1;
    }
  }
  out->muted_slots = &muted_;
  double best_slack = std::numeric_limits<double>::infinity();
  for (const NearPair& near : world.nearPairs()) {
    // A robot body and a monitored track, in either order.
    const bool robot_first = robot.robotOfSlot(near.body_a.index) >= 0;
    const BodyHandle r = robot_first ? near.body_a : near.body_b;
    const BodyHandle o = robot_first ? near.body_b : near.body_a;
    if (robot.robotOfSlot(r.index) < 0) continue;
    const int track = tracks.trackOfSlot(o.index);
    const auto slot = static_cast<std::size_t>(o.index);
    if (track < 0 || slot >= monitored_.size() || !monitored_[slot]) continue;
    ++out->pairs;
    const Eigen::Vector3d& p_robot = robot_first ? near.point_a : near.point_b;
    const Eigen::Vector3d& p_object = robot_first ? near.point_b : near.point_a;
    // The direction from the object's nearest point to the robot's; for touching or
    // overlapping shapes the contact normal, turned to point from the object to the robot.
    Eigen::Vector3d towards = p_robot - p_object;
    const double length = towards.norm();
    if (near.distance > 0.0 && length > 1e-9) {
      towards /= length;
    } else {
      towards = robot_first ? Eigen::Vector3d(-near.normal) : near.normal;
    }
    const Track& object = tracks.track(track);
    const LabelSettings& label = labels.settings(object.settings);
    // Its tracker's own errors, when it gave them: the approach may be faster by the velocity
    // error (not for an unknown velocity: nominal 0, the label's minimum rules), and the
    // object nearer by what its position error exceeds Z_d.
    const TrackErrors& own = object.errors;
    const double along = world.motion(o).linear_velocity.dot(towards) +
                         (own.velocity_known ? own.velocity_error : 0.0);
    const double v_h = std::max({0.0, along, approachFloor(label, own)});
    const double extra = extraUncertainty(params_, own);
    const double required = protectiveSeparation(params_, v_h, params_.robot_max_speed) + extra;
    const double slack = near.distance - required;
    if (slack < 0.0) ++out->within;  // muted or not: resets and mutes are judged on every pair
    if (slot < muted_.size() && muted_[slot]) {
      ++out->muted_pairs;  // reported as contacts still, but not lowering the scale
      continue;
    }
    out->raw_scale = std::min(out->raw_scale, pairScale(params_, near.distance - extra, v_h));
    if (slack < best_slack) {
      best_slack = slack;
      out->limited = true;
      out->robot = r;
      out->object = o;
      out->separation = near.distance;
      out->required_separation = required;
      out->approach_speed = v_h;
      out->point_robot = p_robot;
      out->point_object = p_object;
    }
  }

  out->degraded = degraded;
  if (degraded) {
    std::snprintf(buffer_, sizeof buffer_, "DEGRADED, scale at most %.2f: ", params_.degraded_scale);
    out->reason.assign(buffer_);
    out->reason.append(status_lines.empty() ? std::string_view("?") : std::string_view(status_lines.front()));
  } else if (out->limited) {
    // "person_1 at 0.83 m from link_2, full speed needs 1.11 m (approach 1.00 m/s)"
    out->reason.assign(out->raw_scale < 1.0 ? "" : "clear: ").append(world.desc(out->object).id);
    std::snprintf(buffer_, sizeof buffer_, " at %.2f m from ", out->separation);
    out->reason.append(buffer_).append(world.desc(out->robot).id);
    std::snprintf(buffer_, sizeof buffer_, ", full speed needs %.2f m (approach %.2f m/s)",
                  out->required_separation, out->approach_speed);
    out->reason.append(buffer_);
  } else {
    out->reason.assign("clear: no monitored object within reach");
  }
  output(now, degraded, out);
}

void SsmCycle::failed(Stamp now, const std::string& why, SsmVerdict* out) {
  // Nothing is known: the raw scale is what DEGRADED allows.
  if (!startVerdict(params_.degraded_scale, true, out)) return;
  std::snprintf(buffer_, sizeof buffer_, "DEGRADED, scale at most %.2f: cycle failed: ",
                params_.degraded_scale);
  out->reason.assign(buffer_).append(why);
  output(now, true, out);
}

bool SsmCycle::startVerdict(double raw_scale, bool degraded, SsmVerdict* out) const {
  out->enabled = params_.enabled;
  out->raw_scale = raw_scale;
  out->pairs = 0;
  out->limited = false;
  out->separation = std::numeric_limits<double>::infinity();
  out->required_separation = 0.0;
  out->approach_speed = 0.0;
  out->within = 0;
  out->muted_pairs = 0;
  out->degraded = degraded;
  if (params_.enabled) return true;
  // Off: the verdict is final, the robot at full speed whatever the cycle saw.
  out->speed_scale = 1.0;
  out->reason.assign("speed and separation monitoring is off (~ssm/enabled)");
  return false;
}

void SsmCycle::output(Stamp now, bool degraded, SsmVerdict* out) {
  // While DEGRADED the prediction rests on data that may be missing or old: never more than
  // degraded_scale. The filter drops at once and rises slowly, also after a DEGRADED spell.
  double target = degraded ? std::min(out->raw_scale, params_.degraded_scale) : out->raw_scale;
  // The latch holds the filter at 0 after a stop (minimum off time, restart interlock): once
  // released, the filter rises from 0 by its usual hold and rate.
  if (latch_.begin(now)) target = 0.0;
  out->speed_scale = filter_.update(now, target);
  if (out->speed_scale < target) {
    std::snprintf(buffer_, sizeof buffer_, "; rising to %.2f (after %.1f s, at most %.2f/s)",
                  target, params_.hold_time, params_.max_increase_rate);
    out->reason.append(buffer_);
  }
  latch_.end(now, out->speed_scale, degraded, out->within, out->reason);
  const LatchState& latch = latch_.state();
  if (latch.hold == "reset") {
    out->reason.append("; held at 0 until a reset is accepted (~reset)");
  } else if (latch.hold == "min_stop_time") {
    out->reason.append("; held at 0 for the minimum stop time (~ssm/min_stop_time)");
  }
  if (!latch_.haltWait().empty()) out->reason.append("; ").append(latch_.haltWait());
  if (latch.muted) {
    std::snprintf(buffer_, sizeof buffer_, "; muted for %.1f s more (%d pairs): ", latch.mute_left,
                  out->muted_pairs);
    out->reason.append(buffer_).append(latch.mute_scope);
  }
  out->latch = &latch;
  out->latch_events = &latch_.events();
}

}  // namespace workspace_proximity
