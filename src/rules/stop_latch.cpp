#include "workspace_proximity/rules/stop_latch.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace workspace_proximity {
namespace {

constexpr std::size_t kReasonCapacity = 256;

void appendList(std::string* out, const char* title, const std::vector<std::string>& names) {
  if (names.empty()) return;
  if (!out->empty()) out->append("; ");
  out->append(title);
  for (std::size_t i = 0; i < names.size(); ++i) {
    out->append(i == 0 ? " " : ", ").append(names[i]);
  }
}

}  // namespace

const char* latchEventName(LatchEventKind kind) {
  switch (kind) {
    case LatchEventKind::kStop: return "stop";
    case LatchEventKind::kReleased: return "released";
    case LatchEventKind::kResetAccepted: return "reset_accepted";
    case LatchEventKind::kResetRefused: return "reset_refused";
    case LatchEventKind::kMuteStarted: return "mute_started";
    case LatchEventKind::kMuteRefused: return "mute_refused";
    case LatchEventKind::kMuteEnded: return "mute_ended";
    case LatchEventKind::kHaltRequested: return "halt_requested";
  }
  return "?";
}

LatchEvents::LatchEvents() {
  for (LatchEvent& e : events_) e.reason.reserve(kReasonCapacity);
}

void LatchEvents::add(LatchEventKind kind, const std::string& reason) {
  if (count_ == kCapacity) {
    // Full: the last slot keeps counting what could not be kept (never silently lost).
    ++lost_;
    LatchEvent& last = events_[kCapacity - 1];
    char text[96];
    std::snprintf(text, sizeof text, "%d more latch events this cycle not kept", lost_);
    last.reason.assign(text);
    return;
  }
  LatchEvent& e = events_[static_cast<std::size_t>(count_++)];
  e.kind = kind;
  e.reason.assign(reason);
}

StopLatch::StopLatch(const LatchParams& params) : params_(params) {
  text_.reserve(kReasonCapacity);
  halt_wait_.reserve(kReasonCapacity);
  state_.hold.reserve(16);
  state_.mute_scope.reserve(kReasonCapacity);
}

void StopLatch::noteJointSpeed(Stamp stamp, double max_abs_speed, bool known) {
  known = known && std::isfinite(max_abs_speed);
  const bool still = known && max_abs_speed < params_.standstill_speed;
  if (!still) {
    still_since_ = -1;
  } else if (still_since_ < 0 || !speed_seen_ || stamp < speed_stamp_) {
    still_since_ = stamp;
  }
  speed_known_ = known;
  speed_seen_ = true;
  speed_stamp_ = stamp;
}

bool StopLatch::lastCycleRefuses(const char* action, std::string* why) const {
  // Resets and mutes alike rest on the last cycle; unknown is never clear.
  if (last_degraded_) {
    why->assign(action).append(" refused: status DEGRADED (unknown is never clear)");
    return true;
  }
  if (last_within_ > 0) {
    char text[160];
    std::snprintf(text, sizeof text,
                  "%s refused: %d monitored pair(s) within the protective separation S_p(v_max)",
                  action, last_within_);
    why->assign(text);
    return true;
  }
  return false;
}

bool StopLatch::requestReset(Stamp /*now*/, std::string* why) {
  // Acceptance rests on the last cycle: its status must be OK and no monitored pair may be
  // within its protective separation at full speed (muted pairs included).
  if (!state_.reset_required) {
    why->assign("nothing to reset: no stop is waiting for a reset");
    return true;
  }
  if (!seen_cycle_) {
    why->assign("reset refused: no cycle has run yet");
  } else if (!lastCycleRefuses("reset", why)) {
    state_.reset_required = false;
    why->assign("reset accepted: the scale rises after the hold");
    if (params_.min_stop_time > 0.0) why->append(" and the minimum stop time");
    pending_.add(LatchEventKind::kResetAccepted, *why);
    return true;
  }
  pending_.add(LatchEventKind::kResetRefused, *why);
  return false;
}

