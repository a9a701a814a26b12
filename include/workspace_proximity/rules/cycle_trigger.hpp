#pragma once
/// ~cycle_trigger: input. Cycles run on the arrival of an array of the trigger source, limited
/// by a token bucket, with a floor for silence. ROS-free: the node drives it from its
/// subscription and a one-shot timer, the offline replay from the bag's receive times.
///   - The bucket holds at most kBurst tokens and gains ~rate a second. An array that finds a
///     token spends it and runs a cycle at once; one that finds none waits for the floor (at
///     most a period) and is used by that cycle. So a tracker at the node's rate whose arrays
///     jitter never waits, while a flooding one runs at most ~rate cycles a second, floor
///     cycles included.
///   - The floor: a cycle one period after the last cycle, whatever the bucket holds (silence is
///     still published). When it runs for an array the bucket refused, it spends that array's
///     token, so that the next array of the flood does not run a second cycle right after it;
///     for silence or a slow tracker it costs nothing, and the next array still runs at once.
///   - The first array, and the first after the clock went back, finds a full bucket.

#include "workspace_proximity/rules/stamp.hpp"

namespace workspace_proximity {

class CycleTrigger {
 public:
  /// Tokens the bucket holds at most.
  static constexpr double kBurst = 2.0;

  /// `rate`: Hz, ~rate (> 0).
  explicit CycleTrigger(double rate) : rate_(rate) {}
  /// Live tuning: from now on (the floor's period follows at the next cycle).
  void setRate(double rate) { rate_ = rate; }
  /// The floor's period: 1 / rate, s.
  double period() const { return 1.0 / rate_; }
  /// Instant of the floor cycle after a cycle at `last_cycle`.
  Stamp floorAfter(Stamp last_cycle) const { return last_cycle + nanoseconds(period()); }

  /// An array of the trigger source arrived at `now`. True: run a cycle now (a token spent);
  /// false: the bucket is empty, the floor cycle takes the array.
  bool onArray(Stamp now);
  /// The floor fired at `now`: its cycle runs (always).
  void onFloor(Stamp now);

  /// Tokens after the last call (tests, diagnostics).
  double tokens() const { return tokens_; }

 private:
  void refill(Stamp now);  // the bucket counted up to `now`

  double rate_;
  double tokens_ = 0.0;
  Stamp refilled_ = 0;     // when the tokens were last counted up (0: never)
  bool refused_ = false;   // an array was refused a cycle since the last one
};

}  // namespace workspace_proximity
