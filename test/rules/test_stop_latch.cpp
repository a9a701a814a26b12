// The stop latch (restart interlock, minimum stop time, stop category 1, muting) driven as
// SsmCycle drives it: begin() -> SpeedScaleFilter -> end(), every 0.1 s. Every expected scale
// is worked out by hand from the filter's rule (drops at once; rises only after the raw scale
// stayed above it for hold_time, then at most max_increase_rate per s) and the latch's rules.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "allocation_counter.hpp"  // test/shared
#include "workspace_proximity/rules/ssm_rule.hpp"
#include "workspace_proximity/rules/stop_latch.hpp"

namespace wp = workspace_proximity;

namespace {

// Hold 0.2 s, then 5 per s: from 0 the scale takes 0.2 s of rising to reach 1.
wp::SsmParams filterParams() {
  wp::SsmParams p;
  p.hold_time = 0.2;
  p.max_increase_rate = 5.0;
  return p;
}

struct Drive {
  explicit Drive(const wp::LatchParams& lp) : latch(lp), filter(filterParams()) {}
  // One cycle at t seconds; returns the scale.
  double step(double t, double raw, bool degraded = false, int within = 0) {
    const wp::Stamp now = wp::nanoseconds(t);
    double target = raw;
    if (latch.begin(now)) target = 0.0;
    const double out = filter.update(now, target);
    latch.end(now, out, degraded, within, reason);
    return out;
  }
  // Cycles every 0.1 s from t0 up to (not including) t1 at `raw`; returns the last scale.
  double run(double t0, double t1, double raw, bool degraded = false, int within = 0) {
    double out = -1.0;
    for (int i = 0; t0 + 0.1 * i < t1 - 1e-9; ++i) out = step(t0 + 0.1 * i, raw, degraded, within);
    return out;
  }
  int count(wp::LatchEventKind kind) const {
    int n = 0;
    for (int i = 0; i < latch.events().size(); ++i) n += latch.events()[i].kind == kind;
    return n;
  }
  wp::StopLatch latch;
  wp::SpeedScaleFilter filter;
  const std::string reason = "person_1 too near";
};

wp::LatchParams manual() {
  wp::LatchParams p;
  p.manual = true;
  return p;
}

// Brings the scale to 1 (t 0 .. 1 s), then stops it at t = 1.0.
void runThenStop(Drive* d) {
  // Raw 1 from t = 0: above 0 since 0, the hold ends at 0.2, then 5/s: 0.5 at 0.3, 1 at 0.4.
  EXPECT_DOUBLE_EQ(d->step(0.0, 1.0), 0.0);
  EXPECT_DOUBLE_EQ(d->step(0.1, 1.0), 0.0);
  EXPECT_DOUBLE_EQ(d->step(0.2, 1.0), 0.0);
  EXPECT_NEAR(d->step(0.3, 1.0), 0.5, 1e-9);
  EXPECT_NEAR(d->step(0.4, 1.0), 1.0, 1e-9);
  EXPECT_NEAR(d->run(0.5, 1.0, 1.0), 1.0, 1e-9);
  EXPECT_DOUBLE_EQ(d->step(1.0, 0.0, false, 1), 0.0);
}

}  // namespace

TEST(StopLatch, AutomaticWithoutMinimumTimeIsTodaysFilter) {
  Drive d{wp::LatchParams()};
  wp::SpeedScaleFilter bare(filterParams());
  // Any raw sequence: the scale is the bare filter's, step by step.
  const double raws[] = {1, 1, 0.3, 0, 0, 1, 1, 1, 1, 0.5, 0, 1, 1, 1, 1, 1, 1};
  for (int i = 0; i < static_cast<int>(sizeof raws / sizeof raws[0]); ++i) {
    const double t = 0.1 * i;
    EXPECT_DOUBLE_EQ(d.step(t, raws[i]), bare.update(wp::nanoseconds(t), raws[i])) << "t = " << t;
    EXPECT_FALSE(d.latch.state().held);
    EXPECT_FALSE(d.latch.state().reset_required);
  }
}

