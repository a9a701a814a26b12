#include "sweep_and_prune_coast_policy.hpp"

#include <algorithm>
#include <cstdlib>

namespace workspace_proximity {
namespace sap {

void CoastPolicy::enlargedAll(std::uint32_t update, const Resort& r, End end) {
  const bool spread = end != End::kAtOnce;
  // The run that ends here was enlarged with run_lead_; the one that starts here with lead_
  // (a lead changed below applies from the next enlargement on).
  const double ended_lead = run_lead_;
  run_lead_ = lead_;
  // This enlargement and its re-sort: the work the next run starts with.
  const double endpoints = 2.0 * r.live;
  double work = kEnlargeWork * r.live + kSwapWork * static_cast<double>(r.swaps);
  work += r.rebuilt ? rebuildWork(3.0, r.live, r.sweep_tests, static_cast<double>(r.candidates))
                    : kPassWork * 3.0 * endpoints;
  if (unjudged_ > 0) {
    --unjudged_;
  } else {
    settled_ = true;
    // A run that ended at once, or by a swap when it ended, ended when its proxies left their
    // bounds together (or at the longest run): the next ones are expected to last as long, and
    // the next arrays are swapped in just before. A run ended early by a swap might have lasted
    // longer: the next one is given an update more, until a swap comes when the run ends
    // anyway. (Steady motion, lead 16, N = 10 000: without the reset at the run's end the
    // expected run grew past the real one and every fourth run ended at once.)
    if (end != End::kSpreadEarly) {
      expected_run_ = std::max<std::uint32_t>(2, std::min(longestRun(), update - last_global_));
    } else {
      expected_run_ = std::min(longestRun(), expected_run_ + 1);
    }
    // The run that ends here, from the last enlargement of everybody to this one, against what
    // the same updates would have cost without coasting: one pass over every axis and the
    // swaps of its motion (this jump's estimated swaps, spread over the run), or a rebuild of
    // the given bounds (one axis sorted) if cheaper; both with the scan of the pairs. Coasting
    // that costs more switches off for a while (longer after each failure in a row).
    const double run = static_cast<double>(update - last_global_);
    double swaps = static_cast<double>(r.estimated_swaps >= 0 ? r.estimated_swaps : r.swaps);
    // A swap's jump is estimated a few updates into the run, from the next bounds in the
    // current order, and it sees fewer swaps than a jump at the run's end (the drift scene of
    // test_sweep_and_prune: 3 800 against 8 600-9 000 for the same motion): its run is judged
    // with the motion's swaps per update of the last run that ended at once, when more.
    if (spread) {
      swaps = std::max(swaps, swaps_per_update_ * run);
    } else {
      swaps_per_update_ = swaps / run;
    }
    const double pairs = static_cast<double>(r.pairs);
    const double without = kScanWork * pairs +
                           std::min(kPassWork * 3.0 * endpoints + kSwapWork * swaps / run,
                                    rebuildWork(1.0, r.live, r.sweep_tests, pairs));
    // The episode (coasting's judged runs since it last started): what it cost against what
    // it saved, for the retry after a failure.
    episode_work_ += run_work_;
    episode_without_ += without * run;
    const bool steady_run = steadyLead() && ended_lead == lead_;
    // The steady lead taken for this enlargement (takeSteadyLead()): its runs are expected about
    // kSteadyLead times as long as this one, so that the first one's end is spread too.
    if (steadyLead() && ended_lead != lead_) {
      expected_run_ = std::min(longestRun(), static_cast<std::uint32_t>(kSteadyLead * run));
    }
    // Runs at the configured lead that end at once, run after run (their ends not spread over
    // the updates before): each end costs 5-10 times a coasting update, so they coast only
    // where they save at least a quarter with every update's own part counted (kAtOnceWorth;
    // see there). A run at its longest ends at once anyway (the motion calmed: tracker
    // jitter's first run), the one at whose end the steady lead is taken is followed by spread
    // ones, and a run at another lead ends the row.
    const double per_update = kProxyWork * static_cast<double>(r.live);
    const double ratio = (run_work_ / run + per_update) / (without + per_update);
    if (end == End::kAtOnce && run < longestRunOf(LeadKind::kConfigured) && ended_lead == coast_updates_ &&
        lead_ == coast_updates_) {
      once_ratios_[once_next_] = ratio;
      once_next_ = (once_next_ + 1) % kAtOnceRuns;
      once_runs_ = std::min(once_runs_ + 1, kAtOnceRuns);
    } else {
      once_runs_ = 0;
    }
    double once_mean = 0.0;
    for (double q : once_ratios_) once_mean += q / kAtOnceRuns;
    const bool tail_fails = once_runs_ >= kAtOnceRuns && once_mean > kAtOnceWorth;
    if ((run_work_ / run > without || tail_fails) && steady_run) {
      // The steady lead's larger bounds cost more than they saved (more candidates scanned):
      // back to the configured lead, which paid, rather than off.
      leaveSteadyLead();
    } else if (run_work_ / run > without || tail_fails) {
      // A run that cost more on its own starts the row afresh after the retry; a failure of
      // the row goes on with it (the retry's first judged run that ends at once is judged with
      // the two before).
      if (!tail_fails) once_runs_ = 0;
      failures_ = std::min(failures_ + 1, 2);
      // (A failure of the tail's rule is judged against kAtOnceWorth when retried, too.)
      episode_ratio_ = tail_fails ? once_mean : episode_work_ / episode_without_;
      worth_ = tail_fails ? kAtOnceWorth : kWorthIt;
      episode_work_ = episode_without_ = 0.0;
      failed_live_ = std::max(1, r.live);
      failed_at_ = update;
      ref_swaps_ = -1.0;
      ref_open_ = true;
      off_swaps_ = -1.0;
      lead_ = 0.0;
      kind_ = LeadKind::kConfigured;
      retry_at_ = update + backoff_;
      backoff_ = std::min<std::uint32_t>(2 * backoff_, kMaxBackoff);
    } else {
      backoff_ = kFirstBackoff;
      // The lead (kLongLead): doubled after a run at the configured lead that lasted its
      // longest (or was swapped out just before), back when a run ends in fewer updates than
      // that. (A run ended early by a swap counts: its build was due by the expected run, so a
      // steady motion whose runs at the long lead are spread, 16-20 updates, comes back.)
      const double longest = longestRunOf(LeadKind::kConfigured);
      if (longLead()) {
        if (run < longest) {
          lead_ = coast_updates_;
          kind_ = LeadKind::kConfigured;
          expected_run_ = std::min(expected_run_, longestRun());
        }
      } else if (steadyLead()) {
        // (A run enlarged before the lead became the steady one says nothing of it.) A run at
        // it that cost more per update than the last judged run at the configured lead did
        // (larger bounds, more candidates scanned in every update: walkers' swept boxes at
        // N = 100 cost 1.4-2 times as much by the mean) brings the configured lead back too.
        if (steady_run && (run < kMinSpreadRun || run_work_ / run > configured_rate_)) {
          leaveSteadyLead();
        } else if (steady_run && run >= longest) {
          lead_ = coast_updates_;
          kind_ = LeadKind::kConfigured;
        } else if (steady_run) {
          steady_backoff_ = kSteadyBlock;
        }
      } else if (kLongLead * coast_updates_ <= kLongLeadAtMost && run + kSwapMargin + 1 >= longest) {
        lead_ = kLongLead * coast_updates_;
        kind_ = LeadKind::kLong;
        expected_run_ = longestRun();
      } else if (steady_block_ > 0) {
        --steady_block_;
      }
      // What a run at the configured lead costs per update, for the steady lead's runs.
      if (ended_lead == coast_updates_) configured_rate_ = run_work_ / run;
    }
  }
  run_work_ = work;
  last_global_ = update;
}

bool CoastPolicy::steadyLeadDue(std::uint32_t update) const {
  if (!steady_allowed_ || unjudged_ > 0 || kind_ != LeadKind::kConfigured || !(lead_ > 0.0) ||
      steady_block_ > 0 || kSteadyLead * coast_updates_ > kSteadyLeadAtMost) {
    return false;
  }
  // Steady motion: the proxies left their bounds together, too soon for the run's end to be
  // spread (and not at its longest, which the long lead answers).
  const std::uint32_t run = update - last_global_;
  return run < kMinSpreadRun && run + kSwapMargin + 1 < longestRunOf(LeadKind::kConfigured);
}

bool CoastPolicy::repeatsFailure(std::uint32_t update, int live) {
  // A first failure is retried as before: it may have been the scene's start (drifts measured
  // from a few updates, boxes at rest that then jump), after which coasting pays. So is one
  // that ended an episode in which coasting paid (a rare dear run among cheap ones). A failure
  // of the tail's rule is not the scene's start (three judged runs after probation), and its
  // retry would end four runs at once again before it is judged: postponed at once.
  const int retried = worth_ < kWorthIt ? 1 : 2;
  if (failures_ < retried || !(episode_ratio_ > worth_) || update - failed_at_ >= kRetryAnyway) return false;
  const bool first = ref_open_;
  closeReference();
  // (No reference measured, or none now: the motion is taken for the same.)
  if (!first && off_swaps_ >= 0.0 && off_swaps_ < kCalmer * ref_swaps_) return false;
  if (4 * std::abs(live - failed_live_) > failed_live_) return false;
  retry_at_ = update + kFirstBackoff;
  return true;
}

}  // namespace sap
}  // namespace workspace_proximity