bool StopLatch::requestMute(Stamp now, const std::vector<std::string>& labels,
                            const std::vector<std::string>& ids, double duration,
                            std::string* why) {
  char text[200];
  bool ok = false;
  if (!(params_.max_mute_time > 0.0)) {
    why->assign("mute refused: muting is off (~ssm/max_mute_time is 0)");
  } else if (labels.empty() && ids.empty()) {
    why->assign("mute refused: name at least one label or id");
  } else if (std::any_of(labels.begin(), labels.end(), [](const std::string& s) { return s.empty(); }) ||
             std::any_of(ids.begin(), ids.end(), [](const std::string& s) { return s.empty(); })) {
    why->assign("mute refused: an empty label or id");
  } else if (!(duration > 0.0) || !std::isfinite(duration)) {
    std::snprintf(text, sizeof text, "mute refused: duration %g s is not a positive time", duration);
    why->assign(text);
  } else if (state_.muted) {
    why->assign("mute refused: already muted (").append(state_.mute_scope).append(")");
  } else if (!seen_cycle_) {
    why->assign("mute refused: no cycle has run yet");
  } else if (state_.stopped || last_scale_ <= 0.0) {
    why->assign("mute refused: the speed scale is 0 (protective stop)");
  } else {
    ok = !lastCycleRefuses("mute", why);
  }
  if (!ok) {
    pending_.add(LatchEventKind::kMuteRefused, *why);
    return false;
  }
  const double granted = std::min(duration, params_.max_mute_time);
  mute_labels_ = labels;
  mute_ids_ = ids;
  mute_until_ = now + nanoseconds(granted);
  state_.muted = true;
  state_.mute_left = granted;
  describeScope();
  std::snprintf(text, sizeof text, "muted for %.1f s%s: ", granted,
                granted < duration ? " (cut to ~ssm/max_mute_time)" : "");
  why->assign(text).append(state_.mute_scope);
  pending_.add(LatchEventKind::kMuteStarted, *why);
  return true;
}

bool StopLatch::muted(const std::string& label, const std::string& id) const {
  if (!state_.muted) return false;
  return std::find(mute_labels_.begin(), mute_labels_.end(), label) != mute_labels_.end() ||
         std::find(mute_ids_.begin(), mute_ids_.end(), id) != mute_ids_.end();
}

void StopLatch::describeScope() {
  state_.mute_scope.clear();
  appendList(&state_.mute_scope, "labels", mute_labels_);
  appendList(&state_.mute_scope, "ids", mute_ids_);
}

void StopLatch::endMute(const char* why) {
  if (!state_.muted) return;
  state_.muted = false;
  state_.mute_left = 0.0;
  text_.assign("mute ended (").append(why).append("): ").append(state_.mute_scope);
  // Before begin() (the cycle's rule ends a mute whose time is up) it waits with the requests.
  (in_cycle_ ? events_ : pending_).add(LatchEventKind::kMuteEnded, text_);
  state_.mute_scope.clear();
}

void StopLatch::expireMute(Stamp now) {
  if (!state_.muted) return;
  if (now >= mute_until_) {
    endMute("time up");
  } else {
    state_.mute_left = secondsBetween(now, mute_until_);
  }
}

bool StopLatch::begin(Stamp now) {
  // This cycle's events: the requests since the last cycle first.
  events_.clear();
  for (int i = 0; i < pending_.size(); ++i) events_.add(pending_[i].kind, pending_[i].reason);
  pending_.clear();
  in_cycle_ = true;
  expireMute(now);
  if (state_.stopped && stop_since_ < 0) stop_since_ = now;  // after a clock jump
  const bool min_time = state_.stopped && now < stop_since_ + nanoseconds(params_.min_stop_time);
  const bool reset = state_.stopped && state_.reset_required;
  const bool held = min_time || reset;
  if (state_.held && !held) {
    events_.add(LatchEventKind::kReleased,
                params_.manual ? "hold released: reset accepted and minimum stop time over"
                               : "hold released: minimum stop time over");
  }
  state_.held = held;
  state_.hold.assign(reset ? "reset" : min_time ? "min_stop_time" : "");
  return held;
}