TEST(StopLatch, ManualHoldsUntilAnAcceptedResetThenRisesByHoldAndRate) {
  Drive d(manual());
  runThenStop(&d);
  EXPECT_EQ(d.count(wp::LatchEventKind::kStop), 1);
  EXPECT_NE(d.latch.events()[0].reason.find("person_1 too near"), std::string::npos);
  EXPECT_TRUE(d.latch.state().stopped);
  EXPECT_TRUE(d.latch.state().reset_required);
  EXPECT_EQ(d.latch.state().hold, "reset");
  // The person left at 1.1: raw 1 for 9 s, the scale never rises without a reset.
  for (int i = 0; i < 90; ++i) EXPECT_EQ(d.step(1.1 + 0.1 * i, 1.0), 0.0) << i;
  std::string why;
  EXPECT_TRUE(d.latch.requestReset(wp::nanoseconds(10.05), &why)) << why;
  EXPECT_NE(why.find("accepted"), std::string::npos);
  // Released at 10.1: the raw scale is above from 10.1, held 0.2 s, then 5/s.
  EXPECT_DOUBLE_EQ(d.step(10.1, 1.0), 0.0);
  EXPECT_EQ(d.count(wp::LatchEventKind::kResetAccepted), 1);
  EXPECT_EQ(d.count(wp::LatchEventKind::kReleased), 1);
  EXPECT_DOUBLE_EQ(d.step(10.2, 1.0), 0.0);
  EXPECT_DOUBLE_EQ(d.step(10.3, 1.0), 0.0);
  EXPECT_NEAR(d.step(10.4, 1.0), 0.5, 1e-9);
  EXPECT_NEAR(d.step(10.5, 1.0), 1.0, 1e-9);
  EXPECT_FALSE(d.latch.state().stopped);
  // A second stop needs a second reset.
  EXPECT_DOUBLE_EQ(d.step(10.6, 0.0, false, 1), 0.0);
  EXPECT_EQ(d.run(10.7, 12.0, 1.0), 0.0);
  EXPECT_TRUE(d.latch.state().reset_required);
}

TEST(StopLatch, ResetRefusedWhilePersonWithinReachOrDegradedAcceptedOnceClear) {
  Drive d(manual());
  runThenStop(&d);
  std::string why;
  // Still within S_p(v_max) at the last cycle.
  d.step(1.1, 0.4, false, 1);
  EXPECT_FALSE(d.latch.requestReset(wp::nanoseconds(1.15), &why));
  EXPECT_NE(why.find("within"), std::string::npos) << why;
  // Out of reach but DEGRADED: unknown is never clear.
  d.step(1.2, 1.0, true, 0);
  EXPECT_EQ(d.count(wp::LatchEventKind::kResetRefused), 1);  // the one at 1.15, in 1.2's list
  EXPECT_FALSE(d.latch.requestReset(wp::nanoseconds(1.25), &why));
  EXPECT_NE(why.find("DEGRADED"), std::string::npos) << why;
  d.step(1.3, 1.0);
  EXPECT_EQ(d.count(wp::LatchEventKind::kResetRefused), 1);  // the one at 1.25
  EXPECT_TRUE(d.latch.state().reset_required);
  // Clear and OK: accepted.
  EXPECT_TRUE(d.latch.requestReset(wp::nanoseconds(1.35), &why)) << why;
  EXPECT_FALSE(d.latch.state().reset_required);
  EXPECT_DOUBLE_EQ(d.step(1.4, 1.0), 0.0);
  EXPECT_NEAR(d.run(1.5, 2.0, 1.0), 1.0, 1e-9);  // 0.5 at 1.7, 1 at 1.8
}

TEST(StopLatch, AnIntrusionAfterTheResetBeforeTheRiseArmsTheInterlockAgain) {
  Drive d(manual());
  runThenStop(&d);
  std::string why;
  d.step(1.1, 1.0);
  EXPECT_TRUE(d.latch.requestReset(wp::nanoseconds(1.15), &why)) << why;
  EXPECT_DOUBLE_EQ(d.step(1.2, 1.0), 0.0);  // released; the filter's hold runs to 1.4
  EXPECT_DOUBLE_EQ(d.step(1.3, 0.0, false, 1), 0.0);  // back within reach before the rise
  EXPECT_TRUE(d.latch.state().reset_required);
  EXPECT_EQ(d.count(wp::LatchEventKind::kStop), 1);
  EXPECT_EQ(d.run(1.4, 4.0, 1.0), 0.0);  // gone again: no rise without a second reset
  EXPECT_TRUE(d.latch.requestReset(wp::nanoseconds(4.05), &why)) << why;
  EXPECT_NEAR(d.run(4.1, 4.6, 1.0), 1.0, 1e-9);  // released at 4.1: 0.5 at 4.4, 1 at 4.5
}

