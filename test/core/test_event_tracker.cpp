// Event tracking: BEGIN / ONGOING / END per pair, earliest first, records recycled.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>
#include <vector>
#include <map>
#include <random>
#include <set>

#include "random.hpp"
#include "workspace_proximity/event_tracker.hpp"

namespace wp = workspace_proximity;

namespace {
wp::PairEvent prediction(int a, int b, double ttc) {
  wp::PairEvent e;
  e.body_a = wp::BodyHandle{a, 0};
  e.body_b = wp::BodyHandle{b, 0};
  e.time_to_contact = ttc;
  e.time_to_separation = ttc + 1.0;
  return e;
}
std::uint64_t key(int a, int b) { return (static_cast<std::uint64_t>(a) << 32) | b; }
}  // namespace

TEST(EventTracker, BeginOngoingEndOnce) {
  wp::EventTracker tracker(8);
  tracker.beginCycle();
  tracker.report(key(1, 2), prediction(1, 2, 0.5));
  tracker.endCycle();
  ASSERT_EQ(tracker.events().size(), 1u);
  EXPECT_EQ(tracker.events()[0].state, wp::ContactState::kBegin);

  tracker.beginCycle();
  tracker.report(key(1, 2), prediction(1, 2, 0.4));
  tracker.endCycle();
  ASSERT_EQ(tracker.events().size(), 1u);
  EXPECT_EQ(tracker.events()[0].state, wp::ContactState::kOngoing);
  EXPECT_DOUBLE_EQ(tracker.events()[0].time_to_contact, 0.4);

  tracker.beginCycle();
  tracker.endCycle();
  ASSERT_EQ(tracker.events().size(), 1u);
  const wp::PairEvent& end = tracker.events()[0];
  EXPECT_EQ(end.state, wp::ContactState::kEnd);
  EXPECT_TRUE(std::isinf(end.time_to_contact));
  EXPECT_EQ(end.body_a.index, 1);
  EXPECT_EQ(tracker.activeCount(), 0);

  tracker.beginCycle();
  tracker.endCycle();
  EXPECT_TRUE(tracker.events().empty());  // END is sent once

  tracker.beginCycle();
  tracker.report(key(1, 2), prediction(1, 2, 0.3));
  tracker.endCycle();
  EXPECT_EQ(tracker.events()[0].state, wp::ContactState::kBegin);  // a new contact begins
}

TEST(EventTracker, PairNumberLastsFromBeginToEndAndIsReusedOnlyAfterIt) {
  wp::EventTracker tracker(8);
  auto number = [&](int a, int b) {
    for (const auto& e : tracker.events()) {
      if (e.body_a.index == a && e.body_b.index == b) return e.pair;
    }
    return -2;
  };
  tracker.beginCycle();
  tracker.report(key(1, 2), prediction(1, 2, 0.5));
  tracker.report(key(3, 4), prediction(3, 4, 0.6));
  tracker.endCycle();
  const std::int32_t p12 = number(1, 2), p34 = number(3, 4);
  EXPECT_GE(p12, 0);
  EXPECT_GE(p34, 0);
  EXPECT_NE(p12, p34);
  for (int cycle = 0; cycle < 3; ++cycle) {  // ONGOING keeps the number
    tracker.beginCycle();
    tracker.report(key(3, 4), prediction(3, 4, 0.6));
    tracker.report(key(1, 2), prediction(1, 2, 0.5));
    tracker.endCycle();
    EXPECT_EQ(number(1, 2), p12);
    EXPECT_EQ(number(3, 4), p34);
  }
  // (1, 2) ends while (5, 6) begins: the new pair cannot take the number yet.
  tracker.beginCycle();
  tracker.report(key(3, 4), prediction(3, 4, 0.6));
  tracker.report(key(5, 6), prediction(5, 6, 0.7));
  tracker.endCycle();
  ASSERT_EQ(tracker.events().size(), 3u);
  EXPECT_EQ(tracker.events().back().state, wp::ContactState::kEnd);
  EXPECT_EQ(number(1, 2), p12);  // END carries the pair's number
  EXPECT_NE(number(5, 6), p12);
  EXPECT_NE(number(5, 6), p34);
  // After the END the number is free again (the pool hands out the record freed last first).
  tracker.beginCycle();
  tracker.report(key(3, 4), prediction(3, 4, 0.6));
  tracker.report(key(5, 6), prediction(5, 6, 0.7));
  tracker.report(key(7, 8), prediction(7, 8, 0.8));
  tracker.endCycle();
  EXPECT_EQ(number(7, 8), p12);
  EXPECT_LT(number(7, 8), tracker.poolCapacity());
}

