// Tests of SweepAndPrune's coasting policy (src/core/sweep_and_prune_coast_policy.hpp) on its
// own: every expected value below is computed by hand from the documented rules (the room of
// a side, the step of an update, the cost model's work units and the back-off), not read from
// the code. The arrays it steers are tested against brute force in test_sweep_and_prune.cpp.

#include <gtest/gtest.h>

#include <cmath>

#include "sweep_and_prune_coast_policy.hpp"

namespace {

using workspace_proximity::sap::CoastPolicy;
using Step = CoastPolicy::Step;

// The caller's side of a run that ends at once (SweepAndPrune's update): the steady lead is
// taken when due, the proxies' motion (`capped`) not leaving its bounds before 16 updates.
void endsAtOnce(CoastPolicy* p, std::uint32_t update, bool capped = false) {
  if (p->steadyLeadDue(update)) p->takeSteadyLead(capped);
}

// A re-sort after an enlargement of everybody, by insertion sort unless `rebuilt`.
CoastPolicy::Resort resort(int live, std::int64_t swaps, std::int64_t estimate, std::size_t pairs,
                           bool rebuilt = false, std::int64_t sweep_tests = 1000,
                           std::size_t candidates = 80) {
  CoastPolicy::Resort r;
  r.live = live;
  r.swaps = swaps;
  r.rebuilt = rebuilt;
  r.candidates = candidates;
  r.sweep_tests = sweep_tests;
  r.estimated_swaps = estimate;
  r.pairs = pairs;
  return r;
}

TEST(CoastPolicy, RoomLeadsAnOutwardSideAndFollowsAnInwardOne) {
  double below = -1.0, above = -1.0;
  // Moving up 1 cm per update with a lead of 8: 8 cm above, one update's 1 cm below.
  CoastPolicy::room(0.01, 0.01, 8.0, 1.0, &below, &above);
  EXPECT_DOUBLE_EQ(above, 0.08);
  EXPECT_DOUBLE_EQ(below, 0.01);
  // Moving down: the mirror image.
  CoastPolicy::room(-0.01, -0.01, 8.0, 1.0, &below, &above);
  EXPECT_DOUBLE_EQ(below, 0.08);
  EXPECT_DOUBLE_EQ(above, 0.01);
  // Growing on both sides: both lead.
  CoastPolicy::room(-0.02, 0.03, 8.0, 1.0, &below, &above);
  EXPECT_DOUBLE_EQ(below, 0.16);
  EXPECT_DOUBLE_EQ(above, 0.24);
  // Shrinking on both sides: one update's each.
  CoastPolicy::room(0.02, -0.03, 8.0, 1.0, &below, &above);
  EXPECT_DOUBLE_EQ(below, 0.02);
  EXPECT_DOUBLE_EQ(above, 0.03);
}

TEST(CoastPolicy, RoomOfARestingSideIsNoneAndTheLeadIsCapped) {
  double below = -1.0, above = -1.0;
  CoastPolicy::room(0.0, 0.0, 8.0, 1.0, &below, &above);
  EXPECT_FALSE(below > 0.0);
  EXPECT_FALSE(above > 0.0);
  // 0.5 m per update with a lead of 8 would be 4 m ahead: the cap (say half a 2 m box) wins,
  // and also caps the side behind.
  CoastPolicy::room(0.5, 0.5, 8.0, 1.0, &below, &above);
  EXPECT_DOUBLE_EQ(above, 1.0);
  EXPECT_DOUBLE_EQ(below, 0.5);
  CoastPolicy::room(3.0, 3.0, 8.0, 1.0, &below, &above);
  EXPECT_DOUBLE_EQ(below, 1.0);
  // A cap of 0 (max_lead_fraction 0) leaves no room at all.
  CoastPolicy::room(-0.5, 0.5, 8.0, 0.0, &below, &above);
  EXPECT_FALSE(below > 0.0);
  EXPECT_FALSE(above > 0.0);
}

TEST(CoastPolicy, EscapersMoveAloneUpToOnePlusAThirtySecondOfTheLiveProxies) {
  CoastPolicy p(8.0);
  EXPECT_DOUBLE_EQ(p.lead(), 8.0);
  // 100 live proxies: a few is 1 + 100 / 32 = 4.
  EXPECT_EQ(p.step(1, 0, 100, false, false), Step::kNothing);
  EXPECT_EQ(p.step(1, 1, 100, false, false), Step::kMoveFew);
  EXPECT_EQ(p.step(1, 4, 100, false, false), Step::kMoveFew);
  EXPECT_EQ(p.step(1, 5, 100, false, false), Step::kEnlargeAll);
  // An axis out of order: escapers cannot move alone.
  EXPECT_EQ(p.step(1, 1, 100, true, false), Step::kEnlargeAll);
  // 31 live proxies: a few is 1; 32: 2.
  EXPECT_EQ(p.step(1, 1, 31, false, false), Step::kMoveFew);
  EXPECT_EQ(p.step(1, 2, 31, false, false), Step::kEnlargeAll);
  EXPECT_EQ(p.step(1, 2, 32, false, false), Step::kMoveFew);
  // Coasting on, "moved" means nothing (moveProxy sorts out escapers itself).
  EXPECT_EQ(p.step(1, 0, 100, false, true), Step::kNothing);
  EXPECT_DOUBLE_EQ(p.lead(), 8.0);
}

TEST(CoastPolicy, ARunEndsAfterFourCoastUpdatesUpdates) {
  CoastPolicy p(8.0);
  p.enlargedAll(10, resort(100, 0, 0, 0));  // coasting starts at update 10: on probation
  // A run on probation lasts coast_updates = 8 updates, escapers or not.
  EXPECT_EQ(p.step(17, 0, 100, false, false), Step::kNothing);
  EXPECT_EQ(p.step(17, 1, 100, false, false), Step::kMoveFew);
  EXPECT_EQ(p.step(18, 0, 100, false, false), Step::kEnlargeAll);
  p.enlargedAll(18, resort(100, 0, 0, 0));
  p.enlargedAll(26, resort(100, 0, 0, 0));
  p.enlargedAll(34, resort(100, 0, 0, 0));  // the last probation run ends: runs are judged
  // 4 * 8 = 32 updates later everybody is enlarged again, escapers or not.
  EXPECT_EQ(p.step(65, 0, 100, false, false), Step::kNothing);
  EXPECT_EQ(p.step(65, 1, 100, false, false), Step::kMoveFew);
  EXPECT_EQ(p.step(66, 0, 100, false, false), Step::kEnlargeAll);
  EXPECT_EQ(p.step(66, 1, 100, false, false), Step::kEnlargeAll);
  // coast_updates 2.5: 2.5 updates on probation, then 10.
  CoastPolicy q(2.5);
  EXPECT_EQ(q.step(2, 0, 100, false, false), Step::kNothing);
  EXPECT_EQ(q.step(3, 0, 100, false, false), Step::kEnlargeAll);
  for (int i = 0; i < 4; ++i) q.enlargedAll(10, resort(100, 0, 0, 0));
  EXPECT_EQ(q.step(19, 0, 100, false, false), Step::kNothing);
  EXPECT_EQ(q.step(20, 0, 100, false, false), Step::kEnlargeAll);
}

TEST(CoastPolicy, WorkOfARunIsCountedInUnits) {
  CoastPolicy p(8.0);
  // Enlarging 100 (20 each), 200 swaps (10 each), one pass over 3 axes of 200 endpoints (1.5
  // each): 2000 + 2000 + 900.
  p.enlargedAll(1, resort(100, 200, 300, 50));
  EXPECT_DOUBLE_EQ(p.runWork(), 4900.0);
  p.scanned(100);  // 4 each
  EXPECT_DOUBLE_EQ(p.runWork(), 5300.0);
  p.movedFew(2, 30);  // 100 per escaper, 10 per swap
  EXPECT_DOUBLE_EQ(p.runWork(), 5800.0);
  // A rebuild instead of the pass: 12 per endpoint and axis sorted (3 axes of 200), 1.5 per
  // overlap test (1000), 25 per candidate (80): 7200 + 1500 + 2000; with enlarging, 12700.
  CoastPolicy q(8.0);
  q.enlargedAll(1, resort(100, 0, 0, 50, true, 1000, 80));
  EXPECT_DOUBLE_EQ(q.runWork(), 12700.0);
  EXPECT_DOUBLE_EQ(CoastPolicy::rebuildWork(1.0, 100, 1000, 50.0), 2400.0 + 1500.0 + 1250.0);
}

TEST(CoastPolicy, ARunCheaperThanNotCoastingKeepsCoasting) {
  CoastPolicy p(8.0);
  p.enlargedAll(0, resort(100, 0, 0, 0));       // coasting starts; three probation runs follow
  p.enlargedAll(0, resort(100, 0, 0, 0));       // the first ends, unjudged
  p.enlargedAll(0, resort(100, 0, 0, 0));       // the second
  p.enlargedAll(1, resort(100, 200, 300, 50));  // 4900, not judged (the third ends)
  p.scanned(100);
  p.movedFew(2, 30);                            // 5800 in all
  // Judged at update 33 (a run of 32): 5800 / 32 = 181.25 per update, against, without
  // coasting, 4 per pair (50) plus the cheaper of a pass over 3 axes of 200 endpoints with
  // 640 / 32 swaps per update (900 + 200) and a rebuild of one axis (5150): 1300.
  p.enlargedAll(33, resort(100, 0, 640, 50));
  EXPECT_DOUBLE_EQ(p.lead(), 16.0);  // kept, and doubled: the run lasted its longest
  EXPECT_EQ(p.backoff(), 64u);
  EXPECT_DOUBLE_EQ(p.runWork(), 2900.0);  // the next run: 2000 + 0 + 900
}

TEST(CoastPolicy, ACostlyRunSwitchesCoastingOffThenRetries) {
  CoastPolicy p(8.0);
  p.enlargedAll(1, resort(100, 0, 0, 0));      // coasting starts; three probation runs follow
  p.enlargedAll(1, resort(100, 0, 0, 0));      // the first ends, unjudged
  p.enlargedAll(1, resort(100, 0, 0, 0));      // the second
  p.scanned(1000000);                          // a probation run is not judged, however costly
  p.enlargedAll(33, resort(100, 0, 640, 50));  // 2900, not judged
  EXPECT_DOUBLE_EQ(p.lead(), 8.0);
  p.scanned(20000);                            // + 80000 = 82900
  // 82900 / 32 = 2590.6 per update > 1300: off until update 65 + 64 = 129, 128 next time.
  p.enlargedAll(65, resort(100, 0, 640, 50));
  EXPECT_DOUBLE_EQ(p.lead(), 0.0);
  EXPECT_EQ(p.retryAt(), 129u);
  EXPECT_EQ(p.backoff(), 128u);
  // Off: scans are not counted; without motion nothing is sorted, with it the given bounds.
  const double work = p.runWork();
  p.scanned(1000);
  EXPECT_DOUBLE_EQ(p.runWork(), work);
  EXPECT_EQ(p.step(70, 5, 100, false, false), Step::kNothing);
  EXPECT_EQ(p.step(70, 0, 100, false, true), Step::kResort);
  EXPECT_EQ(p.step(128, 0, 100, false, true), Step::kResort);
  EXPECT_DOUBLE_EQ(p.lead(), 0.0);
  // Due, and a proxy moved: coasting starts again with everybody enlarged, and that first
  // enlargement ends no run (nothing is judged, however costly).
  EXPECT_EQ(p.step(129, 0, 100, false, true), Step::kEnlargeAll);
  EXPECT_DOUBLE_EQ(p.lead(), 8.0);
  p.scanned(1000000);
  p.enlargedAll(129, resort(100, 0, 640, 50));
  EXPECT_DOUBLE_EQ(p.lead(), 8.0);
  EXPECT_EQ(p.backoff(), 128u);
  // Then the probation runs (not judged), and a cheap run after them resets the back-off to 64.
  p.scanned(1000000);
  p.enlargedAll(137, resort(100, 0, 640, 50));
  p.scanned(1000000);
  p.enlargedAll(145, resort(100, 0, 640, 50));
  p.scanned(1000000);
  p.enlargedAll(161, resort(100, 0, 640, 50));
  EXPECT_DOUBLE_EQ(p.lead(), 8.0);
  EXPECT_EQ(p.backoff(), 128u);
  p.enlargedAll(193, resort(100, 0, 640, 50));  // 2900 / 32 < 1300
  EXPECT_DOUBLE_EQ(p.lead(), 16.0);  // (doubled: a run of 32, its longest)
  EXPECT_EQ(p.backoff(), 64u);
}

TEST(CoastPolicy, BackOffDoublesAfterEachFailureInARowUpTo4096) {
  CoastPolicy p(8.0);
  std::uint32_t update = 1;
  // Coasting starts, then the probation runs end, unjudged.
  for (int run = 0; run <= CoastPolicy::kProbationRuns; ++run) {
    p.enlargedAll(update, resort(100, 0, 640, 50));
  }
  const std::uint32_t expected_off[] = {64, 128, 256, 512, 1024, 2048, 4096, 4096, 4096};
  for (std::uint32_t off : expected_off) {
    p.scanned(1000000);  // far more than 1300 per update over any run below
    update += 32;
    p.enlargedAll(update, resort(100, 0, 640, 50));
    ASSERT_DOUBLE_EQ(p.lead(), 0.0);
    EXPECT_EQ(p.retryAt(), update + off);
    update = p.retryAt();
    ASSERT_EQ(p.step(update, 0, 100, false, true), Step::kEnlargeAll);
    // Starts the next run, then the probation runs end, unjudged.
    for (int run = 0; run <= CoastPolicy::kProbationRuns; ++run) {
    p.enlargedAll(update, resort(100, 0, 640, 50));
  }
  }
}

TEST(CoastPolicy, WithoutAnEstimateTheSwapsOfTheReSortStandIn) {
  // Judged with swaps 3200 (no estimate): a pass with 3200 / 32 = 100 swaps per update costs
  // 900 + 1000; with the 50 pairs' scan, 2100. A run of 2100 * 32 = 67200 is not more: kept;
  // one unit more per update is: off.
  CoastPolicy kept(8.0), off(8.0);
  for (CoastPolicy* p : {&kept, &off}) {
    p->enlargedAll(0, resort(100, 0, 0, 0));   // coasting starts; three probation runs follow
    p->enlargedAll(0, resort(100, 0, 0, 0));
    p->enlargedAll(0, resort(100, 0, 0, 0));
    p->enlargedAll(1, resort(100, 0, 0, 50));  // 2900 each, the probation ends
  }
  kept.scanned((67200 - 2900) / 4);
  off.scanned((67200 + 32 - 2900) / 4);
  kept.enlargedAll(33, resort(100, 3200, -1, 50));
  off.enlargedAll(33, resort(100, 3200, -1, 50));
  EXPECT_DOUBLE_EQ(kept.lead(), 16.0);  // kept (the long lead: a run of 32)
  EXPECT_DOUBLE_EQ(off.lead(), 0.0);
}

TEST(CoastPolicy, ARetryThatWouldFailIsPostponedWithoutEnlargingAnybody) {
  CoastPolicy p(8.0);
  for (int run = 0; run <= CoastPolicy::kProbationRuns; ++run) p.enlargedAll(1, resort(100, 0, 640, 50));
  p.scanned(1000000);
  p.enlargedAll(33, resort(100, 0, 640, 50));  // fails: off until 33 + 64 = 97, 128 next time
  ASSERT_DOUBLE_EQ(p.lead(), 0.0);
  EXPECT_FALSE(p.retryDue(96));
  EXPECT_TRUE(p.retryDue(97));
  // Postponed at 97: due again 64 updates later, the back-off unchanged; coasting stays off
  // and nobody is enlarged in between.
  p.postponeRetry(97);
  EXPECT_FALSE(p.retryDue(160));
  EXPECT_EQ(p.step(160, 0, 100, false, true), Step::kResort);
  EXPECT_TRUE(p.retryDue(161));
  EXPECT_EQ(p.backoff(), 128u);
  EXPECT_DOUBLE_EQ(p.lead(), 0.0);
  // Not postponed: the retry starts as before.
  EXPECT_EQ(p.step(161, 0, 100, false, true), Step::kEnlargeAll);
  EXPECT_DOUBLE_EQ(p.lead(), 8.0);
  EXPECT_FALSE(p.retryDue(161));
  // Never due while coasting, nor with coasting turned off for good.
  CoastPolicy never(0.0);
  EXPECT_FALSE(never.retryDue(100000));
}

// Issue 26 (the tail): after two failures in a row, a retry in the scene coasting failed in
// is postponed by 64 updates, enlarging nobody, until the motion is calmer by half than in the stretch off after the
// failure, the crowd has grown or shrunk by a quarter, or the failure is 4 096 updates old.
// Expected values from those rules.
TEST(CoastPolicy, ARetryInTheSceneThatFailedIsPostponedUntilTheSceneChanges) {
  // Coasting fails at 33 (off for 64), is retried at 97 and fails again at 129 (off for 128,
  // 256 next time): its next retry is due at 257.
  auto failedTwice = [](CoastPolicy* p) {
    std::uint32_t at = 1;
    for (int run = 0; run <= CoastPolicy::kProbationRuns; ++run) p->enlargedAll(at, resort(100, 0, 640, 50));
    for (int failure = 0; failure < 2; ++failure) {
      p->scanned(1000000);
      at += 32;
      p->enlargedAll(at, resort(100, 0, 640, 50));
      ASSERT_DOUBLE_EQ(p->lead(), 0.0);
      at = p->retryAt();
      if (failure == 0) {
        // The first failure is retried as before, whatever the scene.
        p->sortedOff(400.0);
        EXPECT_FALSE(p->repeatsFailure(at, 100));
        ASSERT_EQ(p->step(at, 0, 100, false, true), Step::kEnlargeAll);
        for (int run = 0; run <= CoastPolicy::kProbationRuns; ++run) p->enlargedAll(at, resort(100, 0, 640, 50));
      }
    }
    ASSERT_EQ(at, 257u);
    ASSERT_EQ(p->backoff(), 256u);
  };
  CoastPolicy p(8.0);
  failedTwice(&p);
  // Never failed (or coasting never tried): nothing to repeat.
  CoastPolicy fresh(8.0);
  EXPECT_FALSE(fresh.repeatsFailure(257, 100));
  // Off, the insertion sorts make 400 swaps an update.
  for (int u = 130; u < 257; ++u) p.sortedOff(400.0);
  ASSERT_TRUE(p.retryDue(257));
  // The first retry after the second failure ends the reference's stretch, the scene the
  // same: postponed by 64; the back-off unchanged; coasting stays off.
  EXPECT_TRUE(p.repeatsFailure(257, 100));
  EXPECT_EQ(p.retryAt(), 257u + 64u);
  EXPECT_EQ(p.backoff(), 256u);
  EXPECT_DOUBLE_EQ(p.lead(), 0.0);
  EXPECT_EQ(p.step(320, 0, 100, false, true), Step::kResort);
  // The same motion (a little calmer, 250 of 400: not by half) and a crowd within a quarter
  // (75 and 125 of 100): postponed again.
  for (int u = 0; u < 64; ++u) p.sortedOff(250.0);
  EXPECT_TRUE(p.repeatsFailure(321, 75));
  EXPECT_EQ(p.retryAt(), 321u + 64u);
  EXPECT_TRUE(p.repeatsFailure(385, 125));
  EXPECT_EQ(p.retryAt(), 385u + 64u);
  // A crowd grown by more than a quarter (126 of 100): tried. So is a shrunk one (74).
  EXPECT_FALSE(p.repeatsFailure(449, 126));
  EXPECT_FALSE(p.repeatsFailure(449, 74));
  EXPECT_EQ(p.retryAt(), 449u);  // (not postponed)
  // A motion calmer by half (the average falls below 200 of 400): tried.
  for (int u = 0; u < 64; ++u) p.sortedOff(150.0);
  EXPECT_FALSE(p.repeatsFailure(449, 100));
  EXPECT_EQ(p.step(449, 0, 100, false, true), Step::kEnlargeAll);
  EXPECT_DOUBLE_EQ(p.lead(), 8.0);
  // Not a number of swaps, or a negative one, is no measurement.
  CoastPolicy q(8.0);
  failedTwice(&q);
  q.sortedOff(400.0);
  q.sortedOff(std::nan(""));
  EXPECT_TRUE(q.repeatsFailure(257, 100));  // the reference: 400
  q.sortedOff(-1.0);
  EXPECT_TRUE(q.repeatsFailure(321, 100));
  // A retry postponed because its runs would be too short also ends the reference's stretch:
  // a calmer motion after it is measured against the stretch before.
  CoastPolicy r(8.0);
  failedTwice(&r);
  for (int u = 130; u < 257; ++u) r.sortedOff(4000.0);
  r.postponeRetry(257);
  for (int u = 0; u < 64; ++u) r.sortedOff(100.0);
  EXPECT_FALSE(r.repeatsFailure(321, 100));
}

TEST(CoastPolicy, ARetryAfterAnEpisodeThatPaidIsTried) {
  // Fails at 33 (off for 64), is retried at 97; after its probation `paid` judged runs of 32
  // updates pay (2900 each, against 1300 an update without coasting: 41600 a run), then one
  // fails with `scans` candidates scanned (2900 + 4 scans over its 32 updates).
  auto episode = [](CoastPolicy* p, int paid, double scans) {
    std::uint32_t at = 1;
    for (int run = 0; run <= CoastPolicy::kProbationRuns; ++run) p->enlargedAll(at, resort(100, 0, 640, 50));
    p->scanned(1000000);
    p->enlargedAll(at + 32, resort(100, 0, 640, 50));
    at = p->retryAt();
    EXPECT_FALSE(p->repeatsFailure(at, 100));  // a first failure: retried
    EXPECT_EQ(p->step(at, 0, 100, false, true), Step::kEnlargeAll);
    for (int run = 0; run <= CoastPolicy::kProbationRuns; ++run) p->enlargedAll(at, resort(100, 0, 640, 50));
    for (int run = 0; run < paid; ++run) {
      at += 32;
      p->enlargedAll(at, resort(100, 0, 640, 50));
      EXPECT_DOUBLE_EQ(p->lead(), 16.0);  // runs of 32: the long lead
    }
    p->scanned(static_cast<std::size_t>(scans));
    at += 32;
    p->enlargedAll(at, resort(100, 0, 640, 50));
    EXPECT_DOUBLE_EQ(p->lead(), 0.0);
    p->sortedOff(400.0);
    return p->retryAt();
  };
  // The retry's first judged run fails: the episode cost more than not coasting: postponed.
  CoastPolicy none(8.0);
  EXPECT_TRUE(none.repeatsFailure(episode(&none, 0, 1000000), 100));
  // One run paid, then one far dearer (the robot cells' alternation): (2900 + 4002900) /
  // (2 x 41600) > 0.9: postponed.
  CoastPolicy one(8.0);
  EXPECT_TRUE(one.repeatsFailure(episode(&one, 1, 1000000), 100));
  // One run paid, then one a little dearer than not coasting (1400 an update: 11200 scans):
  // (2900 + 47700) / 83200 = 0.61: the episode saved, the retry is tried.
  CoastPolicy saved(8.0);
  EXPECT_FALSE(saved.repeatsFailure(episode(&saved, 1, 11200), 100));
  // No run paid and the failing one at 1400 an update: 47700 / 41600 > 0.9: postponed.
  CoastPolicy marginal(8.0);
  EXPECT_TRUE(marginal.repeatsFailure(episode(&marginal, 0, 11200), 100));
}

TEST(CoastPolicy, ARetryIsTriedWhateverTheScene4096UpdatesAfterTheFailure) {
  CoastPolicy p(8.0);
  for (int run = 0; run <= CoastPolicy::kProbationRuns; ++run) p.enlargedAll(1, resort(100, 0, 640, 50));
  // Fails at 33 (off for 64), is retried at 97 and fails again at 129 (off for 128).
  p.scanned(1000000);
  p.enlargedAll(1 + 32, resort(100, 0, 640, 50));
  ASSERT_EQ(p.step(97, 0, 100, false, true), Step::kEnlargeAll);
  for (int run = 0; run <= CoastPolicy::kProbationRuns; ++run) p.enlargedAll(97, resort(100, 0, 640, 50));
  p.scanned(1000000);
  p.enlargedAll(97 + 32, resort(100, 0, 640, 50));
  ASSERT_DOUBLE_EQ(p.lead(), 0.0);
  ASSERT_EQ(p.retryAt(), 129u + 128u);
  p.sortedOff(400.0);
  std::uint32_t update = p.retryAt();
  int postponed = 0;
  while (update < 129 + 4096) {
    ASSERT_TRUE(p.retryDue(update));
    ASSERT_TRUE(p.repeatsFailure(update, 100));
    ++postponed;
    update = p.retryAt();
  }
  EXPECT_EQ(postponed, 62);  // 257, 321, ..., 4161: every 64 updates
  EXPECT_EQ(update, 129u + 64u * 64u);
  EXPECT_FALSE(p.repeatsFailure(update, 100));
  EXPECT_EQ(p.step(update, 0, 100, false, true), Step::kEnlargeAll);
  // It fails again: a new failure, a new reference, the back-off doubled (256 -> 512).
  for (int run = 0; run <= CoastPolicy::kProbationRuns; ++run) p.enlargedAll(update, resort(100, 0, 640, 50));
  p.scanned(1000000);
  p.enlargedAll(update + 32, resort(100, 0, 640, 50));
  EXPECT_DOUBLE_EQ(p.lead(), 0.0);
  EXPECT_EQ(p.retryAt(), update + 32 + 256);
  EXPECT_EQ(p.backoff(), 512u);
  EXPECT_TRUE(p.repeatsFailure(p.retryAt(), 100));
}

// Issue 26 (the tail): when a run's end is spread over the updates before it (the next
// arrays), and over how many. Expected values from the documented rules: nothing before a
// judged run has ended; runs shorter than 16 updates end at once; a build over
// min(spread, run - 5, max(6, run / 2 - 2)) updates starts when it would be swapped in 3
// updates before the run's expected end; a swap before the run ended lengthens the expected
// run by one (up to the longest, 4 coast_updates), one at its end keeps it, a run ended at
// once sets it.
TEST(CoastPolicy, RunEndsAreSpreadOnlyOverLongRuns) {
  CoastPolicy p(8.0);
  const CoastPolicy::Resort cheap = resort(100, 0, 1000000, 0);  // a run well worth coasting
  for (std::uint32_t u : {10u, 18u, 26u, 34u}) p.enlargedAll(u, cheap);  // probation
  EXPECT_EQ(p.longestRun(), 32u);
  EXPECT_FALSE(p.nextDue(40, p.nextSlices(32)));  // no judged run has ended yet
  // Steady motion: everybody left together after 9 updates. Too short to spread.
  p.enlargedAll(43, cheap);
  EXPECT_DOUBLE_EQ(p.lead(), 8.0);
  EXPECT_EQ(p.expectedRun(), 9u);
  EXPECT_EQ(p.nextSlices(32), 0u);
  EXPECT_FALSE(p.nextDue(45, p.nextSlices(32)));
  // A run of 27 updates (43 -> 70, long enough to spread).
  p.enlargedAll(70, cheap);
  EXPECT_DOUBLE_EQ(p.lead(), 8.0);  // 27 + 3 + 1 < 32: the lead stays
  EXPECT_EQ(p.expectedRun(), 27u);
  EXPECT_EQ(p.nextSlices(32), 11u);  // 27 / 2 - 2
  EXPECT_EQ(p.nextSlices(8), 8u);
  EXPECT_FALSE(p.nextDue(70, 11));  // not in the update of the enlargement
  EXPECT_FALSE(p.nextDue(82, 11));  // 82 + 11 + 3 < 70 + 27
  EXPECT_TRUE(p.nextDue(83, 11));
  EXPECT_EQ(p.nextSwapAt(83, 11), 94u);  // 3 updates before the run's expected end (97)
  EXPECT_FALSE(p.nextDue(85, 8));
  EXPECT_TRUE(p.nextDue(86, 8));
  EXPECT_EQ(p.nextSwapAt(86, 8), 94u);
  EXPECT_EQ(p.nextSwapAt(90, 8), 98u);  // a late start: its slices first
  // A swap before the run ended: the next run is expected an update longer, up to the longest.
  p.enlargedAll(94, cheap, CoastPolicy::End::kSpreadEarly);
  EXPECT_EQ(p.expectedRun(), 28u);
  // A run of 20 updates ended at once (114), then swaps before and at the runs' ends.
  p.enlargedAll(114, cheap);
  EXPECT_EQ(p.expectedRun(), 20u);
  EXPECT_EQ(p.nextSlices(32), 8u);  // 20 / 2 - 2
  EXPECT_EQ(p.nextSlices(4), 4u);
  p.enlargedAll(131, cheap, CoastPolicy::End::kSpreadEarly);
  EXPECT_EQ(p.expectedRun(), 21u);
  // A swap when the run ended (its proxies left their bounds) after 19 updates: the next
  // runs are expected to last as long (not 22: then the build would be overtaken).
  p.enlargedAll(150, cheap, CoastPolicy::End::kSpreadAtEnd);
  EXPECT_EQ(p.expectedRun(), 19u);
  EXPECT_DOUBLE_EQ(p.lead(), 8.0);
  // Never while coasting is off: a costly run (a million candidates scanned, nothing to
  // re-sort without coasting) switches it off.
  p.scanned(1000000);
  p.enlargedAll(162, resort(100, 0, 0, 0));
  EXPECT_DOUBLE_EQ(p.lead(), 0.0);
  EXPECT_FALSE(p.nextDue(200, 8));
}

// Issue 26 (jitter): the long lead. Expected values from the documented rules: a judged run
// at the configured lead that lasted its longest (4 coast_updates), or was swapped out at
// most kSwapMargin + 1 updates before, doubles the lead (kLongLead); runs then last up to 6
// coast_updates (kLongRuns long leads), expected that long at once; a judged run shorter than
// 4 coast_updates (however it ended) brings the configured lead back. Probation and failures
// start again from the configured lead.
TEST(CoastPolicy, TheLeadDoublesWhileRunsLastTheirLongestAndComesBackWhenOneIsShorter) {
  EXPECT_DOUBLE_EQ(CoastPolicy::kLongLead, 2.0);
  EXPECT_DOUBLE_EQ(CoastPolicy::kLongRuns, 3.0);
  CoastPolicy p(8.0);
  const CoastPolicy::Resort cheap = resort(100, 0, 1000000, 0);
  EXPECT_EQ(p.step(1, 0, 100, false, true), Step::kNothing);  // coasting from the start
  // Probation (the first enlargement and three runs) never doubles it, however long a run.
  for (std::uint32_t u : {8u, 16u, 24u, 64u}) p.enlargedAll(u, cheap);
  EXPECT_FALSE(p.longLead());
  EXPECT_DOUBLE_EQ(p.lead(), 8.0);
  // A judged run of 27 ended at once: 27 + 3 + 1 < 32.
  p.enlargedAll(91, cheap);
  EXPECT_DOUBLE_EQ(p.lead(), 8.0);
  EXPECT_EQ(p.longestRun(), 32u);
  // A run swapped out early at 28 updates: 28 + 4 >= 32, the lead doubles.
  p.enlargedAll(119, cheap, CoastPolicy::End::kSpreadEarly);
  EXPECT_TRUE(p.longLead());
  EXPECT_DOUBLE_EQ(p.lead(), 16.0);
  EXPECT_EQ(p.longestRun(), 48u);
  EXPECT_EQ(p.expectedRun(), 48u);
  EXPECT_EQ(p.nextSlices(16), 30u);  // 2 x 48 / 3 - 2 at the long lead: up to twice spread_updates
  EXPECT_EQ(p.nextSlices(8), 16u);
  // Its runs end at 48 updates, nothing leaving.
  EXPECT_EQ(p.step(119 + 47, 0, 100, false, true), Step::kNothing);
  EXPECT_EQ(p.step(119 + 48, 0, 100, false, true), Step::kEnlargeAll);
  p.enlargedAll(167, cheap);
  EXPECT_DOUBLE_EQ(p.lead(), 16.0);
  EXPECT_EQ(p.expectedRun(), 48u);
  // A run of 32 (swapped out early) keeps it.
  p.enlargedAll(199, cheap, CoastPolicy::End::kSpreadEarly);
  EXPECT_DOUBLE_EQ(p.lead(), 16.0);
  // A run of 31, swapped out when it ended: back to 8, expected 31, longest 32.
  p.enlargedAll(230, cheap, CoastPolicy::End::kSpreadAtEnd);
  EXPECT_FALSE(p.longLead());
  EXPECT_DOUBLE_EQ(p.lead(), 8.0);
  EXPECT_EQ(p.longestRun(), 32u);
  EXPECT_EQ(p.expectedRun(), 31u);
  EXPECT_EQ(p.step(230 + 31, 0, 100, false, true), Step::kNothing);
  EXPECT_EQ(p.step(230 + 32, 0, 100, false, true), Step::kEnlargeAll);
  // Up again at the longest; then a failure: coasting resumes at the configured lead.
  p.enlargedAll(262, cheap);
  EXPECT_DOUBLE_EQ(p.lead(), 16.0);
  p.scanned(1000000);
  p.enlargedAll(302, resort(100, 0, 0, 0));
  EXPECT_DOUBLE_EQ(p.lead(), 0.0);
  EXPECT_EQ(p.longestRun(), 32u);
  EXPECT_EQ(p.step(302 + 64, 0, 100, false, true), Step::kEnlargeAll);
  EXPECT_DOUBLE_EQ(p.lead(), 8.0);
  // At most 16: the monitor's lead of 16 stays, runs of up to 64; a lead of 4 doubles to 8.
  EXPECT_DOUBLE_EQ(CoastPolicy::kLongLeadAtMost, 16.0);
  CoastPolicy q(16.0), r(4.0);
  for (std::uint32_t u : {16u, 32u, 48u, 64u}) q.enlargedAll(u, cheap);
  q.enlargedAll(128, cheap);
  EXPECT_DOUBLE_EQ(q.lead(), 16.0);
  EXPECT_EQ(q.longestRun(), 64u);
  for (std::uint32_t u : {4u, 8u, 12u, 16u}) r.enlargedAll(u, cheap);
  r.enlargedAll(32, cheap);
  EXPECT_DOUBLE_EQ(r.lead(), 8.0);
  EXPECT_EQ(r.longestRun(), 24u);
}

// Issue 26 (the tail of steady motion): the steady lead. Expected values from the documented
// rules: a judged run at the configured lead that ends at once before kMinSpreadRun (16)
// updates takes kSteadyLead (3) times the lead for the enlargement that ends it, when that is
// at most kSteadyLeadAtMost (24); the next runs are expected 3 times as long. A run at it
// shorter than 16 updates, costing more per update than the last judged run at the configured
// lead, or costing more than not coasting, brings the configured lead back and blocks the
// steady lead for 8 judged runs (16 after a second such run in a row); one that
// lasts its longest (4 coast_updates) brings it back without a block. One whose proxies would
// leave it before 16 updates anyway (the cap) is not taken and blocked alike.
TEST(CoastPolicy, TheLeadTriplesWhenRunsEndTogetherTooSoonToSpreadAndComesBack) {
  EXPECT_DOUBLE_EQ(CoastPolicy::kSteadyLead, 3.0);
  EXPECT_DOUBLE_EQ(CoastPolicy::kSteadyLeadAtMost, 24.0);
  EXPECT_EQ(CoastPolicy::kSteadyBlock, 8u);
  CoastPolicy p(8.0);
  const CoastPolicy::Resort cheap = resort(100, 0, 1000000, 0);
  // Probation (the first enlargement and three runs): never, however short the runs.
  for (std::uint32_t u : {8u, 16u, 24u, 32u}) {
    endsAtOnce(&p, u);
    EXPECT_FALSE(p.steadyLead());
    p.enlargedAll(u, cheap);
  }
  // A judged run of 9 ends at once: the enlargement that ends it takes 24.
  endsAtOnce(&p, 41);
  EXPECT_TRUE(p.steadyLead());
  EXPECT_FALSE(p.longLead());
  EXPECT_DOUBLE_EQ(p.lead(), 24.0);
  p.enlargedAll(41, cheap);
  EXPECT_DOUBLE_EQ(p.lead(), 24.0);
  EXPECT_EQ(p.expectedRun(), 27u);  // 3 x 9
  EXPECT_EQ(p.longestRun(), 32u);
  EXPECT_EQ(p.nextSlices(16), 11u);  // 27 / 2 - 2
  EXPECT_EQ(p.step(41 + 31, 0, 100, false, true), Step::kNothing);
  EXPECT_EQ(p.step(41 + 32, 0, 100, false, true), Step::kEnlargeAll);
  // A run of 25 at it, swapped in when it ended: it stays, expected 25.
  p.enlargedAll(66, cheap, CoastPolicy::End::kSpreadAtEnd);
  EXPECT_DOUBLE_EQ(p.lead(), 24.0);
  EXPECT_EQ(p.expectedRun(), 25u);
  // A run of 12 at it (the lead's cap) ends at once: back to 8, blocked for 8 judged runs.
  endsAtOnce(&p, 78);
  EXPECT_DOUBLE_EQ(p.lead(), 24.0);  // (only a run at the configured lead takes it)
  p.enlargedAll(78, cheap);
  EXPECT_FALSE(p.steadyLead());
  EXPECT_DOUBLE_EQ(p.lead(), 8.0);
  std::uint32_t u = 78;
  for (int i = 0; i < 8; ++i) {
    u += 9;
    endsAtOnce(&p, u);
    EXPECT_DOUBLE_EQ(p.lead(), 8.0) << "judged run " << i << " after the block began";
    p.enlargedAll(u, cheap);
  }
  u += 9;
  endsAtOnce(&p, u);
  EXPECT_DOUBLE_EQ(p.lead(), 24.0);
  p.enlargedAll(u, cheap);
  // A run at it that costs more than not coasting (a million candidates scanned): back to 8,
  // not off, and blocked for 16 judged runs (a second run in a row that did not pay).
  u += 20;
  p.scanned(1000000);
  endsAtOnce(&p, u);
  p.enlargedAll(u, resort(100, 0, 0, 0));
  EXPECT_DOUBLE_EQ(p.lead(), 8.0);
  for (int i = 0; i < 16; ++i) {
    u += 9;
    endsAtOnce(&p, u);
    EXPECT_DOUBLE_EQ(p.lead(), 8.0) << "judged run " << i << " after the second block began";
    p.enlargedAll(u, cheap);
  }
  u += 9;
  endsAtOnce(&p, u);
  EXPECT_DOUBLE_EQ(p.lead(), 24.0);
  p.enlargedAll(u, cheap);
  // A run at it that lasts its longest (the motion slowed): back to 8 without a block.
  u += 32;
  p.enlargedAll(u, cheap);
  EXPECT_DOUBLE_EQ(p.lead(), 8.0);
  u += 9;
  endsAtOnce(&p, u);
  EXPECT_DOUBLE_EQ(p.lead(), 24.0);
  // A run of 16 or more at the configured lead never takes it (long enough to spread), nor does
  // one at its longest (the long lead), nor a lead whose triple is over 24, nor steady_lead off.
  CoastPolicy q(8.0), r(16.0), t(8.0, false);
  for (CoastPolicy* c : {&q, &r, &t}) {
    for (std::uint32_t v : {16u, 32u, 48u, 64u}) c->enlargedAll(v, cheap);
  }
  endsAtOnce(&q, 80);
  EXPECT_DOUBLE_EQ(q.lead(), 8.0);
  q.enlargedAll(80, cheap);
  EXPECT_DOUBLE_EQ(q.lead(), 8.0);
  endsAtOnce(&q, 112);
  EXPECT_DOUBLE_EQ(q.lead(), 8.0);
  q.enlargedAll(112, cheap);
  EXPECT_TRUE(q.longLead());
  endsAtOnce(&r, 73);
  EXPECT_DOUBLE_EQ(r.lead(), 16.0);
  endsAtOnce(&t, 73);
  EXPECT_DOUBLE_EQ(t.lead(), 8.0);
  EXPECT_FALSE(t.steadyLeadDue(73));
  // Due, but the motion would leave bounds enlarged with it before 16 updates (its cap): not
  // taken, and blocked for 8 judged runs, as after a run at it that was too short.
  CoastPolicy w(8.0);
  for (std::uint32_t v : {8u, 16u, 24u, 32u}) w.enlargedAll(v, cheap);
  EXPECT_TRUE(w.steadyLeadDue(41));
  endsAtOnce(&w, 41, true);
  EXPECT_DOUBLE_EQ(w.lead(), 8.0);
  w.enlargedAll(41, cheap);
  u = 41;
  for (int i = 0; i < 8; ++i) {
    u += 9;
    EXPECT_FALSE(w.steadyLeadDue(u)) << "judged run " << i << " after the block began";
    w.enlargedAll(u, cheap);
  }
  EXPECT_TRUE(w.steadyLeadDue(u + 9));
  // A run at it that cost more per update than the last judged run at 8 (which cost 2 900
  // units over 9 updates: enlarging 100 proxies, 20 each, and a pass over 3 axes of 200
  // endpoints, 1.5 each), though less than not coasting (a rebuild of one axis, 3 900 units
  // per update): 2 900 + 2 000 candidates scanned at 4 units over 25 updates is 436 a
  // update. Back to 8, blocked.
  CoastPolicy z(8.0);
  for (std::uint32_t v : {8u, 16u, 24u, 32u}) z.enlargedAll(v, cheap);
  endsAtOnce(&z, 41);
  z.enlargedAll(41, cheap);
  EXPECT_DOUBLE_EQ(z.lead(), 24.0);
  z.scanned(2000);
  z.enlargedAll(66, cheap, CoastPolicy::End::kSpreadAtEnd);
  EXPECT_DOUBLE_EQ(z.lead(), 8.0);
  EXPECT_FALSE(z.steadyLeadDue(75));
}

// Runs of 8 updates that end at once, judged against not coasting: 4 per pair (50) plus the
// cheaper of a pass over 3 axes of 200 endpoints with 640 / 8 swaps per update (900 + 800)
// and a rebuild of one axis (5 150): 1 900 units per update. Each run starts with the 2 900
// units of its enlargement (100 proxies at 20, the pass at 900); `scans` candidates add 4
// each. The tail's rule adds every update's own part, 20 units per live proxy (2 000), to
// both sides. Returns that ratio of the run.
double runOfEight(CoastPolicy* p, std::uint32_t* update, std::size_t scans) {
  p->scanned(scans);
  *update += 8;
  p->enlargedAll(*update, resort(100, 0, 640, 50));
  return ((2900.0 + 4.0 * static_cast<double>(scans)) / 8.0 + 2000.0) / (1900.0 + 2000.0);
}

// Probation: coasting starts at `update` and three runs of 8 follow, unjudged.
void startCoasting(CoastPolicy* p, std::uint32_t* update) {
  for (int i = 0; i < 4; ++i) {
    p->enlargedAll(*update, resort(100, 0, 640, 50));
    *update += 8;
  }
  *update -= 8;
}

TEST(CoastPolicy, RunsEndingAtOnceInARowCoastOnlyWhereTheySaveAQuarter) {
  EXPECT_DOUBLE_EQ(CoastPolicy::kAtOnceWorth, 0.75);
  EXPECT_EQ(CoastPolicy::kAtOnceRuns, 3);
  EXPECT_DOUBLE_EQ(CoastPolicy::kProxyWork, 20.0);
  // (steady_lead off: the runs stay at the configured lead and end at once.)
  // With 1 935 candidates a run costs 1 330 units per update, 0.7 of not coasting: it pays by
  // the cost model, but with every update's own part it is 0.854, and three in a row switch
  // coasting off, for 64 updates.
  CoastPolicy p(8.0, false);
  std::uint32_t u = 1;
  startCoasting(&p, &u);
  EXPECT_NEAR(runOfEight(&p, &u, 1935), 3330.0 / 3900.0, 1e-12);
  EXPECT_DOUBLE_EQ(p.lead(), 8.0);
  runOfEight(&p, &u, 1935);
  EXPECT_DOUBLE_EQ(p.lead(), 8.0);
  runOfEight(&p, &u, 1935);
  EXPECT_DOUBLE_EQ(p.lead(), 0.0);
  EXPECT_EQ(p.retryAt(), u + 64);
  // The retry due then, in the same scene (no swaps measured off: the same motion; the same
  // live count), is postponed by 64 updates, though it is the first failure; with a third more
  // proxies it is tried.
  const std::uint32_t due = p.retryAt();
  EXPECT_TRUE(p.repeatsFailure(due, 100));
  EXPECT_EQ(p.retryAt(), due + 64);
  EXPECT_FALSE(p.repeatsFailure(due + 64, 134));
  // The retry: after its probation, its first judged run at 0.854 is the fourth in a row,
  // and switches coasting off at once, for 128 updates.
  u = p.retryAt();
  EXPECT_EQ(p.step(u, 0, 100, false, true), Step::kEnlargeAll);
  for (int i = 0; i < 3; ++i) {
    p.enlargedAll(u, resort(100, 0, 640, 50));
    u += 8;
  }
  p.enlargedAll(u, resort(100, 0, 640, 50));
  EXPECT_DOUBLE_EQ(p.lead(), 8.0);
  runOfEight(&p, &u, 1935);
  EXPECT_DOUBLE_EQ(p.lead(), 0.0);
  EXPECT_EQ(p.retryAt(), u + 128);

  // With 500 candidates (612.5 units per update, 0.67) they keep coasting, however many in a
  // row.
  CoastPolicy q(8.0, false);
  u = 1;
  startCoasting(&q, &u);
  for (int i = 0; i < 10; ++i) {
    EXPECT_NEAR(runOfEight(&q, &u, 500), 2612.5 / 3900.0, 1e-12);
    EXPECT_DOUBLE_EQ(q.lead(), 8.0) << "run " << i;
  }
  EXPECT_EQ(q.backoff(), 64u);
  // ... until the last three of the row are dear enough: one at 0.854 after ten at 0.670
  // keeps it (0.731), a second switches it off (0.793).
  runOfEight(&q, &u, 1935);
  EXPECT_DOUBLE_EQ(q.lead(), 8.0);
  runOfEight(&q, &u, 1935);
  EXPECT_DOUBLE_EQ(q.lead(), 0.0);

  // The mean of the last three counts: 0.854, 0.670, 0.670 is 0.731, kept; then 0.854 makes
  // it 0.731 again, kept; another 0.854 makes it 0.793: off.
  CoastPolicy r(8.0, false);
  u = 1;
  startCoasting(&r, &u);
  runOfEight(&r, &u, 1935);
  runOfEight(&r, &u, 500);
  runOfEight(&r, &u, 500);
  EXPECT_DOUBLE_EQ(r.lead(), 8.0);
  runOfEight(&r, &u, 1935);
  EXPECT_DOUBLE_EQ(r.lead(), 8.0);
  runOfEight(&r, &u, 1935);
  EXPECT_DOUBLE_EQ(r.lead(), 0.0);

  // A spread run between breaks the row: two more at 0.854 after it do not switch off, a third
  // does.
  CoastPolicy t(8.0, false);
  u = 1;
  startCoasting(&t, &u);
  runOfEight(&t, &u, 1935);
  runOfEight(&t, &u, 1935);
  u += 8;
  t.enlargedAll(u, resort(100, 0, 640, 50), CoastPolicy::End::kSpreadAtEnd);
  runOfEight(&t, &u, 1935);
  runOfEight(&t, &u, 1935);
  EXPECT_DOUBLE_EQ(t.lead(), 8.0);
  runOfEight(&t, &u, 1935);
  EXPECT_DOUBLE_EQ(t.lead(), 0.0);

  // Runs at their longest (32 updates at a lead of 8) end at once because the motion calmed:
  // they never count (here (2 900 + 29 600) / 32 = 1 015.6 units per update against 1 300,
  // with 640 / 32 swaps per update: 0.91 with every update's part).
  CoastPolicy w(8.0, false);
  u = 1;
  startCoasting(&w, &u);
  for (int i = 0; i < 3; ++i) {
    w.scanned(7400);
    u += 32;
    w.enlargedAll(u, resort(100, 0, 640, 50));
  }
  EXPECT_GT(w.lead(), 0.0);

  // Nor does the run at whose end the steady lead is taken (the next ones are spread), and a
  // run at the steady lead ends the row: here it is too short (8 updates) and brings the
  // configured lead back from the next enlargement on (the run that enlargement ends was
  // still enlarged with 24); two runs at 0.854 after those keep coasting, a third does not.
  CoastPolicy z(8.0);
  u = 1;
  startCoasting(&z, &u);
  z.scanned(1935);
  u += 8;
  ASSERT_TRUE(z.steadyLeadDue(u));
  z.takeSteadyLead(false);
  z.enlargedAll(u, resort(100, 0, 640, 50));
  EXPECT_TRUE(z.steadyLead());
  runOfEight(&z, &u, 1935);
  EXPECT_DOUBLE_EQ(z.lead(), 8.0);
  runOfEight(&z, &u, 1935);
  runOfEight(&z, &u, 1935);
  runOfEight(&z, &u, 1935);
  EXPECT_DOUBLE_EQ(z.lead(), 8.0);
  runOfEight(&z, &u, 1935);
  EXPECT_DOUBLE_EQ(z.lead(), 0.0);
}

TEST(CoastPolicy, NoCoastUpdatesNeverCoasts) {
  CoastPolicy p(0.0);
  EXPECT_DOUBLE_EQ(p.lead(), 0.0);
  EXPECT_EQ(p.step(1, 0, 100, false, false), Step::kNothing);
  EXPECT_EQ(p.step(1, 0, 100, false, true), Step::kResort);
  EXPECT_EQ(p.step(100000, 0, 100, false, true), Step::kResort);
  EXPECT_DOUBLE_EQ(p.lead(), 0.0);
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
