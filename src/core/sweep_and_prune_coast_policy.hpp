#pragma once
/// Coasting's policy (private to the core): how much a proxy's bounds are enlarged ahead of
/// its motion, what an update does with the proxies that left their enlarged bounds, and
/// whether coasting pays. A value class fed counts, kept outside the arrays it steers (as
/// Box2D keeps its fat-bounds margin outside its tree), so that its decisions are tested on
/// their own (test/core/test_coast_policy.cpp).
///
/// The lead ahead of a side that moved outward is `coast_updates` updates of its own
/// displacement per update, capped at a fraction of the box's largest extent; a side that moved
/// inward gets one update's, a resting side none (room()); the lead is the configured one, or
/// twice it while runs last their longest (the long lead: jitter), or three times it while
/// runs end together too soon to spread (the steady lead: steady motion). An update with no
/// escaper does nothing; up to 1 + n / 32 escapers move alone; more, or a run of 4
/// coast_updates updates (coast_updates while on probation; 6 at the long lead: kLongLead),
/// enlarge everybody again (step()). Each enlargement of everybody ends a run, which is judged
/// with a cost model in work units against what the same updates would have cost without
/// coasting; a run that cost more, or the third of runs in a row that ended at once without
/// saving a quarter (kAtOnceWorth: their ends set the tail), switches coasting off for 64
/// updates, twice as long after each failure in a row (up to 4 096), then it is tried again
/// (postponeRetry(): not when the last displacements show at once that it would fail, nor,
/// after a second failure or one of those rows, in the scene of an episode that did not save:
/// repeatsFailure()). The first three runs after
/// coasting starts are on probation (not judged): their leads were measured from an update or
/// two. They are short (coast_updates updates each), so that each proxy's drift under tracker
/// jitter is measured again soon, before the long runs: with the leads of the first update or
/// two, drifting boxes left their bounds by the hundreds per update all through a long first
/// run (N = 100 000, +-1 %: 300-1 200 per update over updates 4-35, against 25-60 over
/// updates 12-28 with a short first run).

#include <algorithm>
#include <cstddef>
#include <cstdint>

namespace workspace_proximity {
namespace sap {

class CoastPolicy {
 public:
  // Work units of the cost model (about a nanosecond each on the benchmark machine: perf
  // profiles of the uniform, walker and robot-cell scenes, bench/results/NOTES.md section 19).
  static constexpr double kScanWork = 4.0;     ///< one candidate tested on the given bounds
  static constexpr double kSwapWork = 10.0;    ///< one swap (insertion sort or a relocated endpoint)
  static constexpr double kPassWork = 1.5;     ///< one endpoint read in a pass over an axis
  static constexpr double kSearchWork = 100.0; ///< finding a proxy's six endpoints (binary searches)
  static constexpr double kEnlargeWork = 20.0; ///< enlarging one proxy
  static constexpr double kSortWork = 12.0;    ///< one endpoint radix-sorted in a rebuild, per axis
  static constexpr double kTestWork = 1.5;     ///< one overlap test of a rebuild's sweep
  static constexpr double kFoundWork = 25.0;   ///< one pair found (and stamped) by a rebuild
  /// One live proxy's part of every update, coasting or not (its given bounds taken in, and
  /// its coasting test or its keys written): 19-27 ns measured either way (the broad-phase
  /// benchmark, AMD EPYC VM, session 26). The same on both sides of a comparison, it changes
  /// no "costs more" verdict, only the ratios (kAtOnceWorth).
  static constexpr double kProxyWork = 20.0;
  static constexpr std::uint32_t kFirstBackoff = 64;   ///< updates off after a first failure
  static constexpr std::uint32_t kMaxBackoff = 4096;   ///< updates off at most
  /// Runs after coasting starts that are not judged: their leads (and the bounds on tracker
  /// jitter) were measured from an update or two, and the waves of escapers that follow say
  /// nothing yet of what coasting costs.
  static constexpr int kProbationRuns = 3;

  /// `coast_updates`: SweepAndPruneConfig::coast_updates (0: never coast); `steady_lead`:
  /// SweepAndPruneConfig::steady_lead (false: never the steady lead).
  explicit CoastPolicy(double coast_updates, bool steady_lead = true)
      : coast_updates_(coast_updates), lead_(coast_updates), steady_allowed_(steady_lead) {}