TEST(EventTracker, EventsAreSortedEarliestFirstWithEndsLast) {
  wp::EventTracker tracker(4);
  tracker.beginCycle();
  tracker.report(key(0, 9), prediction(0, 9, 1.0));
  tracker.endCycle();
  tracker.beginCycle();
  const double times[] = {1.5, 0.0, 0.7, 0.2, 1.9, 0.2};
  for (int i = 0; i < 6; ++i) tracker.report(key(i + 1, 100), prediction(i + 1, 100, times[i]));
  tracker.endCycle();
  const auto& events = tracker.events();
  ASSERT_EQ(events.size(), 7u);
  for (std::size_t i = 1; i < events.size(); ++i) {
    EXPECT_LE(events[i - 1].time_to_contact, events[i].time_to_contact);
  }
  EXPECT_EQ(events.back().state, wp::ContactState::kEnd);
}

// A model-based check: random pairs come and go over many cycles; the events must match
// a std::map model, and the pool must stop growing once it has seen the peak. Reports carry
// hints of every kind (none, the pair's record last time, which may since have gone to
// another pair, random and out-of-range numbers): a hint never changes an event.
TEST(EventTracker, MatchesModelAndRecyclesRecords) {
  wp::EventTracker tracker(16);
  wp_test::Rng rng(7);
  std::map<std::uint64_t, int> model_active;  // key -> cycles active
  std::map<std::uint64_t, std::int32_t> model_number;  // live key -> its pair number
  std::map<std::uint64_t, std::int32_t> last_record;   // key -> report's return, never erased
  int reused_numbers = 0;
  std::set<std::int32_t> ever_numbered;
  int capacity_after_warmup = -1;
  for (int cycle = 0; cycle < 4000; ++cycle) {
    std::map<std::uint64_t, double> reported;
    const int n = static_cast<int>(rng() % 60);
    for (int i = 0; i < n; ++i) {
      const int a = static_cast<int>(rng() % 20), b = 20 + static_cast<int>(rng() % 20);
      reported[key(a, b)] = (rng() % 1000) / 1000.0;
    }
    tracker.beginCycle();
    for (const auto& kv : reported) {
      std::int32_t hint = -1;
      switch (rng() % 4) {
        case 1: {  // its record last time, also long after its END (then another pair's)
          const auto it = last_record.find(kv.first);
          if (it != last_record.end()) hint = it->second;
          break;
        }
        case 2: hint = static_cast<std::int32_t>(rng() % (tracker.poolCapacity() + 10)) - 5; break;
        case 3: hint = tracker.poolCapacity() + static_cast<std::int32_t>(rng() % 100); break;
        default: break;
      }
      last_record[kv.first] =
          tracker.report(kv.first, prediction(static_cast<int>(kv.first >> 32),
                                              static_cast<int>(kv.first & 0xffffffff), kv.second),
                         hint);
    }
    tracker.endCycle();

    std::map<std::uint64_t, wp::ContactState> expected;
    for (const auto& kv : reported) {
      expected[kv.first] =
          model_active.count(kv.first) ? wp::ContactState::kOngoing : wp::ContactState::kBegin;
    }
    for (const auto& kv : model_active) {
      if (!reported.count(kv.first)) expected[kv.first] = wp::ContactState::kEnd;
    }
    std::map<std::uint64_t, wp::ContactState> got;
    std::set<std::int32_t> numbers;  // pair numbers of this cycle's events
    for (const auto& e : tracker.events()) {
      const std::uint64_t k = key(e.body_a.index, e.body_b.index);
      ASSERT_EQ(got.count(k), 0u) << "duplicate event";
      got[k] = e.state;
      // Pair numbers: small, one per live pair, kept from BEGIN through END.
      ASSERT_GE(e.pair, 0);
      ASSERT_LT(e.pair, tracker.poolCapacity());
      ASSERT_TRUE(numbers.insert(e.pair).second) << "two pairs share number " << e.pair;
      if (e.state == wp::ContactState::kBegin) {
        ASSERT_EQ(model_number.count(k), 0u);
      } else {
        ASSERT_EQ(e.pair, model_number.at(k)) << "pair number changed, cycle " << cycle;
      }
      if (e.state != wp::ContactState::kEnd) {
        ASSERT_EQ(last_record.at(k), e.pair);  // report returned the pair's record
      }
      model_number[k] = e.pair;
      if (e.state == wp::ContactState::kEnd) model_number.erase(k);
    }
    ASSERT_EQ(got, expected) << "cycle " << cycle;
    for (const auto& kv : model_number) {  // numbers of live pairs are not given to others
      for (const auto& other : model_number) {
        if (other.first != kv.first) {
          ASSERT_NE(other.second, kv.second);
        }
      }
    }
    model_active.clear();
    for (const auto& kv : reported) model_active[kv.first] = 1;
    ASSERT_EQ(tracker.activeCount(), static_cast<int>(model_active.size()));

    for (const auto& e : tracker.events()) {
      if (e.state == wp::ContactState::kBegin) reused_numbers += !ever_numbered.insert(e.pair).second;
    }

    if (cycle == 1000) capacity_after_warmup = tracker.poolCapacity();
  }
  EXPECT_EQ(tracker.poolCapacity(), capacity_after_warmup);
  EXPECT_GT(reused_numbers, 1000);  // numbers of ended pairs do get reused
}

