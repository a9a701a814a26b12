#pragma once
/// What happens after a protective stop, as integrators know it from safety laser scanners and
/// robot controllers: the restart interlock (~ssm/restart), the minimum off time
/// (~ssm/min_stop_time), the stop category (~ssm/stop_category: 1 requests a halt once the
/// robot stands still) and muting (a scoped, time-limited exception). ROS-free; SsmCycle runs it
/// around its SpeedScaleFilter every cycle, the ROS bridges pass it reset and mute requests.
///
/// States (docs/ssm.md draws them):
///   RUNNING --scale reaches 0--> STOPPED (held at 0 while < min_stop_time, and in manual mode
///   until a reset is accepted) --released--> the filter rises by its hold and rate --scale > 0-->
///   RUNNING. Category 1: in STOPPED, once every joint speed has stayed below standstill_speed
///   for standstill_time, one halt request per stop.
/// Muting: IDLE --accepted request--> MUTED --time up / stop--> IDLE.
///
/// Decisions on requests use the last cycle's verdict (status, scale, pairs within S_p(v_max)).
/// Every transition is an event {kind, reason}; a cycle's events are handed to its verdict.
/// Storage is reserved up front: no allocation in steady state.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "workspace_proximity/rules/stamp.hpp"

namespace workspace_proximity {

/// The latch's constants (the ~ssm/ parameters). Times in s.
struct LatchParams {
  bool manual = false;          ///< ~ssm/restart == "manual": a stop holds until a reset
  double min_stop_time = 0.0;   ///< s the scale stays 0 after a stop, in both modes
  int stop_category = 2;        ///< 2: hold; 1: hold, then request a halt at standstill
  double standstill_speed = 0.01;  ///< rad/s or m/s: every joint slower than this is standing
  double standstill_time = 0.5;    ///< s of standing before the halt request
  double max_mute_time = 0.0;      ///< s a mute lasts at most; 0: muting refused
};

/// One transition of the latch.
enum class LatchEventKind : std::uint8_t {
  kStop,            ///< the scale reached 0: a protective stop
  kReleased,        ///< the hold ended (min_stop_time over, reset accepted): the scale may rise
  kResetAccepted,
  kResetRefused,
  kMuteStarted,
  kMuteRefused,
  kMuteEnded,
  kHaltRequested,   ///< category 1: the robot stood still, the halt goes out
};

const char* latchEventName(LatchEventKind kind);

struct LatchEvent {
  LatchEventKind kind = LatchEventKind::kStop;
  std::string reason;  ///< one line
};

/// A cycle's events, in order. Capacity fixed: beyond it the last slot says how many were lost.
class LatchEvents {
 public:
  static constexpr int kCapacity = 16;
  LatchEvents();
  void clear() { count_ = 0; lost_ = 0; }
  void add(LatchEventKind kind, const std::string& reason);
  int size() const { return count_; }
  const LatchEvent& operator[](int i) const { return events_[static_cast<std::size_t>(i)]; }
  int lost() const { return lost_; }

 private:
  std::array<LatchEvent, kCapacity> events_;
  int count_ = 0;
  int lost_ = 0;
};

/// The latch's state as the outputs show it.
struct LatchState {
  bool stopped = false;         ///< in a protective stop (since the scale reached 0)
  bool held = false;            ///< the scale is forced to 0 this cycle
  bool reset_required = false;  ///< manual restart: waiting for an accepted reset
  bool halt_requested = false;  ///< category 1: the halt of this stop went out
  bool muted = false;
  double mute_left = 0.0;       ///< s, while muted
  std::string hold;             ///< "" | "min_stop_time" | "reset"
  std::string mute_scope;       ///< "labels: a, b; ids: x" while muted
};

class StopLatch {
 public:
  explicit StopLatch(const LatchParams& params);
  void setParams(const LatchParams& params) { params_ = params; }
  const LatchParams& params() const { return params_; }

  // ---- inputs between cycles ----
  /// A joint reading at `stamp`: the largest |joint speed|, or `known` false when a joint's
  /// speed is not measured (an unknown speed is never standing still).
  void noteJointSpeed(Stamp stamp, double max_abs_speed, bool known);
  /// A reset request at `now`. True when accepted; `why` says why (refused) or what it did.
  bool requestReset(Stamp now, std::string* why);
  /// A mute of the objects with any of `labels` or `ids`, for `duration` s (cut to
  /// max_mute_time). True when accepted; `why` says why not, or until when.
  bool requestMute(Stamp now, const std::vector<std::string>& labels,
                   const std::vector<std::string>& ids, double duration, std::string* why);
  /// True while a mute covers an object of `label` and `id`.
  bool muted(const std::string& label, const std::string& id) const;

  // ---- the cycle ----
  /// Ends a mute whose time is up at `now` (before the rule asks muted(); begin() does too).
  void expireMute(Stamp now);
  /// Before the filter at `now`: ends a mute whose time is up. True when the filter's target
  /// must be 0 (held).
  bool begin(Stamp now);
  /// After the filter: its output `scale`, the cycle's status (`degraded`), how many monitored
  /// pairs are within their S_p(v_max) (muted ones too), and the reason of the scale.
  void end(Stamp now, double scale, bool degraded, int within, const std::string& reason);
  /// The clock went back: stamps are void; a stop stays (its off time restarts), a mute ends.
  void reset();

  const LatchState& state() const { return state_; }
  /// The last cycle's events: the requests since the cycle before, then the cycle's own.
  const LatchEvents& events() const { return events_; }
  /// Why the halt has not gone out yet (category 1, stopped), else "".
  const std::string& haltWait() const { return halt_wait_; }

 private:
  // True when the last cycle refuses `action` ("reset", "mute"): it was DEGRADED or had a
  // monitored pair within S_p(v_max); `why` then says so ("<action> refused: ...").
  bool lastCycleRefuses(const char* action, std::string* why) const;
  void endMute(const char* why);
  void updateHalt(Stamp now);
  void describeScope();

  LatchParams params_;
  LatchState state_;
  LatchEvents events_;   // the last cycle's
  LatchEvents pending_;  // requests since the last cycle
  std::string text_;       // scratch for reasons, reserved
  std::string halt_wait_;  // reserved
  Stamp stop_since_ = -1;  // -1: the off time restarts at the next cycle
  // The last cycle, for requests.
  bool seen_cycle_ = false;
  bool ran_ = false;
  bool in_cycle_ = false;  // between begin() and end(): events go to this cycle's list  // the scale has been above 0 (the start is no stop)
  double last_scale_ = 0.0;
  bool last_degraded_ = true;
  int last_within_ = 0;
  // Joint speeds.
  bool speed_known_ = false;
  bool speed_seen_ = false;
  Stamp speed_stamp_ = 0;
  Stamp still_since_ = -1;  // -1: not standing
  // Mute.
  std::vector<std::string> mute_labels_;
  std::vector<std::string> mute_ids_;
  Stamp mute_until_ = 0;
};

/// A joint reading older than this is no reading (s).
constexpr double kJointSpeedStale = 0.5;

}  // namespace workspace_proximity
