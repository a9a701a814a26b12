#pragma once
/// The one cycle runner: every prediction cycle, the node's, the offline replay's and the
/// benchmarks', runs through CycleRunner::run, which owns
///   - reset: a clock that went back (bag loop, simulation reset) resets the monitor and the
///     feed's history first;
///   - failure: an exception anywhere in the cycle becomes Monitor::cycleFailed, and the cycle
///     still reports (silence must not read as clear);
///   - timing: the stage laps (input, near, ssm, safety, predict, report, contacts) and the
///     whole cycle's wall time.
/// It lives here, below the bridges and ROS-free, so that the benchmarks run the cycle the node
/// runs without ROS; what needs ROS (tf2's buffer, the subscriptions' waiting arrays, the
/// publishers) comes in through the two interfaces below, which MonitorBridges (the bridges)
/// and the node or the replay (the outputs) implement.
///
/// One cycle at `now`:
///   clock went back? feed.reset + Monitor::reset -> feed.update (arrays, robot poses)
///   -> Monitor::beginCycle (expire, extrapolate, pairs within reach, status, SSM verdict)
///   -> out.safety (speed_scale, speed_override, stop actions: before the contacts are even
///      predicted)  [lap kSafety]
///   -> Monitor::finishCycle (broad phase, contact window, narrow phase, events, their levels)
///   -> out.contacts  [lap kContacts] -> out.rest (markers' schedule) -> cycle time noted
///   on an exception: feed.failed -> Monitor::cycleFailed -> out.safety -> out.contacts
///   -> out.rest

#include <string>

#include "workspace_proximity/rules/cycle_report.hpp"
#include "workspace_proximity/rules/cycle_timing.hpp"
#include "workspace_proximity/rules/monitor.hpp"

namespace workspace_proximity {

/// What one cycle did.
struct CycleRun {
  bool reset = false;   ///< the clock had gone back: the history was reset first
  bool failed = false;  ///< an exception: the report says "cycle failed: ..." and has no events
};

/// What feeds the monitor before its cycle (the ROS bridges: MonitorBridges).
class CycleFeed {
 public:
  virtual ~CycleFeed() = default;
  /// The clock went back to `now`: forget what is held from before (waiting arrays, tf
  /// history, joint readings). The monitor resets itself.
  virtual void reset(Stamp now) = 0;
  /// Before the monitor's cycle at `now`: waiting arrays and the robot's poses into it.
  virtual void update(Stamp now) = 0;
  /// The cycle failed with `what` (before the monitor is told): say so.
  virtual void failed(const std::string& what) = 0;
};

/// Where a cycle's report goes (the node's publishers, the replay's files).
class CycleOutput {
 public:
  virtual ~CycleOutput() = default;
  /// The safety output (speed and separation: what a controller acts on): the first output,
  /// before the contacts are predicted and before the markers and diagnostics are built, so
  /// that their cost never delays it. The report's verdict, status and stamp are this cycle's;
  /// it has no events yet (eventCount() 0). Also for a failed cycle (then `run.failed`, and the
  /// verdict is the failure's).
  virtual void safety(const CycleReport& report, const ProximityWorld& world, const CycleRun& run) {
    (void)report, (void)world, (void)run;
  }
  /// Right after safety(), before the contacts are predicted: the transport's chance to
  /// deliver the safety output (the ROS bridge lets roscpp's poll thread write it). Timed in
  /// CycleStage::kSafety but not in kToSafety, which ends when safety() returns.
  virtual void handOff() {}
  /// The contacts: after the safety output and the events' prediction; timed as
  /// CycleStage::kContacts.
  virtual void contacts(const CycleReport& report, const ProximityWorld& world) = 0;
  /// Everything after the contacts (the markers' schedule), in the cycle's time.
  virtual void rest(const CycleReport& report, const ProximityWorld& world, const CycleRun& run) {
    (void)report, (void)world, (void)run;
  }
};

class CycleRunner {
 public:
  /// `monitor` is borrowed.
  explicit CycleRunner(Monitor* monitor) : monitor_(monitor) {}

  /// One cycle at `now`. `feed` and `out` may be null (nothing beyond the monitor). Never
  /// throws from the cycle itself; an exception thrown by `out` while reporting a failed cycle
  /// propagates.
  CycleRun run(Stamp now, CycleFeed* feed, CycleOutput* out);

  /// A stage outside the cycle took `ms` (kArrival: an array used on arrival; kMarkers).
  void noteTime(CycleStage stage, double ms) { timing_.add(stage, ms); }

  const CycleTiming& timing() const { return timing_; }
  /// Wall time of the last and the longest cycle, outputs included, ms (failed cycles are not
  /// timed: their stages are cut short).
  double lastCycleMs() const { return last_cycle_ms_; }
  double maxCycleMs() const { return max_cycle_ms_; }

 private:
  Monitor* monitor_;
  CycleTiming timing_;
  double last_cycle_ms_ = 0.0;
  double max_cycle_ms_ = 0.0;
};

}  // namespace workspace_proximity
