#pragma once
/// Wall time of each stage of the node's prediction cycle over the last cycles, for
/// diagnostics and the shutdown summary. ROS-free; fixed capacity, no allocation per cycle.

#include <array>
#include <chrono>
#include <cstddef>
#include <string>
#include <vector>

namespace workspace_proximity {

/// Stages of one cycle, in order (the laps of CycleRunner::run), then the stages outside the
/// cycle and the parts of a stage noted on their own.
enum class CycleStage : int {
  kInput = 0,  ///< arrays left for the cycle -> tracks, extrapolation, robot poses, the SSM's reach
  kNear,       ///< ProximityWorld::predictNear: swept bounds, the pairs within reach
  kSsm,        ///< the status (OK / DEGRADED) and the speed and separation verdict
  kSafety,     ///< the safety output built and published (speed_scale first)
  kPredict,    ///< ProximityWorld::predictEvents: broad phase, contact window, narrow phase, events
  kReport,     ///< the events' levels, stale flags, bodies' worst levels
  kContacts,   ///< the ContactEventArray built and published
  kMarkers,    ///< not in the cycle: a MarkerArray built and published, half a period later
  kArrival,    ///< not in the cycle: an array turned into tracks when it arrives
  kTransit,    ///< not in the cycle: an array's stamp to its callback (the publisher's
               ///< serialisation, the wire, deserialisation, the callback queue; and whatever
               ///< the tracker's stamp is older than its publication)
  kBroad,      ///< part of kPredict: the broad phase with the world's pair cache (WorldStats)
  kSerialise,  ///< part of kContacts: the contacts' publish() (serialisation, hand-off)
  kToSafety,   ///< the cycle's start to the safety output published (input + near + ssm +
               ///< safety but its hand-off), one sample per cycle: the monitor's own part of
               ///< a controller's reaction time
  kToContacts, ///< the cycle's start to the contacts published, one sample per cycle: the
               ///< monitor's own part of a contacts reader's wait (the hand-off included)
  kCount
};

/// Ring buffers of the last `kWindow` samples per stage, in milliseconds.
class CycleTiming {
 public:
  static constexpr std::size_t kWindow = 1024;
  static constexpr int kStages = static_cast<int>(CycleStage::kCount);

  void add(CycleStage stage, double ms);
  /// One line: "<stage> median/p99/max ms" for every stage, over the window.
  std::string summary() const;
  /// p in [0, 1] over the window; 0 when empty.
  double percentile(CycleStage stage, double p) const;
  double last(CycleStage stage) const;
  static const char* name(CycleStage stage);

 private:
  struct Ring {
    std::array<double, kWindow> ms{};
    std::size_t next = 0;
    std::size_t size = 0;
  };
  std::array<Ring, kStages> rings_;
};

/// Laps of one cycle: each lap() adds the time since the previous lap (or the start) to a
/// stage. Two clock reads per stage, none per pair.
class StageClock {
 public:
  using Clock = std::chrono::steady_clock;
  StageClock(CycleTiming* timing, Clock::time_point start) : timing_(timing), mark_(start) {}
  explicit StageClock(CycleTiming* timing) : StageClock(timing, Clock::now()) {}
  /// Adds the time since the last lap to `stage`; returns it in milliseconds.
  double lap(CycleStage stage) {
    const Clock::time_point now = Clock::now();
    const double ms = std::chrono::duration<double, std::milli>(now - mark_).count();
    timing_->add(stage, ms);
    mark_ = now;
    return ms;
  }

 private:
  CycleTiming* timing_;
  Clock::time_point mark_;
};

}  // namespace workspace_proximity