TEST(StopLatch, TheStartIsNoStopAndAResetAfterAClockJumpWaitsForACycle) {
  wp::StopLatch latch(manual());
  latch.end(0, 0.0, false, 0, "first cycle");  // the filter starts at 0: no stop
  EXPECT_FALSE(latch.state().stopped);
  std::string why;
  EXPECT_TRUE(latch.requestReset(0, &why));  // nothing waits for a reset
  EXPECT_NE(why.find("nothing to reset"), std::string::npos);
  latch.end(wp::nanoseconds(0.1), 1.0, false, 0, "");
  latch.end(wp::nanoseconds(0.2), 0.0, false, 0, "stop");
  EXPECT_TRUE(latch.state().reset_required);
  latch.reset();  // the clock went back: the stop stays, the last cycle is forgotten
  EXPECT_FALSE(latch.requestReset(0, &why));
  EXPECT_NE(why.find("no cycle"), std::string::npos) << why;
  EXPECT_TRUE(latch.begin(0));  // still held
}

TEST(StopLatch, MinimumStopTimeHoldsInAutomaticMode) {
  wp::LatchParams p;
  p.min_stop_time = 1.0;
  Drive d(p);
  runThenStop(&d);  // stop at 1.0
  EXPECT_EQ(d.latch.state().hold, "min_stop_time");
  // Raw back to 1 at 1.1, but held until 2.0.
  EXPECT_EQ(d.run(1.1, 2.0, 1.0), 0.0);
  EXPECT_TRUE(d.latch.state().held);
  // 2.0: released; above from 2.0, hold to 2.2, 0.5 at 2.3, 1 at 2.4.
  EXPECT_DOUBLE_EQ(d.step(2.0, 1.0), 0.0);
  EXPECT_FALSE(d.latch.state().held);
  EXPECT_DOUBLE_EQ(d.step(2.1, 1.0), 0.0);
  EXPECT_DOUBLE_EQ(d.step(2.2, 1.0), 0.0);
  EXPECT_NEAR(d.step(2.3, 1.0), 0.5, 1e-9);
  EXPECT_NEAR(d.step(2.4, 1.0), 1.0, 1e-9);
}

TEST(StopLatch, MinimumStopTimeAlsoAfterAResetInManualMode) {
  wp::LatchParams p = manual();
  p.min_stop_time = 2.0;
  Drive d(p);
  runThenStop(&d);  // stop at 1.0, off until 3.0 at least
  std::string why;
  d.step(1.1, 1.0);
  EXPECT_TRUE(d.latch.requestReset(wp::nanoseconds(1.15), &why)) << why;
  EXPECT_EQ(d.run(1.2, 3.0, 1.0), 0.0);
  EXPECT_EQ(d.latch.state().hold, "min_stop_time");
  EXPECT_DOUBLE_EQ(d.step(3.0, 1.0), 0.0);  // released, the filter's hold starts
  EXPECT_NEAR(d.run(3.1, 3.5, 1.0), 1.0, 1e-9);
}

TEST(StopLatch, CategoryOneRequestsTheHaltOnceAfterStandstill) {
  wp::LatchParams p;
  p.stop_category = 1;
  p.standstill_speed = 0.01;
  p.standstill_time = 0.5;
  Drive d(p);
  runThenStop(&d);  // stop at 1.0; no joint speeds yet
  EXPECT_NE(d.latch.haltWait().find("unknown"), std::string::npos) << d.latch.haltWait();
  // Unknown speeds (not measured) for 2 s: never standstill.
  for (int i = 0; i < 20; ++i) {
    d.latch.noteJointSpeed(wp::nanoseconds(1.05 + 0.1 * i), 0.0, false);
    d.step(1.1 + 0.1 * i, 0.0);
    EXPECT_EQ(d.count(wp::LatchEventKind::kHaltRequested), 0);
  }
  EXPECT_NE(d.latch.haltWait().find("not measured"), std::string::npos) << d.latch.haltWait();
  // Still moving (0.05 rad/s) for 1 s.
  for (int i = 0; i < 10; ++i) {
    d.latch.noteJointSpeed(wp::nanoseconds(3.05 + 0.1 * i), 0.05, true);
    d.step(3.1 + 0.1 * i, 0.0);
    EXPECT_EQ(d.count(wp::LatchEventKind::kHaltRequested), 0);
  }
  // Below 0.01 from 4.05: standstill for 0.5 s at 4.55 -> the cycle at 4.6 requests it.
  int halts = 0;
  double at = -1.0;
  for (int i = 0; i < 30; ++i) {
    const double t = 4.1 + 0.1 * i;
    d.latch.noteJointSpeed(wp::nanoseconds(t - 0.05), 0.005, true);
    d.step(t, 0.0);
    if (d.count(wp::LatchEventKind::kHaltRequested) > 0 && at < 0) at = t;
    halts += d.count(wp::LatchEventKind::kHaltRequested);
  }
  EXPECT_EQ(halts, 1);  // once per stop
  EXPECT_NEAR(at, 4.6, 1e-9);
  EXPECT_TRUE(d.latch.state().halt_requested);
}

