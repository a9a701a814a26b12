#include "workspace_proximity/rules/cycle_trigger.hpp"

#include <algorithm>

namespace workspace_proximity {

void CycleTrigger::refill(Stamp now) {
  if (refilled_ == 0 || now < refilled_) {
    tokens_ = kBurst;  // the first cycle, or the clock went back
  } else {
    tokens_ = std::min(kBurst, tokens_ + secondsBetween(refilled_, now) * rate_);
  }
  refilled_ = now;
}

bool CycleTrigger::onArray(Stamp now) {
  refill(now);
  // Out of tokens (a tracker faster than ~rate): the array waits for the floor, at most a
  // period, and is used by that cycle (as with the timer trigger).
  if (tokens_ < 1.0) {
    refused_ = true;
    return false;
  }
  tokens_ -= 1.0;
  refused_ = false;
  return true;
}

void CycleTrigger::onFloor(Stamp now) {
  refill(now);
  // Silence or a slow tracker: the floor costs nothing, the next array still runs at once.
  if (refused_) tokens_ = std::max(0.0, tokens_ - 1.0);
  refused_ = false;
}

}  // namespace workspace_proximity
