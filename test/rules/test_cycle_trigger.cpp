// ~cycle_trigger: input without ROS (CycleTrigger): the token bucket and the floor against
// sequences worked out by hand. Rate 10 Hz: a token every 0.1 s, at most kBurst = 2 saved up.
// Array intervals of 25 ms add exactly 0.25 tokens (binary fractions), so the hand-computed
// token counts are exact.

#include <gtest/gtest.h>

#include <vector>

#include "workspace_proximity/rules/cycle_trigger.hpp"

namespace wp = workspace_proximity;

namespace {

constexpr wp::Stamp kMs = 1000000;
constexpr wp::Stamp kT0 = 1000000 * kMs;  // an arbitrary clock reading

// Drives the trigger as the node and the replay do: arrays at the given instants, the floor
// whenever it falls due before the next array (an array at the floor's instant comes first).
// Returns the instants of the cycles.
std::vector<wp::Stamp> drive(wp::CycleTrigger* trigger, const std::vector<wp::Stamp>& arrays,
                             wp::Stamp until) {
  std::vector<wp::Stamp> cycles;
  wp::Stamp floor = kT0 + trigger->floorAfter(0);  // the first floor a period after the start
  for (wp::Stamp t : arrays) {
    while (floor < t) {
      trigger->onFloor(floor);
      cycles.push_back(floor);
      floor = trigger->floorAfter(floor);
    }
    if (trigger->onArray(t)) {
      cycles.push_back(t);
      floor = trigger->floorAfter(t);
    }
  }
  while (floor <= until) {
    trigger->onFloor(floor);
    cycles.push_back(floor);
    floor = trigger->floorAfter(floor);
  }
  return cycles;
}

}  // namespace

TEST(CycleTrigger, AFloodRunsTheBurstThenOneCycleAPeriod) {
  // Arrays at 40 Hz: 0 (2 tokens -> 1), 25 ms (1.25 -> 0.25), 50 (0.5, refused), 75 (0.75,
  // refused), 100 (1.0 -> 0), 125, 150, 175 refused, 200 (1.0, before the floor at 200) ...
  wp::CycleTrigger trigger(10.0);
  std::vector<wp::Stamp> arrays;
  for (int k = 0; k <= 40; ++k) arrays.push_back(kT0 + 25 * kMs * k);
  const std::vector<wp::Stamp> cycles = drive(&trigger, arrays, kT0 + 1000 * kMs);
  std::vector<wp::Stamp> expected = {kT0, kT0 + 25 * kMs};
  for (int k = 1; k <= 10; ++k) expected.push_back(kT0 + 100 * kMs * k);
  EXPECT_EQ(cycles, expected);
  // 12 cycles in the first second: ~rate plus the burst, floor cycles included (none here).
  EXPECT_EQ(cycles.size(), 12u);
}

TEST(CycleTrigger, AnArrayRefusedByTheBucketIsTakenByTheFloorWhichSpendsItsToken) {
  wp::CycleTrigger trigger(10.0);
  EXPECT_TRUE(trigger.onArray(kT0));                // 2 -> 1
  EXPECT_TRUE(trigger.onArray(kT0 + 25 * kMs));     // 1.25 -> 0.25
  EXPECT_FALSE(trigger.onArray(kT0 + 50 * kMs));    // 0.5: refused, waits for the floor
  EXPECT_DOUBLE_EQ(trigger.tokens(), 0.5);
  // The floor a period after the last cycle (125 ms): 0.5 + 0.75 = 1.25, less the refused
  // array's token: 0.25.
  EXPECT_EQ(trigger.floorAfter(kT0 + 25 * kMs), kT0 + 125 * kMs);
  trigger.onFloor(kT0 + 125 * kMs);
  EXPECT_NEAR(trigger.tokens(), 0.25, 1e-12);
  // So the flood's next array does not run a second cycle right after the floor's.
  EXPECT_FALSE(trigger.onArray(kT0 + 150 * kMs));  // 0.5
}

TEST(CycleTrigger, TheFloorCostsNothingInSilenceAndTheNextArrayRunsAtOnce) {
  wp::CycleTrigger trigger(10.0);
  EXPECT_TRUE(trigger.onArray(kT0));  // 1 left
  trigger.onFloor(kT0 + 100 * kMs);   // 2 (full), nothing spent
  EXPECT_DOUBLE_EQ(trigger.tokens(), 2.0);
  trigger.onFloor(kT0 + 200 * kMs);
  trigger.onFloor(kT0 + 300 * kMs);
  EXPECT_DOUBLE_EQ(trigger.tokens(), 2.0);  // never more than the burst
  EXPECT_TRUE(trigger.onArray(kT0 + 350 * kMs));   // 2 -> 1
  EXPECT_TRUE(trigger.onArray(kT0 + 375 * kMs));   // 1.25 -> 0.25: the burst
  EXPECT_FALSE(trigger.onArray(kT0 + 400 * kMs));  // 0.5
}

TEST(CycleTrigger, ASlowTrackerRunsACycleOnEveryArrayWithFloorsBetween) {
  // Arrays at 4 Hz (every 250 ms) at a 10 Hz rate: each array runs at once; the floor runs
  // 100 and 200 ms after each.
  wp::CycleTrigger trigger(10.0);
  const std::vector<wp::Stamp> arrays = {kT0, kT0 + 250 * kMs, kT0 + 500 * kMs};
  const std::vector<wp::Stamp> cycles = drive(&trigger, arrays, kT0 + 500 * kMs);
  const std::vector<wp::Stamp> expected = {kT0,             kT0 + 100 * kMs, kT0 + 200 * kMs,
                                           kT0 + 250 * kMs, kT0 + 350 * kMs, kT0 + 450 * kMs,
                                           kT0 + 500 * kMs};
  EXPECT_EQ(cycles, expected);
}

TEST(CycleTrigger, TheClockGoingBackRefillsTheBucket) {
  wp::CycleTrigger trigger(10.0);
  EXPECT_TRUE(trigger.onArray(kT0));
  EXPECT_TRUE(trigger.onArray(kT0 + 25 * kMs));
  EXPECT_FALSE(trigger.onArray(kT0 + 50 * kMs));
  // A bag loop: 53 s earlier, the bucket is full again (the first array finds two tokens).
  EXPECT_TRUE(trigger.onArray(kT0 - 53000 * kMs));
  EXPECT_DOUBLE_EQ(trigger.tokens(), 1.0);
}

TEST(CycleTrigger, TheRateSetsTheRefillAndTheFloorsPeriod) {
  wp::CycleTrigger trigger(10.0);
  EXPECT_DOUBLE_EQ(trigger.period(), 0.1);
  trigger.setRate(20.0);
  EXPECT_DOUBLE_EQ(trigger.period(), 0.05);
  EXPECT_EQ(trigger.floorAfter(kT0), kT0 + 50 * kMs);
  EXPECT_TRUE(trigger.onArray(kT0));             // 1
  EXPECT_TRUE(trigger.onArray(kT0 + 25 * kMs));  // 1 + 0.5 -> 0.5
  EXPECT_DOUBLE_EQ(trigger.tokens(), 0.5);
  EXPECT_TRUE(trigger.onArray(kT0 + 50 * kMs));  // 1.0 -> 0 (20 Hz: a token per 50 ms)
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
