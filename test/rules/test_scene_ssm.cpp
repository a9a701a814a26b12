// Speed and separation monitoring over a scene, ROS-free (formerly the rostest ssm_approach):
// a person walks straight at a static robot box, stands beside it, and walks away; every
// cycle's verdict against the ISO/TS 15066 formula written out from the known geometry, the
// protective stop without a predicted contact, and the hysteresis after the person leaves.
// (The SafetyStatus message is fillSafetyStatus's, test_conversions; the speed_scale and
// speed_override topics are the rostest ssm_actions'.)

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "monitor_scenes.hpp"  // test/shared
#include "node_scene.hpp"      // test/shared

namespace wp = workspace_proximity;
using wp_test::SceneCycle;
using wp_test::SceneEvent;
using wp_test::SceneNode;
using wp_test::SceneTrack;

namespace {

// The defaults: T_r 0.1 s, T_s 0.3 s, C 0.1 m, Z_d 0.1 m, Z_r 0.02 m, v_max 1 m/s.
constexpr double kTr = 0.1, kTs = 0.3, kC = 0.1, kZd = 0.1, kZr = 0.02, kVmax = 1.0;

/// S_p(v_r) = v_h (T_r + T_s) + v_r T_r + v_r T_s / 2 + C + Z_d + Z_r, m.
double required(double v_h, double v_r) {
  return v_h * (kTr + kTs) + v_r * kTr + v_r * kTs / 2.0 + kC + kZd + kZr;
}

/// min(1, v_allowed / v_max) with v_allowed the largest v_r >= 0 with S_p(v_r) <= d.
double scale(double d, double v_h) {
  const double spare = d - required(v_h, 0.0);
  return std::min(1.0, std::max(0.0, spare / (kTr + kTs / 2.0) / kVmax));
}

}  // namespace