  /// The lead (in updates of displacement) of enlargements now; 0 while coasting is off (the
  /// arrays then hold the given bounds).
  double lead() const { return lead_; }

  /// Room (m) below and above a proxy on one axis, from the displacements per update of its
  /// lower and upper side since its last enlargement (d_lo, d_hi, m: positive upward), the
  /// lead and the cap (m). Without branches (directions are random): max(-lead d, d) is
  /// lead |d| for a side moving outward, |d| for one moving inward, both capped. A room that is
  /// not positive (or NaN) means none.
  static void room(double d_lo, double d_hi, double lead, double cap, double* below, double* above) {
    *below = std::min(cap, std::max(-lead * d_lo, d_lo));
    *above = std::min(cap, std::max(lead * d_hi, -d_hi));
  }

  /// What an update does to the arrays.
  enum class Step : std::uint8_t {
    kNothing,     ///< nothing to re-sort
    kResort,      ///< coasting off: re-sort the given bounds (insertion sort or rebuild)
    kMoveFew,     ///< move the escapers' endpoints alone
    kEnlargeAll,  ///< enlarge every proxy again, then re-sort (and report enlargedAll())
  };
  /// The step of update number `update` (1 for the first), from the number of live proxies
  /// that left their enlarged bounds, the live count, whether an axis of the arrays is out of
  /// order (escapers then cannot move alone), and, for coasting off, whether a live proxy
  /// moved. Turns coasting on again when it is due (then kEnlargeAll, with no run to judge).
  Step step(std::uint32_t update, std::size_t escapers, int live, bool any_stale, bool moved) {
    if (lead_ <= 0.0) {
      if (!moved) return Step::kNothing;
      if (!(coast_updates_ > 0.0 && update >= retry_at_)) return Step::kResort;
      lead_ = coast_updates_;
      kind_ = LeadKind::kConfigured;
      unjudged_ = 1 + kProbationRuns;  // the run starts here, on probation
      settled_ = false;
      expected_run_ = longestRun();
      return Step::kEnlargeAll;
    }
    // A run lasts at most 4 coast_updates updates (6 at the long lead, coast_updates on
    // probation): then everybody is enlarged again, with leads measured anew (stale ones only
    // cost tests), and the run is judged.
    const double run_length = unjudged_ > 0 ? coast_updates_ : longestRunOf(kind_);
    const bool run_over = update - last_global_ >= run_length;
    if (escapers == 0 && !run_over) return Step::kNothing;
    // A few: move their endpoints alone (a pass over the arrays costs more).
    const std::size_t few = 1 + static_cast<std::size_t>(live) / 32;
    if (escapers > 0 && escapers <= few && !any_stale && !run_over) return Step::kMoveFew;
    return Step::kEnlargeAll;
  }

