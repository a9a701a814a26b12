// When markers are published (MarkerSchedule): at most ~marker_rate, less half a cycle so that
// a marker period of a whole number of cycles does not slip with jitter. Worked out by hand.

#include <gtest/gtest.h>

#include <vector>

#include "workspace_proximity/rules/marker_schedule.hpp"

namespace wp = workspace_proximity;

namespace {

constexpr wp::Stamp kMs = 1000000;
constexpr wp::Stamp kT0 = 1000000 * kMs;

// Indices of the cycles (at the given instants) that publish markers.
std::vector<int> dueCycles(const std::vector<wp::Stamp>& cycles, double marker_rate, double rate) {
  wp::MarkerSchedule schedule;
  std::vector<int> out;
  for (std::size_t k = 0; k < cycles.size(); ++k) {
    if (schedule.due(cycles[k], marker_rate, rate)) out.push_back(static_cast<int>(k));
  }
  return out;
}

}  // namespace

TEST(MarkerSchedule, TenHertzOnThirtyHertzCyclesIsEveryThirdCycleEvenWithJitter) {
  // Due when 1/10 - 0.5/30 = 83.3 ms have passed. Cycles 5 ms late and early in turn:
  // 0, 38.3, 61.7, 105 (105 since 0: due), 128.3, 171.7, 195 (90 since 105: due), ...
  // With the full 100 ms, cycle 6 (90 ms after cycle 3) would slip to cycle 7.
  std::vector<wp::Stamp> jittered, exact;
  for (int k = 0; k <= 12; ++k) {
    const wp::Stamp t = kT0 + (1000 * kMs) * k / 30;
    exact.push_back(t);
    jittered.push_back(t + (k == 0 ? 0 : (k % 2 == 1 ? 5 * kMs : -5 * kMs)));
  }
  const std::vector<int> every_third = {0, 3, 6, 9, 12};
  EXPECT_EQ(dueCycles(exact, 10.0, 30.0), every_third);
  EXPECT_EQ(dueCycles(jittered, 10.0, 30.0), every_third);
}

TEST(MarkerSchedule, AMarkerRateAtOrAboveTheCycleRateIsEveryCycle) {
  std::vector<wp::Stamp> cycles;
  for (int k = 0; k < 6; ++k) cycles.push_back(kT0 + (1000 * kMs) * k / 30);
  EXPECT_EQ(dueCycles(cycles, 30.0, 30.0), (std::vector<int>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(dueCycles(cycles, 100.0, 30.0), (std::vector<int>{0, 1, 2, 3, 4, 5}));
}

TEST(MarkerSchedule, TheFirstCycleAndACycleAfterTheClockWentBackPublish) {
  wp::MarkerSchedule schedule;
  EXPECT_TRUE(schedule.due(kT0, 1.0, 10.0));
  EXPECT_FALSE(schedule.due(kT0 + 500 * kMs, 1.0, 10.0));  // 0.5 s < 1 - 0.05 s
  EXPECT_TRUE(schedule.due(kT0 + 950 * kMs, 1.0, 10.0));   // 0.95 s: due
  EXPECT_TRUE(schedule.due(kT0 - 53000 * kMs, 1.0, 10.0)); // the clock went back
  EXPECT_FALSE(schedule.due(kT0 - 52900 * kMs, 1.0, 10.0));
}

TEST(MarkerSchedule, MarkersAreBuiltHalfACycleLater) {
  EXPECT_DOUBLE_EQ(wp::MarkerSchedule::delay(10.0), 0.05);
  EXPECT_DOUBLE_EQ(wp::MarkerSchedule::delay(30.0), 1.0 / 60.0);
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