TEST(StopLatch, CategoryOneStaleJointSpeedsAreNoStandstill) {
  wp::LatchParams p;
  p.stop_category = 1;
  p.standstill_time = 0.2;
  Drive d(p);
  runThenStop(&d);
  d.latch.noteJointSpeed(wp::nanoseconds(1.0), 0.0, true);  // one reading, then silence
  int halts = 0;
  for (int i = 0; i < 30; ++i) {
    d.step(1.1 + 0.1 * i, 0.0);
    halts += d.count(wp::LatchEventKind::kHaltRequested);
  }
  // Stood still 0.2 s by 1.2 while the reading was fresh (0.2 s old): one halt at most then,
  // never later from the stale reading.
  EXPECT_LE(halts, 1);
  wp::StopLatch silent(p);
  silent.end(wp::nanoseconds(0.9), 1.0, false, 0, "");
  silent.end(wp::nanoseconds(1.0), 0.0, false, 0, "stop");
  silent.noteJointSpeed(wp::nanoseconds(0.1), 0.0, true);  // 0.9 s older than the stop
  silent.begin(wp::nanoseconds(2.0));
  silent.end(wp::nanoseconds(2.0), 0.0, false, 0, "stop");
  EXPECT_FALSE(silent.state().halt_requested);
  EXPECT_NE(silent.haltWait().find("no recent joint speeds"), std::string::npos);
}

TEST(StopLatch, CategoryTwoNeverRequestsAHalt) {
  Drive d{wp::LatchParams()};
  runThenStop(&d);
  for (int i = 0; i < 30; ++i) {
    d.latch.noteJointSpeed(wp::nanoseconds(1.05 + 0.1 * i), 0.0, true);
    d.step(1.1 + 0.1 * i, 0.0);
    EXPECT_EQ(d.count(wp::LatchEventKind::kHaltRequested), 0);
  }
}

TEST(StopLatch, MuteRefusedWhileStoppedWithinReachDegradedOrOff) {
  wp::LatchParams p;
  p.max_mute_time = 10.0;
  Drive d(p);
  std::string why;
  const std::vector<std::string> labels = {"forklift"};
  runThenStop(&d);
  EXPECT_FALSE(d.latch.requestMute(wp::nanoseconds(1.05), labels, {}, 5.0, &why));
  EXPECT_NE(why.find("scale is 0"), std::string::npos) << why;
  // Running, but a pair within S_p.
  d.run(1.1, 2.0, 1.0);
  d.step(2.0, 0.7, false, 1);
  EXPECT_GT(d.filter.output(), 0.0);
  EXPECT_FALSE(d.latch.requestMute(wp::nanoseconds(2.05), labels, {}, 5.0, &why));
  EXPECT_NE(why.find("within"), std::string::npos) << why;
  d.step(2.1, 1.0, true, 0);
  EXPECT_FALSE(d.latch.requestMute(wp::nanoseconds(2.15), labels, {}, 5.0, &why));
  EXPECT_NE(why.find("DEGRADED"), std::string::npos) << why;
  d.step(2.2, 1.0);
  EXPECT_FALSE(d.latch.requestMute(wp::nanoseconds(2.25), {}, {}, 5.0, &why));
  EXPECT_FALSE(d.latch.requestMute(wp::nanoseconds(2.25), labels, {}, 0.0, &why));
  EXPECT_FALSE(d.latch.state().muted);
  wp::StopLatch off{wp::LatchParams()};
  off.end(0, 1.0, false, 0, "");
  EXPECT_FALSE(off.requestMute(0, labels, {}, 1.0, &why));
  EXPECT_NE(why.find("muting is off"), std::string::npos);
}

