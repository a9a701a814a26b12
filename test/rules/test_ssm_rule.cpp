// Speed and separation monitoring: the ISO/TS 15066 formula against numbers worked out by hand,
// and the output filter's hysteresis (drops at once, rises only after the hold time and at most
// at the configured rate).

#include <gtest/gtest.h>

#include "workspace_proximity/rules/ssm_rule.hpp"

namespace wp = workspace_proximity;

namespace {
constexpr wp::Stamp kMs = 1000000;  // ns per ms
}

TEST(Ssm, TheFormulaWithTheDefaults) {
  const wp::SsmParams p;  // T_r 0.1, T_s 0.3, C 0.1, Z_d 0.1, Z_r 0.02, v_max 1.0
  // C + Z_d + Z_r = 0.22 m; per m/s of robot speed T_r + T_s / 2 = 0.25 m.
  EXPECT_NEAR(wp::protectiveSeparation(p, 0.0, 0.0), 0.22, 1e-12);
  EXPECT_NEAR(wp::protectiveSeparation(p, 1.6, 1.0), 1.6 * 0.4 + 0.1 + 0.15 + 0.22, 1e-12);
  // A person standing still 0.2 m away: inside C + Z_d + Z_r, protective stop.
  EXPECT_EQ(wp::allowedRobotSpeed(p, 0.2, 0.0), 0.0);
  EXPECT_EQ(wp::pairScale(p, 0.2, 0.0), 0.0);
  // Walking at 1.6 m/s, 1 m away: (1.0 - 0.64 - 0.22) / 0.25 = 0.56 m/s.
  EXPECT_NEAR(wp::allowedRobotSpeed(p, 1.0, 1.6), 0.56, 1e-12);
  EXPECT_NEAR(wp::pairScale(p, 1.0, 1.6), 0.56, 1e-12);
  // Far enough for full speed: d >= S_p(v_max) = 0.64 + 0.25 + 0.22 = 1.11 m.
  EXPECT_EQ(wp::pairScale(p, 1.11 + 1e-9, 1.6), 1.0);
  EXPECT_LT(wp::pairScale(p, 1.11 - 1e-6, 1.6), 1.0);
  // The allowed speed is the largest with S_p(v) <= d.
  for (double d : {0.3, 0.7, 1.5, 4.0}) {
    for (double vh : {0.0, 0.5, 2.0}) {
      const double v = wp::allowedRobotSpeed(p, d, vh);
      if (v > 0.0) {
        EXPECT_NEAR(wp::protectiveSeparation(p, vh, v), d, 1e-12);
      } else {
        EXPECT_GE(wp::protectiveSeparation(p, vh, 0.0), d);
      }
    }
  }
  wp::SsmParams slow = p;
  slow.robot_max_speed = 0.25;
  EXPECT_NEAR(wp::pairScale(slow, 0.27, 0.0), (0.27 - 0.22) / 0.25 / 0.25, 1e-12);
}

TEST(Ssm, TheFilterDropsAtOnceAndRisesSlowlyAfterTheHold) {
  wp::SsmParams p;
  p.max_increase_rate = 0.5;  // per second
  p.hold_time = 0.5;
  wp::SpeedScaleFilter f(p);
  EXPECT_EQ(f.output(), 0.0);  // nothing known yet
  // Raw 1 from t = 0: held at 0 for 0.5 s, then +0.5 per second (0.05 per 100 ms step).
  double t_full = -1.0;
  for (int ms = 0; ms <= 4000; ms += 100) {
    const double out = f.update(ms * kMs, 1.0);
    if (ms < 500) {
      EXPECT_EQ(out, 0.0) << ms;
    } else {
      EXPECT_NEAR(out, std::min(1.0, 0.5 * (ms - 500) / 1000.0), 1e-9) << ms;
    }
    if (out >= 1.0 && t_full < 0) t_full = ms / 1000.0;
  }
  EXPECT_NEAR(t_full, 2.5, 1e-9);
  // A drop is immediate.
  EXPECT_EQ(f.update(4100 * kMs, 0.3), 0.3);
  // A brief rise and dip restarts the hold: 0.4 s above, a dip, then 0.5 s above.
  for (int ms = 4200; ms <= 4500; ms += 100) EXPECT_EQ(f.update(ms * kMs, 0.9), 0.3) << ms;
  EXPECT_EQ(f.update(4600 * kMs, 0.3), 0.3);
  for (int ms = 4700; ms <= 5200; ms += 100) EXPECT_EQ(f.update(ms * kMs, 0.9), 0.3) << ms;
  EXPECT_NEAR(f.update(5300 * kMs, 0.9), 0.35, 1e-9);  // the hold ended at 5.2 s
  // Never above the raw scale.
  for (int ms = 5400; ms <= 9000; ms += 100) EXPECT_LE(f.update(ms * kMs, 0.9), 0.9);
  EXPECT_NEAR(f.output(), 0.9, 1e-12);
  f.reset();
  EXPECT_EQ(f.output(), 0.0);
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
