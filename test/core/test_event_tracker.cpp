// Event tracking: BEGIN / ONGOING / END per pair, earliest first, records recycled.

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>

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
// a std::map model, and the pool must stop growing once it has seen the peak.
TEST(EventTracker, MatchesModelAndRecyclesRecords) {
  wp::EventTracker tracker(16);
  std::mt19937 rng(7);
  std::map<std::uint64_t, int> model_active;  // key -> cycles active
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
      tracker.report(kv.first, prediction(static_cast<int>(kv.first >> 32),
                                          static_cast<int>(kv.first & 0xffffffff), kv.second));
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
    for (const auto& e : tracker.events()) {
      const std::uint64_t k = key(e.body_a.index, e.body_b.index);
      ASSERT_EQ(got.count(k), 0u) << "duplicate event";
      got[k] = e.state;
    }
    ASSERT_EQ(got, expected) << "cycle " << cycle;
    model_active.clear();
    for (const auto& kv : reported) model_active[kv.first] = 1;
    ASSERT_EQ(tracker.activeCount(), static_cast<int>(model_active.size()));

    if (cycle == 1000) capacity_after_warmup = tracker.poolCapacity();
  }
  EXPECT_EQ(tracker.poolCapacity(), capacity_after_warmup);
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