TEST(EventTracker, ClearForgetsWithoutEnds) {
  wp::EventTracker tracker;
  tracker.beginCycle();
  tracker.report(key(1, 2), prediction(1, 2, 0.1));
  tracker.endCycle();
  tracker.clear();
  tracker.beginCycle();
  tracker.endCycle();
  EXPECT_TRUE(tracker.events().empty());
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}

// An END repeats its pair's last reported event (bodies, distance, points, normal, closing
// speed, pair number) with the END state, time to contact +infinity and separation 0, also
// when other pairs came and went in between.
TEST(EventTracker, EndCarriesThePairsLastEvent) {
  wp::EventTracker tracker(4);
  auto detailed = [](int a, int b, double ttc, double x) {
    wp::PairEvent e = prediction(a, b, ttc);
    e.distance = x;
    e.point_a = Eigen::Vector3d(x, 1, 2);
    e.point_b = Eigen::Vector3d(x, 3, 4);
    e.normal = Eigen::Vector3d(0, 1, 0);
    e.closing_speed = 2 * x;
    return e;
  };
  for (int cycle = 0; cycle < 3; ++cycle) {
    tracker.beginCycle();
    tracker.report(key(1, 2), detailed(1, 2, 0.5 - 0.1 * cycle, 0.25 * cycle));
    tracker.report(key(3, 4 + cycle), detailed(3, 4 + cycle, 0.1, 9.0));  // a new pair each cycle
    tracker.endCycle();
  }
  const std::int32_t number = tracker.events()[1].pair;  // (1, 2) at 0.3 s, after (3, 6) at 0.1 s
  ASSERT_EQ(tracker.events()[1].body_a.index, 1);
  tracker.beginCycle();
  tracker.endCycle();
  ASSERT_EQ(tracker.events().size(), 2u);
  const wp::PairEvent* end = nullptr;
  for (const auto& e : tracker.events()) {
    if (e.body_a.index == 1) end = &e;
  }
  ASSERT_NE(end, nullptr);
  EXPECT_EQ(end->state, wp::ContactState::kEnd);
  EXPECT_EQ(end->pair, number);
  EXPECT_EQ(end->body_b.index, 2);
  EXPECT_TRUE(std::isinf(end->time_to_contact));
  EXPECT_EQ(end->time_to_separation, 0.0);
  EXPECT_EQ(end->distance, 0.5);
  EXPECT_EQ(end->point_a, Eigen::Vector3d(0.5, 1, 2));
  EXPECT_EQ(end->point_b, Eigen::Vector3d(0.5, 3, 4));
  EXPECT_EQ(end->normal, Eigen::Vector3d(0, 1, 0));
  EXPECT_EQ(end->closing_speed, 1.0);
}

// The order comes from the last cycle's order (its sorted part kept, the keys out of place
// sorted and merged back in): whatever the cycle, it must be exactly the order a full sort of
// (time, bodies) gives. Cycles alternate between coherent ones (every time shrinks by the
// cycle and a little noise, pairs come and go, ties at 0) and shuffled ones (fresh random
// times: most keys out of place); clear() now and then forgets every place.
TEST(EventTracker, OrderEqualsAFullSortInCoherentAndShuffledCycles) {
  wp::EventTracker tracker(16);
  wp_test::Rng rng(11);
  std::map<std::uint64_t, double> live;  // key -> time to contact
  int coherent_cycles = 0, shuffled_cycles = 0;
  for (int cycle = 0; cycle < 3000; ++cycle) {
    const bool shuffled = cycle % 17 == 5;
    std::map<std::uint64_t, double> reported;
    for (const auto& kv : live) {
      if (rng() % 20 == 0) continue;  // this pair ends
      double t = shuffled ? rng.uniform(0.0, 2.0) : kv.second - 1.0 / 30.0 + rng.uniform(-0.02, 0.02);
      if (t < 0.0 || rng() % 40 == 0) t = 0.0;  // touching now: ties at 0
      reported[kv.first] = t;
    }
    const int fresh = static_cast<int>(rng() % 12);
    for (int i = 0; i < fresh; ++i) {
      const int a = static_cast<int>(rng() % 60), b = 60 + static_cast<int>(rng() % 60);
      reported[key(a, b)] = rng.uniform(0.0, 2.0);
    }
    std::map<std::uint64_t, bool> ended;
    for (const auto& kv : live) {
      if (!reported.count(kv.first)) ended[kv.first] = true;
    }
    tracker.beginCycle();
    for (const auto& kv : reported) {
      tracker.report(kv.first, prediction(static_cast<int>(kv.first >> 32),
                                          static_cast<int>(kv.first & 0xffffffff), kv.second));
    }
    tracker.endCycle();
    shuffled ? ++shuffled_cycles : ++coherent_cycles;

    // The oracle: every expected event's (time, a, b), fully sorted.
    std::vector<std::tuple<double, int, int>> expected, got;
    for (const auto& kv : reported) {
      expected.emplace_back(kv.second, static_cast<int>(kv.first >> 32),
                            static_cast<int>(kv.first & 0xffffffff));
    }
    for (const auto& kv : ended) {
      expected.emplace_back(std::numeric_limits<double>::infinity(),
                            static_cast<int>(kv.first >> 32), static_cast<int>(kv.first & 0xffffffff));
    }
    std::sort(expected.begin(), expected.end());
    for (const auto& e : tracker.events()) {
      got.emplace_back(e.time_to_contact, e.body_a.index, e.body_b.index);
    }
    ASSERT_EQ(got, expected) << "cycle " << cycle << (shuffled ? " (shuffled)" : " (coherent)");

    live = reported;
    if (cycle % 500 == 499) {
      tracker.clear();
      live.clear();
    }
  }
  EXPECT_GT(shuffled_cycles, 100);
  EXPECT_GT(coherent_cycles, 2000);
}