  /// Coasting is off and due to be tried again at `update` (with a proxy moving, step() would
  /// start it).
  bool retryDue(std::uint32_t update) const {
    return lead_ <= 0.0 && coast_updates_ > 0.0 && update >= retry_at_;
  }
  /// The retry due at `update` would fail: many proxies would leave bounds enlarged with the
  /// lead within kMinRun updates (runsTooShort() in sweep_and_prune_coasting.hpp). Postpones
  /// it by kFirstBackoff updates without enlarging anybody (the back-off stays: that check is
  /// one pass over the proxies, so coasting resumes soon once the motion calms). A retry that
  /// fails costs several updates that enlarge everybody and rebuild with candidates several
  /// times the pairs: they set the tail of the large-motion rows (uniform 20 %, N = 1 000:
  /// p99 3.6x the median, one retry every 64-4 096 updates).
  void postponeRetry(std::uint32_t update) {
    closeReference();
    retry_at_ = update + kFirstBackoff;
  }
  /// Coasting off: the swaps of this update's motion (insertion sort's, or those estimated
  /// before a rebuild), averaged over the last few updates: what a retry is weighed on.
  void sortedOff(double swaps) {
    if (!(swaps >= 0.0)) return;
    off_swaps_ = off_swaps_ < 0.0 ? swaps : 0.875 * off_swaps_ + 0.125 * swaps;
  }
  /// The retry due at `update` would repeat the runs that failed: coasting failed before (a
  /// first failure is retried as before, unless it was a row of runs ended at once), the
  /// episode that failed (its judged runs since coasting last started) saved less than a tenth
  /// over not coasting (kWorthIt; for a row of runs ended at once, its mean by kAtOnceWorth's
  /// ratio was above kAtOnceWorth, as it is whenever such a row fails), the scene is
  /// the one it failed in (the motion no calmer than in the stretch off that followed the
  /// failure, up to the first retry due; the live count within a quarter of the failure's),
  /// and the failure was less than kRetryAnyway updates ago. Then the retry is postponed by
  /// kFirstBackoff updates, enlarging nobody (the check is cheap: the scene is looked at again
  /// soon). A retry costs several updates that enlarge everybody (its runs on probation and
  /// the judged ones), each 5-10 times an update off: in the robot cells, where coasting costs
  /// about what it saves (episodes at 0.93-1.2 of not coasting), retries every 64-128 updates
  /// were the rows' p99 (6-10x the median). A motion calmer by half (kCalmer) or a crowd that
  /// grew or shrank by a quarter tries again at once. (With a first failure not retried, a
  /// resting scene whose first judged run failed as a few boxes jumped would not coast; with
  /// an episode that paid not retried, a motion whose reversals end a rare run after an
  /// update or two would stop coasting where it saves a third.)
  bool repeatsFailure(std::uint32_t update, int live);
  /// An episode of coasting is worth retrying in the same scene when it cost at most this
  /// fraction of not coasting: below a tenth saved, its runs' ends (5-10 times an update off)
  /// are not worth the saving.
  static constexpr double kWorthIt = 0.9;
  /// Judged runs at the configured lead that end at once before their longest, kAtOnceRuns in
  /// a row, fail when they cost on average more than this fraction of not coasting, with every
  /// update's own part (kProxyWork per live proxy) on both sides. Each such end (everybody
  /// enlarged and re-sorted in one update) costs 5-10 times a coasting update, and the cost
  /// model is optimistic about those runs. Beside a peer of the same build that never coasts
  /// (the broad-phase benchmark, AMD EPYC VM, session 26): rows whose runs ended at once at
  /// 0.82-1.4 by this ratio cost 1.03-1.2 times not coasting by the measured mean (uniform 1 %
  /// and 5 %, walkers and the warehouse at N = 100, the warehouse at 1 000, the small robot
  /// cell); those at 0.56-0.67 cost 0.54-0.71 (uniform 5 % at N = 1 000 and 10 000, which keep
  /// coasting). The proximity monitor's runs at its lead of 16 are spread (no row: none failed
  /// in bench-safety's rounds at 1 000 and 10 000 objects).
  static constexpr double kAtOnceWorth = 0.75;
  /// Runs ended at once in a row that the rule above looks at (their mean).
  static constexpr int kAtOnceRuns = 3;
  /// A retry is tried when the swaps per update fell below this fraction of the reference.
  static constexpr double kCalmer = 0.5;
  /// A retry is tried whatever the scene this many updates after the last failure.
  static constexpr std::uint32_t kRetryAnyway = kMaxBackoff;
  /// Updates of its last displacement that a proxy's enlarged bounds should hold at least, for
  /// a retry to be worth it (half the lead's 8: an enlargement of everybody every other update
  /// or so never pays).
  static constexpr double kMinRun = 4.0;