// The robot is one static 1 m cube "post" (x in [-0.5, 0.5]). A person (0.5 x 0.5 x 1.8 m,
// label "person", margin 0) starts 4 m from its face and
//   A  walks straight at it at 1 m/s for 3.8 s (d = 4 - t),
//   B  stands still 0.2 m from it for 1.5 s,
//   C  walks away at 0.5 m/s (d = 0.2 + 0.5 (t - 5.3)).
// So S_p(v_r) = 0.4 v_h + 0.25 v_r + 0.22 and the raw scale clamp((d - 0.4 v_h - 0.22) / 0.25,
// 0, 1), v_h = 1 m/s in A and 0 in B and C. Cycles within 0.15 s after a change of velocity
// are not compared with the formula (the monitor extrapolates the last array over it).
TEST(SceneSsm, ApproachStandAndLeave) {
  constexpr double kHold = 0.5, kRate = 0.5, kPeriod = 0.05;
  constexpr double kStop = 3.8, kAway = 5.3, kEnd = 8.5;
  wp::MonitorParams p = wp_test::commonParams();
  ASSERT_EQ(p.ssm.hold_time, kHold);
  ASSERT_EQ(p.ssm.max_increase_rate, kRate);
  SceneNode node(p, {wp_test::robotBox("post", {0.5, 0.5, 0.5}, {0.0, 0.0, 0.5})},
                 {"/tracked_objects"}, false);
  std::vector<SceneTrack> tracks{SceneTrack("p1", "person", {0.5 + 0.25 + 4.0, 0.0, 0.9},
                                            {0.5, 0.5, 1.8}, {-1.0, 0.0, 0.0})};
  wp_test::ScenePublisher pub;
  pub.tracks = &tracks;
  pub.latency = 0.05;
  pub.stop = kEnd;
  node.publishers.push_back(pub);
  const std::vector<SceneCycle> all = node.record(0.0, kEnd + 0.3, 0.0, [&](double t) {
    const long ms = std::lround(t * 1000);
    if (ms == 3810) tracks[0].setVelocity(kStop, {0.0, 0.0, 0.0});
    if (ms == 5310) tracks[0].setVelocity(kAway, {0.5, 0.0, 0.0});
  });
  auto gap = [&](double t) { return std::max(0.0, tracks[0].centre(t).x() - 0.25 - 0.5); };
  auto phase = [&](double t) { return t < kStop ? 'A' : (t < kAway ? 'B' : 'C'); };

  std::vector<const SceneCycle*> statuses;
  for (const SceneCycle& c : all) {
    if (c.t >= 0.3 && c.t <= kEnd - 0.1) statuses.push_back(&c);
  }
  ASSERT_GT(statuses.size(), 120u);
  int checked_a = 0, checked_b = 0, checked_c = 0, stopped = 0, held_zero = 0, rising = 0;
  const SceneCycle* prev = nullptr;
  double first_above = -1.0;  // cycle instant from which the raw scale stays above the output
  for (const SceneCycle* m : statuses) {
    const double t = m->t;
    const wp::SsmVerdict& v = m->ssm;
    char ctx[200];
    std::snprintf(ctx, sizeof(ctx), "t=%.3f %c: raw %.4f scale %.4f %s-%s d %.4f S_p %.4f v_h %.3f",
                  t, phase(t), v.raw_scale, v.speed_scale, m->ssm_robot.c_str(),
                  m->ssm_object.c_str(), v.separation, v.required_separation, v.approach_speed);
    EXPECT_FALSE(m->degraded) << ctx << " " << wp_test::joined(m->status_lines);
    EXPECT_TRUE(0.0 <= v.speed_scale && v.speed_scale <= 1.0 && 0.0 <= v.raw_scale &&
                v.raw_scale <= 1.0) << ctx;
    // The hysteresis, on every cycle: never above the raw scale, down at once, up only after
    // the hold and at the rate.
    EXPECT_LE(v.speed_scale, v.raw_scale + 1e-12) << ctx;
    if (prev != nullptr) {
      const double dt = t - prev->t;
      EXPECT_LE(v.speed_scale - prev->ssm.speed_scale, kRate * dt + 1e-9) << ctx;
      if (v.raw_scale <= prev->ssm.speed_scale) {
        EXPECT_EQ(v.speed_scale, v.raw_scale) << "did not drop at once: " << ctx;
      }
    }
    if (v.raw_scale > v.speed_scale ||
        (prev != nullptr && v.speed_scale > prev->ssm.speed_scale)) {
      if (first_above < 0) first_above = t;
    } else {
      first_above = -1.0;
    }
    if (phase(t) == 'C' && first_above >= 0) {
      const double since = t - first_above;
      if (since < kHold - 1e-6) {
        EXPECT_EQ(v.speed_scale, 0.0) << "rose before the hold: " << ctx;
        ++held_zero;
      } else {
        const double want = std::min(v.raw_scale, kRate * (since - kHold));
        EXPECT_NEAR(v.speed_scale, want, kRate * kPeriod + 1e-6)
            << "rise after the hold (" << since << " s): " << ctx;
        rising += v.speed_scale < v.raw_scale;
      }
    }
    prev = m;

    // The formula from the known geometry, away from the changes of velocity.
    if ((kStop <= t && t < kStop + 0.15) || (kAway <= t && t < kAway + 0.15)) continue;
    const double d = gap(t);
    const double v_h = phase(t) == 'A' ? 1.0 : 0.0;
    EXPECT_NEAR(v.raw_scale, scale(d, v_h), 0.01) << "formula: " << ctx;
    const double full_speed_needs = required(v_h, 1.0);
    if (d <= full_speed_needs - 0.01) {
      EXPECT_EQ(m->ssm_robot, "post") << ctx;
      EXPECT_EQ(m->ssm_object, "p1") << ctx;
      EXPECT_NEAR(v.separation, d, 1e-3) << ctx;
      EXPECT_NEAR(v.approach_speed, v_h, 1e-6) << ctx;
      EXPECT_NEAR(v.required_separation, full_speed_needs, 1e-6) << ctx;
    }
    if (required(v_h, 0.0) > d + 0.01) {  // even a standing robot is too close
      EXPECT_EQ(v.raw_scale, 0.0) << ctx;
      EXPECT_EQ(v.speed_scale, 0.0) << ctx;  // the protective stop
      ++stopped;
    }
    (phase(t) == 'A' ? checked_a : phase(t) == 'B' ? checked_b : checked_c) += 1;
  }
  EXPECT_GT(checked_a, 50);
  EXPECT_GT(checked_b, 20);
  EXPECT_GT(checked_c, 40);
  EXPECT_GT(stopped, 30);
  EXPECT_GE(held_zero, 8);
  EXPECT_GE(rising, 20);
  EXPECT_EQ(statuses.back()->ssm.speed_scale, 1.0) << "back to full speed at the end";

  // Standing still: no contact is predicted (after the pair's END), yet the robot stops.
  int standing = 0;
  for (const SceneCycle& c : all) {
    if (c.t < kStop + 0.3 || c.t >= kAway) continue;
    ++standing;
    for (const SceneEvent* e : wp_test::eventsFor(c.events, "p1", "post")) {
      EXPECT_EQ(e->state, wp::ContactState::kEnd) << "contact predicted while standing still";
    }
  }
  EXPECT_GT(standing, 15);
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