TEST(StopLatch, MuteIsScopedCutToTheMaximumAndEndsByItself) {
  wp::LatchParams p;
  p.max_mute_time = 2.0;
  Drive d(p);
  std::string why;
  d.run(0.0, 1.0, 1.0);
  ASSERT_NEAR(d.filter.output(), 1.0, 1e-9);
  // Asks for 30 s: 2 s granted, from 1.0 to 3.0.
  EXPECT_TRUE(d.latch.requestMute(wp::nanoseconds(1.0), {"forklift"}, {"tracks/person_7"}, 30.0, &why))
      << why;
  EXPECT_NE(why.find("cut"), std::string::npos);
  EXPECT_TRUE(d.latch.muted("forklift", "tracks/a"));
  EXPECT_TRUE(d.latch.muted("person", "tracks/person_7"));
  EXPECT_FALSE(d.latch.muted("person", "tracks/person_8"));
  EXPECT_FALSE(d.latch.requestMute(wp::nanoseconds(1.0), {"person"}, {}, 1.0, &why));  // already
  d.step(1.0, 1.0);
  EXPECT_EQ(d.count(wp::LatchEventKind::kMuteStarted), 1);
  d.run(1.1, 3.0, 1.0);
  EXPECT_TRUE(d.latch.state().muted);
  EXPECT_NEAR(d.latch.state().mute_left, 0.1, 1e-6);
  d.step(3.0, 1.0);
  EXPECT_FALSE(d.latch.state().muted);
  EXPECT_EQ(d.count(wp::LatchEventKind::kMuteEnded), 1);
  EXPECT_FALSE(d.latch.muted("forklift", "tracks/a"));
}

TEST(StopLatch, AStopEndsTheMute) {
  wp::LatchParams p;
  p.max_mute_time = 20.0;
  Drive d(p);
  std::string why;
  d.run(0.0, 1.0, 1.0);
  EXPECT_TRUE(d.latch.requestMute(wp::nanoseconds(1.0), {"forklift"}, {}, 10.0, &why)) << why;
  d.step(1.0, 1.0);
  d.step(1.1, 0.0, false, 1);  // someone else came too near
  EXPECT_FALSE(d.latch.state().muted);
  EXPECT_EQ(d.count(wp::LatchEventKind::kStop), 1);
  EXPECT_EQ(d.count(wp::LatchEventKind::kMuteEnded), 1);
}

TEST(StopLatch, EventListIsBoundedAndSaysWhatItLost) {
  wp::LatchParams p;
  Drive d(p);
  d.step(0.0, 1.0);
  std::string why;
  for (int i = 0; i < wp::LatchEvents::kCapacity + 5; ++i) {
    d.latch.requestMute(wp::nanoseconds(0.05), {"x"}, {}, 1.0, &why);  // refused: muting off
  }
  d.step(0.1, 1.0);
  EXPECT_EQ(d.latch.events().size(), wp::LatchEvents::kCapacity);
  EXPECT_NE(d.latch.events()[wp::LatchEvents::kCapacity - 1].reason.find("not kept"),
            std::string::npos);
}

TEST(StopLatch, SteadyCyclesAllocateNothing) {
  // Held in a manual stop with category 1 waiting for standstill and a mute check per pair:
  // the cycles between transitions allocate nothing.
  wp::LatchParams p = manual();
  p.stop_category = 1;
  p.max_mute_time = 10.0;
  Drive d(p);
  runThenStop(&d);
  const std::string label = "person", id = "tracks/person_1";
  d.run(1.1, 2.0, 0.0);
  const long before = wp_test::allocationCount();
  for (int i = 0; i < 50; ++i) {
    d.latch.noteJointSpeed(wp::nanoseconds(2.0 + 0.1 * i), 0.5, true);  // moving: no halt
    d.step(2.05 + 0.1 * i, 1.0);
    EXPECT_FALSE(d.latch.muted(label, id));
  }
  EXPECT_EQ(wp_test::allocationCount() - before, 0);
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