  /// Counts of the re-sort that followed an enlargement of everybody.
  struct Resort {
    int live = 0;                      ///< live proxies
    std::int64_t swaps = 0;            ///< insertion-sort swaps it made
    bool rebuilt = false;              ///< it rebuilt instead
    std::size_t candidates = 0;        ///< candidate pairs after it
    std::int64_t sweep_tests = 0;      ///< overlap tests of the last full sweep
    std::int64_t estimated_swaps = -1; ///< swaps it estimated from the new keys (-1: none)
    std::size_t pairs = 0;             ///< pairs of given bounds at the last report
  };
  /// Everybody was enlarged at `update` and re-sorted, at once or by the next arrays swapped
  /// in: ends the run under way (judging it, unless it is the first since coasting started)
  /// and starts the next with that work. A judged run that ended at once sets how long the next
  /// runs are expected to last; one ended early by a swap, before its proxies left their
  /// bounds, lengthens that by an update (runs after a swap last as long as after everybody
  /// enlarged at once: the next bounds hold the lead past the swap).
  /// How a run ended: everybody enlarged at once; or the next arrays swapped in when the run
  /// ended (many left their bounds, or its longest) or before (when it was expected to end).
  enum class End : std::uint8_t { kAtOnce, kSpreadAtEnd, kSpreadEarly };
  void enlargedAll(std::uint32_t update, const Resort& r, End end = End::kAtOnce);
  /// The run under way ends at `update` with everybody enlarged at once (asked before that
  /// enlargement, so that it can take the lead chosen then): true when it is a judged run at
  /// the configured lead that ended before kMinSpreadRun updates, and the steady lead (see
  /// kSteadyLead) is allowed, at most kSteadyLeadAtMost and not blocked.
  bool steadyLeadDue(std::uint32_t update) const;
  /// Takes the steady lead when it is due; or, when `capped` (the proxies' motion would leave
  /// bounds enlarged with it within kMinSpreadRun updates anyway: the lead's cap), blocks it as
  /// a run at it that was too short would (steadyLeadCapped() in sweep_and_prune_coasting.hpp:
  /// at 5 % motion a lead of 24 hits the cap of half the box, and each try cost a run).
  void takeSteadyLead(bool capped) {
    if (capped) {
      steady_block_ = steady_backoff_ + 1;  // (the run ending now counts one off: enlargedAll())
      steady_backoff_ = std::min(2 * steady_backoff_, kMaxSteadyBlock);
      return;
    }
    lead_ = kSteadyLead * coast_updates_;
    kind_ = LeadKind::kSteady;
  }

