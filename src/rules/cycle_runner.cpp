#include "workspace_proximity/rules/cycle_runner.hpp"

#include <algorithm>
#include <chrono>
#include <exception>

namespace workspace_proximity {

CycleRun CycleRunner::run(Stamp now, CycleFeed* feed, CycleOutput* out) {
  CycleRun run;
  const StageClock::Clock::time_point start = StageClock::Clock::now();
  StageClock clock(&timing_, start);
  try {
    run.reset = monitor_->clockWentBack(now);
    if (run.reset) {
      // Every stamp held is from before the jump: tracks (their pairs END), robot poses,
      // sources, and what the feed holds (waiting arrays, tf history, joint readings).
      if (feed != nullptr) feed->reset(now);
      monitor_->reset();
    }
    if (feed != nullptr) feed->update(now);
    // What a controller acts on goes out first, as soon as it is decided: the contacts'
    // prediction (the contact window and narrow phase of every pair), their message
    // (thousands of events at high density) and everything after them must not delay it.
    const CycleReport& report = monitor_->beginCycle(now, &clock);
    if (out != nullptr) out->safety(report, monitor_->world(), run);
    // The start to the safety output published, as one sample: its p99 is the monitor's part
    // of a controller's wait, which the stages' own p99s do not add up to.
    timing_.add(CycleStage::kToSafety, std::chrono::duration<double, std::milli>(
                                           StageClock::Clock::now() - start).count());
    if (out != nullptr) out->handOff();
    clock.lap(CycleStage::kSafety);
    monitor_->finishCycle(&clock);
    const WorldStats& stats = monitor_->world().stats();
    timing_.add(CycleStage::kBroad, 1e-6 * static_cast<double>(stats.ns_broad));
    if (out != nullptr) out->contacts(report, monitor_->world());
    clock.lap(CycleStage::kContacts);
    timing_.add(CycleStage::kToContacts, std::chrono::duration<double, std::milli>(
                                             StageClock::Clock::now() - start).count());
    if (out != nullptr) out->rest(report, monitor_->world(), run);
    last_cycle_ms_ =
        std::chrono::duration<double, std::milli>(StageClock::Clock::now() - start).count();
    max_cycle_ms_ = std::max(max_cycle_ms_, last_cycle_ms_);
  } catch (const std::exception& e) {
    // Nothing may stop the cycle: say so, and still report, saying the prediction is missing.
    run.failed = true;
    if (feed != nullptr) feed->failed(e.what());
    monitor_->cycleFailed(now, e.what());
    if (out != nullptr) {
      out->safety(monitor_->report(), monitor_->world(), run);
      out->handOff();
      out->contacts(monitor_->report(), monitor_->world());
      out->rest(monitor_->report(), monitor_->world(), run);
    }
  }
  return run;
}

}  // namespace workspace_proximity