// A crowd whose tracks' ages differ from cycle to cycle: every time to contact shifts by up to
// a tenth of a second each cycle, so most keys move hundreds of places and the tracker sorts
// by radix. Its order must still be a full sort's, with ties at zero (and negative zero, and
// a few negative times) broken by the bodies, ENDs last.
TEST(EventTracker, RadixOrderEqualsAFullSortWhenTimesJitter) {
  wp::EventTracker tracker(64);
  wp_test::Rng rng(23);
  std::map<std::uint64_t, double> live;
  int radix_cycles = 0, coherent_cycles = 0;
  for (int cycle = 0; cycle < 400; ++cycle) {
    // Jitter in some stretches only, so that the tracker goes from one way to the other.
    const bool jitter = (cycle / 25) % 2 == 0;
    std::map<std::uint64_t, double> reported;
    for (const auto& kv : live) {
      if (rng() % 50 == 0) continue;  // this pair ends
      double t = kv.second - 1.0 / 30.0 + (jitter ? rng.uniform(-0.1, 0.1) : 0.0);
      if (t < 0.0 || rng() % 30 == 0) t = rng() % 2 == 0 ? 0.0 : -0.0;  // touching now: ties
      if (rng() % 200 == 0) t = -rng.uniform(0.0, 1e-3);  // (times are not checked here)
      if (t == 0.0 && rng() % 10 == 0) t = rng.uniform(0.5, 2.0);  // apart again
      reported[kv.first] = t;
    }
    const int fresh = static_cast<int>(rng() % 60);
    for (int i = 0; i < fresh; ++i) {
      const int a = static_cast<int>(rng() % 400), b = 400 + static_cast<int>(rng() % 400);
      if (!live.count(key(a, b))) reported[key(a, b)] = rng.uniform(0.0, 2.0);
    }
    std::vector<std::tuple<double, int, int>> expected, got;
    for (const auto& kv : reported) {
      // Negative zero sorts as zero, by the bodies.
      expected.emplace_back(kv.second + 0.0, static_cast<int>(kv.first >> 32),
                            static_cast<int>(kv.first & 0xffffffff));
    }
    for (const auto& kv : live) {
      if (!reported.count(kv.first)) {
        expected.emplace_back(std::numeric_limits<double>::infinity(),
                              static_cast<int>(kv.first >> 32), static_cast<int>(kv.first & 0xffffffff));
      }
    }
    std::sort(expected.begin(), expected.end());
    tracker.beginCycle();
    for (const auto& kv : reported) {
      tracker.report(kv.first, prediction(static_cast<int>(kv.first >> 32),
                                          static_cast<int>(kv.first & 0xffffffff), kv.second));
    }
    tracker.endCycle();
    tracker.radixSorted() ? ++radix_cycles : ++coherent_cycles;
    for (const auto& e : tracker.events()) {
      got.emplace_back(e.time_to_contact + 0.0, e.body_a.index, e.body_b.index);
    }
    ASSERT_EQ(got, expected) << "cycle " << cycle << (tracker.radixSorted() ? " (radix)" : "");
    live = reported;
  }
  // Both ways were taken, many times each.
  EXPECT_GT(radix_cycles, 100);
  EXPECT_GT(coherent_cycles, 40);
}