  /// Judged runs last at most this many updates: 4 coast_updates, 6 at the long lead.
  std::uint32_t longestRun() const {
    return static_cast<std::uint32_t>(std::max(2.0, std::min(1e6, longestRunOf(kind_))));
  }
  /// The long lead, in leads: while judged runs last their longest at the configured lead
  /// (nobody leaves their bounds: tracker jitter around rest, a slow drift), the lead doubles
  /// (when that makes at most kLongLeadAtMost) and runs last up to kLongRuns of it; a judged
  /// run shorter than the configured lead's longest (4 coast_updates) brings it back
  /// (enlargedAll()). Each run's end costs about a
  /// re-sort of everybody (or its build spread over the updates before): at +-0.5-5 % jitter
  /// runs ended every 28-29 updates, at their longest, and half the updates carried a slice of
  /// the next build (bench/results/NOTES.md section 27).
  static constexpr double kLongLead = 2.0;
  /// The long lead is taken only when it is at most this many updates: the monitor's 16
  /// doubled to 32 (runs of up to 96 updates) made the jitter rows slower (medians 1.2-1.7
  /// times, means up to 1.4 times).
  static constexpr double kLongLeadAtMost = 16.0;
  /// Runs at the long lead last at most this many of it (6 coast_updates, not 8: at N = 10 000
  /// the drifting boxes left bounds enlarged with it by the hundred per update past 48 updates,
  /// each moved alone while the next build's slices ran).
  static constexpr double kLongRuns = 3.0;
  /// True while the lead is the long one.
  bool longLead() const { return kind_ == LeadKind::kLong; }
  /// The steady lead, in leads: a judged run at the configured lead that ended at once, before
  /// kMinSpreadRun updates, because its proxies left their bounds together (steady motion: 1-5 %
  /// of the box size per update ends runs at a lead of 8 every 7-9 updates) triples the lead
  /// (when that makes at most kSteadyLeadAtMost), so that runs last long enough for their ends
  /// to be spread over the updates before (the next arrays). A run at the steady lead shorter
  /// than kMinSpreadRun (the lead hit its cap, max_lead_fraction, or the motion sped up),
  /// costing more per update than the last judged run at the configured lead (its larger bounds
  /// give more candidates to scan), or failing the cost model brings the configured lead back,
  /// and the steady lead is not tried
  /// again for kSteadyBlock judged runs (twice as many after each such run in a row, up to
  /// kMaxSteadyBlock); one that lasts its longest (4 coast_updates: the motion slowed) brings
  /// it back at once. Uniform 1 %, N = 1 000, one run beside the lead of 8: p99 / median 4x
  /// against 20x, mean 29 % lower, median 51 % higher (bench/results/NOTES.md section 33).
  static constexpr double kSteadyLead = 3.0;
  /// The steady lead is taken only when it is at most this many updates (the monitor's 16 makes
  /// steady runs of about 16 updates, long enough to spread, and keeps it).
  static constexpr double kSteadyLeadAtMost = 24.0;
  /// Judged runs before the steady lead is tried again after it did not pay, at first.
  static constexpr std::uint32_t kSteadyBlock = 8;
  /// ... and at most.
  static constexpr std::uint32_t kMaxSteadyBlock = 512;
  /// True while the lead is the steady one.
  bool steadyLead() const { return kind_ == LeadKind::kSteady; }
  /// The next arrays (sweep_and_prune_next.hpp): true when a build spread over `slices`
  /// updates is due to start at `update`, so that it is swapped in kSwapMargin updates before
  /// the run under way is expected to end (as long as the last judged run that ended at once,
  /// at first the longest). Never while coasting is off, on probation, in its first judged run, or in
  /// the update of an enlargement of everybody. (In the first long run the drifting boxes
  /// still leave their bounds by the hundred per update while their drift is learnt: +-0.5 %
  /// jitter, N = 10 000, 76-125 per update; a build on top of them made the dearest updates.)
  bool nextDue(std::uint32_t update, std::uint32_t slices) const {
    if (lead_ <= 0.0 || unjudged_ > 0 || !settled_ || slices == 0 || update <= last_global_) return false;
    return update + slices + kSwapMargin >= last_global_ + expected_run_;
  }
  /// Runs shorter than this end at once. Steady motion of 1-5 % of the box size per update
  /// ends its runs every 7-9 updates (everybody leaves together): a build squeezed into 4-6
  /// updates fell behind the proxies leaving (their run then ended at once anyway), and its
  /// means were 1.3-1.5 times those of runs ended at once (bench/results/NOTES.md section 21).
  /// Tracker jitter around rest or a slow drift makes runs of 32 updates; the steady lead
  /// (kSteadyLead) makes steady motion's runs long enough.
  static constexpr std::uint32_t kMinSpreadRun = 16;
  /// A build is due to be swapped in this many updates before the run's expected end: one
  /// that takes longer than estimated still has the updates between to be done and swapped
  /// before the run ends (at its longest, or when its proxies leave their bounds).
  static constexpr std::uint32_t kSwapMargin = 3;
  /// Updates a build may take, at most `spread` (twice that at the long lead): under half of a
  /// run's updates (at least 6), under two thirds at the long lead. Spread over the whole run
  /// (29 of 32 updates) the p99 was as high in microseconds and the means 5-15 % higher
  /// (bench/results/NOTES.md section 21): most updates should carry no slice. The long lead's
  /// runs (tracker jitter around rest or a slow drift, up to 48 updates) are the most
  /// predictable: in 30 slices of 48 instead of 22 their p99 fell 3-22 % in microseconds, to
  /// 1.9-2.8 times the median (2.3-4.2 before), the means 7 % lower to 3 % higher, the
  /// medians 9-30 % higher (section 34). Steady motion and walkers at the steady lead lost
  /// from builds that early: a box that turns after its slice leaves its next bounds at the
  /// swap (walkers at N = 10 000: the p99 1.5 times, the mean 8 % higher; a steady drift
  /// between walls lost the steady lead). (The long lead's runs of 48 updates in 16 slices
  /// made the p99, a slice, 3.4 times the median at N = 10 000.) 0: runs too short to spread
  /// their end.
  std::uint32_t nextSlices(std::uint32_t spread) const {
    if (expected_run_ < kMinSpreadRun) return 0;
    const std::uint32_t most = longLead() ? static_cast<std::uint32_t>(kLongLead) * spread : spread;
    const std::uint32_t share = longLead() ? 2 * expected_run_ / 3 : expected_run_ / 2;
    return std::min({most, expected_run_ - kSwapMargin - 2, std::max<std::uint32_t>(6, share - 2)});
  }
  /// The update that swaps in a build started at `update` over `slices` updates.
  std::uint32_t nextSwapAt(std::uint32_t update, std::uint32_t slices) const {
    return std::max(update + slices, last_global_ + expected_run_ - kSwapMargin);
  }
  /// Updates the run under way is expected to last.
  std::uint32_t expectedRun() const { return expected_run_; }
  /// The update of the last enlargement of everybody (at once or by a swap): the run under
  /// way started there.
  std::uint32_t lastEnlargement() const { return last_global_; }

  /// Work of the run under way: `candidates` scanned on their given bounds (while coasting);
  /// `escapers` moved alone with `swaps` swaps.
  void scanned(std::size_t candidates) {
    if (lead_ > 0.0) run_work_ += kScanWork * static_cast<double>(candidates);
  }
  void movedFew(std::size_t escapers, std::size_t swaps) {
    run_work_ += kSearchWork * static_cast<double>(escapers) + kSwapWork * static_cast<double>(swaps);
  }