void StopLatch::end(Stamp now, double scale, bool degraded, int within, const std::string& reason) {
  seen_cycle_ = true;
  last_scale_ = scale;
  last_degraded_ = degraded;
  last_within_ = within;
  // The start is no stop (the filter starts at 0): a stop is the scale reaching 0 after it was
  // above 0.
  if (scale <= 0.0 && !state_.stopped && ran_) {
    state_.stopped = true;
    state_.halt_requested = false;
    state_.reset_required = params_.manual;
    stop_since_ = now;
    text_.assign("protective stop: ").append(reason);
    events_.add(LatchEventKind::kStop, text_);
    // A mute never outlasts a stop: muting is for running next to a known object, and the
    // restart is judged on every object.
    endMute("protective stop");
    // The stop holds from this cycle on.
    state_.held = params_.min_stop_time > 0.0 || state_.reset_required;
    state_.hold.assign(state_.reset_required ? "reset" : state_.held ? "min_stop_time" : "");
  } else if (scale > 0.0) {
    ran_ = true;
  }
  // Manual restart: someone within reach again after an accepted reset, before the scale rose,
  // is a new intrusion: the interlock is armed again.
  if (state_.stopped && params_.manual && !state_.reset_required && scale <= 0.0 && within > 0) {
    state_.reset_required = true;
    state_.held = true;
    state_.hold.assign("reset");
    text_.assign("protective stop (again before the restart): ").append(reason);
    events_.add(LatchEventKind::kStop, text_);
  }
  if (scale > 0.0 && state_.stopped) {
    state_.stopped = false;  // released and risen: running again
    state_.halt_requested = false;
    stop_since_ = -1;
  }
  if (state_.stopped) {
    updateHalt(now);
  } else {
    halt_wait_.clear();
  }
  in_cycle_ = false;
}

void StopLatch::updateHalt(Stamp now) {
  halt_wait_.clear();
  if (params_.stop_category != 1 || state_.halt_requested) return;
  // Category 1: the halt (brakes, drives off) only once the robot stands still.
  char text[160];
  if (!speed_seen_ || secondsBetween(speed_stamp_, now) > kJointSpeedStale) {
    halt_wait_.assign("halt waits for standstill: no recent joint speeds (unknown is not standstill)");
    return;
  }
  if (!speed_known_) {
    halt_wait_.assign("halt waits for standstill: a joint speed is not measured (unknown is not standstill)");
    return;
  }
  if (still_since_ < 0) {
    std::snprintf(text, sizeof text, "halt waits for standstill: a joint moves at %.3g or faster",
                  params_.standstill_speed);
    halt_wait_.assign(text);
    return;
  }
  // Standing counts from the stop at the earliest.
  const Stamp from = std::max(still_since_, stop_since_ < 0 ? now : stop_since_);
  const double stood = secondsBetween(from, now);
  if (stood < params_.standstill_time) {
    std::snprintf(text, sizeof text, "halt waits for standstill: still for %.2f of %.2f s", stood,
                  params_.standstill_time);
    halt_wait_.assign(text);
    return;
  }
  state_.halt_requested = true;
  std::snprintf(text, sizeof text,
                "halt requested: every joint below %.3g for %.2f s after the stop",
                params_.standstill_speed, stood);
  events_.add(LatchEventKind::kHaltRequested, text);
}

void StopLatch::reset() {
  stop_since_ = -1;
  still_since_ = -1;
  speed_seen_ = false;
  seen_cycle_ = false;
  endMute("clock went back");
}

}  // namespace workspace_proximity