  /// Work of a rebuild of `live` proxies that sorts `axes_sorted` axes, sweeps with
  /// `sweep_tests` overlap tests and finds `pairs` pairs.
  static double rebuildWork(double axes_sorted, int live, std::int64_t sweep_tests, double pairs) {
    return kSortWork * axes_sorted * 2.0 * live + kTestWork * static_cast<double>(sweep_tests) +
           kFoundWork * pairs;
  }

  /// For tests and diagnostics: work so far of the run under way; the update at which coasting
  /// is tried again (while off); the updates it stays off after the next failure.
  double runWork() const { return run_work_; }
  std::uint32_t retryAt() const { return retry_at_; }
  std::uint32_t backoff() const { return backoff_; }

 private:
  double coast_updates_;
  // coast_updates_ (or kLongLead or kSteadyLead times it) while coasting, else 0
  double lead_;
  enum class LeadKind : std::uint8_t { kConfigured, kLong, kSteady };
  LeadKind kind_ = LeadKind::kConfigured;     // which lead_ is (kConfigured while off)
  bool steady_allowed_;                       // SweepAndPruneConfig::steady_lead
  double run_lead_ = lead_;                   // the lead the run under way was enlarged with
  std::uint32_t steady_block_ = 0;            // judged runs before the steady lead may be taken
  std::uint32_t steady_backoff_ = kSteadyBlock; // the block after the next one that did not pay
  double configured_rate_ = 0.0;  // work per update of the last judged run at coast_updates_
  // Back to the configured lead from the steady one, blocking the steady lead for a while.
  void leaveSteadyLead() {
    lead_ = coast_updates_;
    kind_ = LeadKind::kConfigured;
    steady_block_ = steady_backoff_;
    steady_backoff_ = std::min(2 * steady_backoff_, kMaxSteadyBlock);
  }
  std::uint32_t last_global_ = 0;            // update of the last enlargement of everybody
  std::uint32_t retry_at_ = 0;               // coasting off: the update that tries it again
  std::uint32_t backoff_ = kFirstBackoff;    // updates it stays off after failing
  std::uint32_t expected_run_ = longestRun(); // length of the last judged run ended at once
  double swaps_per_update_ = 0.0;             // its motion's estimated swaps per update
  bool settled_ = false;                      // a judged run ended since coasting started
  double run_work_ = 0.0;                    // work of the coasting run under way
  int failures_ = 0;                          // judged runs that failed since the start (up to 2)
  double episode_work_ = 0.0;                 // work of the judged runs since coasting started
  double episode_without_ = 0.0;              // the same updates without coasting
  double episode_ratio_ = 0.0;                // their ratio in the episode that last failed
  double worth_ = kWorthIt;                   // the ratio it had to beat (kAtOnceWorth for the tail's rule)
  int once_runs_ = 0;                         // judged runs in a row that ended at once (up to kAtOnceRuns)
  int once_next_ = 0;                         // the slot of once_ratios_ the next one takes
  double once_ratios_[kAtOnceRuns] = {};      // the last kAtOnceRuns of their ratios (kAtOnceWorth's)
  int failed_live_ = 0;                       // live proxies when coasting last failed
  std::uint32_t failed_at_ = 0;               // the update it failed at
  double ref_swaps_ = -1.0;                   // swaps per update off after that failure (-1: none)
  bool ref_open_ = false;                     // that reference is still being measured
  double off_swaps_ = -1.0;                   // swaps per update off, recent average (-1: none)
  // The longest judged run at a lead of that kind (the configured one while coasting is off).
  double longestRunOf(LeadKind kind) const {
    return kind == LeadKind::kLong ? kLongRuns * kLongLead * coast_updates_ : 4.0 * coast_updates_;
  }
  // The first retry due after a failure ends the stretch off that measures the reference.
  void closeReference() {
    if (ref_open_) ref_swaps_ = off_swaps_;
    ref_open_ = false;
  }
  // Enlargements of everybody before runs are judged: the first starts coasting's first run,
  // the next kProbationRuns end runs on probation, unjudged.
  int unjudged_ = 1 + kProbationRuns;
};

}  // namespace sap
}  // namespace workspace_proximity
