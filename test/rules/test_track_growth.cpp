// Tracked objects within bounds, ROS-free: a label's position_error, velocity_error,
// max_accel and max_speed grow its tracks' margins through the monitor's cycle. Every
// expected number is worked out by hand from the model: an object standing still at face gap
// g from a static box first touches it when margin + position_error + R(s) = g, with
// R(s) = min(e s + a s^2 / 2, (v_max + |v|) s) and s counted from the measurement stamp.
// The defaults (all 0) are checked against a world built by hand without any growth, bit for
// bit.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "monitor_scenes.hpp"  // test/shared
#include "workspace_proximity/rules/monitor.hpp"
#include "workspace_proximity/rules/track_growth.hpp"

namespace wp = workspace_proximity;

namespace {

constexpr wp::Stamp kSecond = 1000000000;
constexpr wp::Stamp kT0 = 1000 * kSecond;
// The narrow phase stops within its distance tolerance (1e-5 m) of contact: at the growth
// rates here (>= 1 m/s) that is at most 1e-5 s early, and never late.
constexpr double kEarly = 2e-5;  // s
constexpr double kLate = 1e-9;   // s, rounding only

wp::MonitorParams params(const wp::LabelSettings& person) {
  return wp_test::marginFreeParams(5.0, person);
}

wp::LabelSettings person(double velocity_error, double max_accel, double max_speed) {
  wp::LabelSettings l;
  l.margin = 0.0;
  l.velocity_error = velocity_error;
  l.max_accel = max_accel;
  l.max_speed = max_speed;
  return l;
}

// A robot "wall": 1 m thick along x (faces at x = +-0.5), 100 m long along y, posed at the
// origin and standing still.
wp::RobotBodySpec wall() { return wp_test::robotBox("wall", {0.5, 50.0, 0.5}); }

struct Fixture {
  explicit Fixture(const wp::LabelSettings& p, const std::string& label = "person")
      : monitor(params(p), {wall()}, {"/boxes"}, false, nullptr), clock(&timing),
        label(label) {
    EXPECT_TRUE(monitor.poseRobot(0, wp::BodyMotion()));
  }
  // A 1 m cube whose near face is `gap` m from the wall's face at x = 0.5, moving at
  // (vx, vy), observed at `stamp`.
  // `own`: the tracker's own errors for the box (default: none, the label's settings).
  void object(double gap, double vx, double vy, wp::Stamp stamp, wp::Stamp now,
              const wp::TrackErrors& own = wp::TrackErrors()) {
    wp::BoxObservation b;
    b.id = "p1";
    b.label = label;
    b.position = {0.5 + gap + 0.5, 0, 0};
    b.dimensions = {1, 1, 1};
    b.linear_velocity = {vx, vy, 0};
    b.position_error = own.position_error;
    b.velocity_error = own.velocity_error;
    b.velocity_known = own.velocity_known;
    monitor.noteReceipt(0, now);
    ASSERT_TRUE(monitor.ingest(0, stamp, now, Eigen::Isometry3d::Identity(), {b}));
  }
  const wp::PairEvent& only(wp::Stamp now) {
    const wp::CycleReport& r = monitor.cycle(now, &clock);
    EXPECT_EQ(r.eventCount(), 1u);
    return r.event(0);
  }
  bool none(wp::Stamp now) { return monitor.cycle(now, &clock).eventCount() == 0; }

  wp::Monitor monitor;
  wp::CycleTiming timing;
  wp::StageClock clock;
  std::string label;
};

// Never late, at most kEarly early.
void expectFirstContact(const wp::PairEvent& e, double analytic, const char* what) {
  EXPECT_LE(e.time_to_contact, analytic + kLate) << what;
  EXPECT_GE(e.time_to_contact, analytic - kEarly) << what;
}

// One object of `l`'s label at `gap` m from the wall, moving at (vx, vy), measured at
// `stamp`: its one event, seen by a cycle at kT0, first touches at `analytic` s.
void expectOnlyContactAt(const wp::LabelSettings& l, double gap, double vx, double vy,
                         double analytic, const char* what, wp::Stamp stamp = kT0) {
  Fixture f(l);
  f.object(gap, vx, vy, stamp, kT0);
  expectFirstContact(f.only(kT0), analytic, what);
}

// The same object, standing: no event at all.
bool noContact(const wp::LabelSettings& l, double gap) {
  Fixture f(l);
  f.object(gap, 0.0, 0.0, kT0, kT0);
  return f.none(kT0);
}

}  // namespace

TEST(TrackGrowth, VelocityErrorAloneReachesAStandingPersonsGapAtGapOverError) {
  // e = 1.6 m/s, no acceleration term, zero margins, standing 1.6 m from the wall:
  // R(s) = 1.6 s reaches 1.6 m at s = 1.0 s after the measurement.
  Fixture f(person(1.6, 0.0, 0.0));
  f.object(1.6, 0.0, 0.0, kT0, kT0);
  const wp::PairEvent& e = f.only(kT0);
  expectFirstContact(e, 1.0, "measured now");
  EXPECT_NEAR(e.distance, 1.6, 1e-9);  // nothing has grown yet
  // Without growth a standing person is no contact at all.
  EXPECT_TRUE(noContact(person(0.0, 0.0, 0.0), 1.6));
}

TEST(TrackGrowth, GrowthCountsFromTheMeasurementStampEitherSide) {
  // Measured 0.2 s before the cycle: 0.2 s of the 1.0 s have passed, and 0.32 m of the margin
  // has grown already.
  Fixture late(person(1.6, 0.0, 0.0));
  late.object(1.6, 0.0, 0.0, kT0 - kSecond / 5, kT0);
  const wp::PairEvent& e = late.only(kT0);
  expectFirstContact(e, 0.8, "measured 0.2 s ago");
  EXPECT_NEAR(e.distance, 1.6 - 0.32, 1e-9);
  // Stamped 0.2 s ahead of the cycle (within ~max_future): extrapolated backwards, as
  // uncertain as forwards, so also 0.8 s.
  expectOnlyContactAt(person(1.6, 0.0, 0.0), 1.6, 0.0, 0.0, 0.8, "stamped 0.2 s ahead",
                      kT0 + kSecond / 5);
}

TEST(TrackGrowth, MaxAccelAloneReachesAtTheSquareRoot) {
  // a = 2 m/s^2: R(s) = s^2 reaches 1 m at s = 1.0 s.
  expectOnlyContactAt(person(0.0, 2.0, 0.0), 1.0, 0.0, 0.0, 1.0, "a = 2, gap 1");
  // Both terms: e = 0.5, a = 2, gap 1.5: 0.5 s + s^2 = 1.5 -> s = (-0.5 + sqrt(6.25)) / 2 = 1.
  expectOnlyContactAt(person(0.5, 2.0, 0.0), 1.5, 0.0, 0.0, 1.0, "e = 0.5, a = 2, gap 1.5");
}

TEST(TrackGrowth, MaxSpeedCapsTheGrowthAtSpeedBoundPlusCurrentSpeed) {
  // a = 4 m/s^2, v_max = 1 m/s, standing: R(s) = min(2 s^2, 1 s), the cap from s = 0.5 s on.
  // Gap 1.5 m: capped at s = 1.5 s (uncapped 2 s^2 would reach it at 0.866 s).
  expectOnlyContactAt(person(0.0, 4.0, 1.0), 1.5, 0.0, 0.0, 1.5, "standing, capped");
  // Walking along the wall at 1 m/s (never approaching it at constant velocity): the cap is
  // v_max + |v| = 2 m/s, R(s) = min(2 s^2, 2 s), the cap from s = 1 s on. Gap 3 m: s = 1.5 s
  // (a cap of v_max alone would give 3.0 s, none 1.22 s).
  expectOnlyContactAt(person(0.0, 4.0, 1.0), 3.0, 0.0, 1.0, 1.5,
                      "walking along, capped at v_max + |v|");
  // A cap alone does not grow anything.
  EXPECT_TRUE(noContact(person(0.0, 0.0, 1.0), 0.5));
}

TEST(TrackGrowth, PositionErrorIsAddedToTheMargin) {
  // Approaching at 1 m/s from a gap of 2 m, margin 0.1 + position_error 0.4: touching when the
  // gap is 0.5 m, at 1.5 s; the distance now is 2 - 0.5 = 1.5 m.
  wp::LabelSettings l = person(0.0, 0.0, 0.0);
  l.margin = 0.1;
  l.position_error = 0.4;
  Fixture f(l);
  f.object(2.0, -1.0, 0.0, kT0, kT0);
  const wp::PairEvent& e = f.only(kT0);
  EXPECT_NEAR(e.time_to_contact, 1.5, 1e-6);
  EXPECT_NEAR(e.distance, 1.5, 1e-9);
  EXPECT_EQ(f.monitor.world().desc(f.monitor.tracks().track(0).handle).margin, 0.5);
}

TEST(TrackGrowth, SeparationStaysTheConstantVelocityValue) {
  // Approaching at 1 m/s from 1 m with e = 0.5 m/s: first contact of the grown shapes when
  // 1 - s = 0.5 s, s = 2/3; the constant-velocity contact (1 m cube through a 1 m wall) ends
  // at (1 + 2) / 1 = 3 s, and that is the separation reported.
  Fixture f(person(0.5, 0.0, 0.0));
  f.object(1.0, -1.0, 0.0, kT0, kT0);
  const wp::PairEvent& e = f.only(kT0);
  expectFirstContact(e, 2.0 / 3.0, "approaching with growth");
  EXPECT_NEAR(e.time_to_separation, 3.0, 1e-4);
  // A standing person that only the growth reaches has no constant-velocity contact: the
  // separation is the first contact itself, never earlier.
  Fixture standing(person(1.6, 0.0, 0.0));
  standing.object(1.6, 0.0, 0.0, kT0, kT0);
  const wp::PairEvent& s = standing.only(kT0);
  EXPECT_EQ(s.time_to_separation, s.time_to_contact);
}

TEST(TrackGrowth, OnlyTheLabelsTracksGrow) {
  // The settings are the person label's: a box of another label at the same place is not
  // reached.
  Fixture f(person(1.6, 0.0, 0.0), "pallet");
  f.object(1.6, 0.0, 0.0, kT0, kT0);
  EXPECT_TRUE(f.none(kT0));
}

TEST(TrackGrowth, LiveTuningAppliesAtTheNextCycle) {
  Fixture f(person(0.0, 0.0, 0.0));
  f.object(1.6, 0.0, 0.0, kT0, kT0);
  EXPECT_TRUE(f.none(kT0));
  wp::MonitorParams p = f.monitor.params();
  p.labels["person"].velocity_error = 1.6;
  p.labels["person"].position_error = 0.8;
  f.monitor.setParams(p);
  // Margin 0.8 now, 0.8 m left for R(s) = 1.6 s: s = 0.5 s after the stamp, 0.1 s ago.
  f.object(1.6, 0.0, 0.0, kT0 + kSecond / 10, kT0 + kSecond / 10);
  expectFirstContact(f.only(kT0 + kSecond / 5), 0.4, "after tuning");
  // Back to zero: no growth, no contact (the pair ENDs).
  p.labels["person"].velocity_error = 0.0;
  p.labels["person"].position_error = 0.0;
  f.monitor.setParams(p);
  EXPECT_EQ(f.only(kT0 + kSecond / 4).state, wp::ContactState::kEnd);
  EXPECT_TRUE(f.none(kT0 + kSecond * 3 / 10));
}

TEST(TrackGrowth, DefaultsGiveTodaysEventsBitForBit) {
  // Default settings (every growth term 0) against a world built by hand from the same bodies
  // and motions, without setGrowth: the events are equal to the last bit.
  struct Scene {
    double gap, vx, vy;
    wp::Stamp stamp;
  };
  const Scene scenes[] = {{4.0, -2.0, 0.0, kT0 - kSecond / 10},
                          {0.7, -0.3, 0.4, kT0 - kSecond / 30},
                          {0.0, 0.0, 0.0, kT0},
                          {1.2, -1.0, -0.5, kT0 - kSecond / 7}};
  for (const Scene& s : scenes) {
    wp::LabelSettings defaults;
    defaults.margin = 0.1;
    defaults.max_speed = 2.0;  // a cap without growth terms changes nothing either
    Fixture f(defaults);
    f.object(s.gap, s.vx, s.vy, s.stamp, kT0);
    const wp::PairEvent& e = f.only(kT0);

    wp::WorldConfig config;
    config.rules = wp::makePairRules(f.monitor.params());
    wp::ProximityWorld world(config);
    world.addBody(wp::BodyDesc{"wall", "robot", wp::BodyGroup::kRobot, wall().shape, 0.0},
                  wp::BodyMotion());
    wp::BodyMotion m;
    m.position = {0.5 + s.gap + 0.5, 0, 0};
    m.linear_velocity = {s.vx, s.vy, 0};
    world.addBody(wp::BodyDesc{"p1", "person", wp::BodyGroup::kObject,
                               wp::Shape::box({0.5, 0.5, 0.5}), 0.1},
                  m.advanced(wp::secondsBetween(s.stamp, kT0)));
    const std::vector<wp::PairEvent>& expected = world.predict(5.0);
    ASSERT_EQ(expected.size(), 1u);
    EXPECT_EQ(e.time_to_contact, expected[0].time_to_contact);
    EXPECT_EQ(e.time_to_separation, expected[0].time_to_separation);
    EXPECT_EQ(e.distance, expected[0].distance);
    EXPECT_EQ(e.closing_speed, expected[0].closing_speed);
    EXPECT_TRUE(e.normal == expected[0].normal);
    EXPECT_TRUE(e.point_a == expected[0].point_a);
    EXPECT_TRUE(e.point_b == expected[0].point_b);
  }
}

TEST(TrackGrowth, GrowthOfALabel) {
  wp::LabelSettings l;
  EXPECT_TRUE(wp::trackGrowth(l, 1.0, 0.3).none());
  l.velocity_error = 0.3;
  l.max_accel = 3.0;
  l.max_speed = 2.0;
  l.position_error = 0.05;
  l.margin = 0.1;
  EXPECT_DOUBLE_EQ(wp::trackMargin(l), 0.15);
  const wp::MarginGrowth g = wp::trackGrowth(l, 1.2, -0.1);
  ASSERT_TRUE(g.valid());
  EXPECT_EQ(g.speed_cap, 3.2);
  EXPECT_EQ(g.age, 0.1);
  // R(0.1 + 0.4) = min(0.3 * 0.5 + 1.5 * 0.25, 3.2 * 0.5) = 0.525
  EXPECT_NEAR(g.at(0.4), 0.525, 1e-12);
  l.max_speed = 0.0;  // no cap
  EXPECT_EQ(wp::trackGrowth(l, 1.2, 0.0).speed_cap, std::numeric_limits<double>::infinity());
}

wp::TrackErrors own(double position_error, double velocity_error, bool velocity_known = true) {
  wp::TrackErrors e;
  e.position_error = position_error;
  e.velocity_error = velocity_error;
  e.velocity_known = velocity_known;
  return e;
}

TEST(TrackGrowth, ATracksOwnPositionErrorVisiblyWidensTheMargin) {
  // Label: margin 0.1, position_error 0.05. Approaching at 1 m/s from a gap of 2 m, no growth
  // terms: touching when the gap equals the margin, at (2 - margin) / 1 s.
  wp::LabelSettings l = person(0.0, 0.0, 0.0);
  l.margin = 0.1;
  l.position_error = 0.05;
  struct Case {
    double own, margin;  // the box's own position_error, the margin it must get
  } const cases[] = {
      {0.0, 0.15},    // none: the label's
      {0.02, 0.15},   // below the label's: the label is a floor
      {0.30, 0.40},   // above: its own, 0.1 + 0.3
      {0.123, 0.23},  // rounded up to the next centimetre, never below the error
  };
  for (const Case& c : cases) {
    Fixture f(l);
    f.object(2.0, -1.0, 0.0, kT0, kT0, own(c.own, 0.0));
    const wp::PairEvent& e = f.only(kT0);
    EXPECT_NEAR(f.monitor.world().desc(f.monitor.tracks().track(0).handle).margin, c.margin, 1e-12)
        << "own " << c.own;
    EXPECT_NEAR(e.time_to_contact, 2.0 - c.margin, 1e-6) << "own " << c.own;
  }
}

TEST(TrackGrowth, AMarginFollowsTheTrackersErrorUpAtOnceAndDownWithSlack) {
  wp::LabelSettings l = person(0.0, 0.0, 0.0);
  l.margin = 0.1;
  Fixture f(l);
  auto margin = [&] { return f.monitor.world().desc(f.monitor.tracks().track(0).handle).margin; };
  wp::Stamp t = kT0;
  f.object(3.0, 0.0, 0.0, t, t, own(0.30, 0.0));
  EXPECT_NEAR(margin(), 0.40, 1e-12);
  t += kSecond / 20;
  f.object(3.0, 0.0, 0.0, t, t, own(0.35, 0.0));  // larger: at once
  EXPECT_NEAR(margin(), 0.45, 1e-12);
  t += kSecond / 20;
  f.object(3.0, 0.0, 0.0, t, t, own(0.34, 0.0));  // 1 cm smaller: kept (never too small)
  EXPECT_NEAR(margin(), 0.45, 1e-12);
  t += kSecond / 20;
  f.object(3.0, 0.0, 0.0, t, t, own(0.20, 0.0));  // 15 cm smaller: shrinks
  EXPECT_NEAR(margin(), 0.30, 1e-12);
}

TEST(TrackGrowth, ATracksOwnVelocityErrorGrowsItWhereLargerThanTheLabels) {
  // Label e = 0.4 m/s, standing 1.6 m from the wall, no margins: R(s) = e s reaches the gap at
  // 1.6 / e. The box's own e = 0.8 m/s: at 2.0 s; own 0.2 (below the label): at 4.0 s.
  expectOnlyContactAt(person(0.4, 0.0, 0.0), 1.6, 0.0, 0.0, 4.0, "label only");
  Fixture larger(person(0.4, 0.0, 0.0));
  larger.object(1.6, 0.0, 0.0, kT0, kT0, own(0.0, 0.8));
  expectFirstContact(larger.only(kT0), 2.0, "own 0.8 m/s");
  Fixture smaller(person(0.4, 0.0, 0.0));
  smaller.object(1.6, 0.0, 0.0, kT0, kT0, own(0.0, 0.2));
  expectFirstContact(smaller.only(kT0), 4.0, "own 0.2 m/s: the label's floor");
  // A label without any growth term: the box's own error alone grows it (1.6 / 0.8 = 2 s).
  Fixture alone(person(0.0, 0.0, 0.0));
  alone.object(1.6, 0.0, 0.0, kT0, kT0, own(0.0, 0.8));
  expectFirstContact(alone.only(kT0), 2.0, "own 0.8 m/s, label none");
}

TEST(TrackGrowth, AnUnknownVelocityGrowsAtTheLabelsMaxSpeedFromStandingStill) {
  // Label: e = 0.3, a = 4, v_max = 2 m/s. The box says it moves at 1 m/s away from the wall,
  // but the velocity is not known: nominal 0, R(s) = 2 s, whatever e and a say. Gap 3 m:
  // 1.5 s, the first contact of the same object running at v_max straight at the wall.
  const wp::LabelSettings l = person(0.3, 4.0, 2.0);
  Fixture away(l);
  away.object(3.0, 1.0, 0.0, kT0, kT0, own(0.0, 0.0, false));
  expectFirstContact(away.only(kT0), 1.5, "unknown velocity, reported moving away");
  EXPECT_EQ(away.monitor.world().motion(away.monitor.tracks().track(0).handle).linear_velocity,
            Eigen::Vector3d::Zero());
  Fixture towards(l);
  towards.object(3.0, -1.0, 0.0, kT0, kT0, own(0.0, 0.0, false));
  expectFirstContact(towards.only(kT0), 1.5, "unknown velocity, reported moving towards");
  // Measured 0.25 s ago: 0.5 m have grown already, 1.25 s left.
  Fixture late(l);
  late.object(3.0, 0.0, 0.0, kT0 - kSecond / 4, kT0, own(0.0, 0.0, false));
  expectFirstContact(late.only(kT0), 1.25, "unknown velocity, measured 0.25 s ago");
  // Once the velocity is known the label's model applies: standing, R = min(0.3 s + 2 s^2,
  // 2 s) = 3 at s = 1.5 (the cap; uncapped it would be (-0.3 + sqrt(24.09)) / 4 = 1.152).
  Fixture known(l);
  known.object(3.0, 0.0, 0.0, kT0, kT0);
  expectFirstContact(known.only(kT0), 1.5, "known, standing");
}

TEST(TrackGrowth, GrowthOfAnUnknownVelocity) {
  wp::LabelSettings l;
  l.max_speed = 2.5;
  l.velocity_error = 0.3;
  l.max_accel = 4.0;
  wp::MarginGrowth g = wp::trackGrowth(l, 0.0, 0.1, own(0.0, 0.0, false));
  ASSERT_TRUE(g.valid());
  for (double t : {0.0, 0.3, 1.0, 4.0}) EXPECT_NEAR(g.at(t), 2.5 * (0.1 + t), 1e-12);
  // No max_speed: the larger of ssm_min_speed and the 2 m/s fallback.
  l.max_speed = 0.0;
  EXPECT_EQ(wp::unknownVelocitySpeed(l), 2.0);
  l.ssm_min_speed = 2.4;
  EXPECT_EQ(wp::unknownVelocitySpeed(l), 2.4);
  g = wp::trackGrowth(l, 0.0, 0.0, own(0.0, 0.0, false));
  EXPECT_NEAR(g.at(2.0), 4.8, 1e-12);
  // The box's own velocity error raises e, never lowers it.
  l.max_speed = 2.0;
  EXPECT_EQ(wp::trackGrowth(l, 1.0, 0.0, own(0.0, 0.9)).velocity_error, 0.9);
  EXPECT_EQ(wp::trackGrowth(l, 1.0, 0.0, own(0.0, 0.1)).velocity_error, 0.3);
  EXPECT_DOUBLE_EQ(wp::trackMargin(l, 0.5), l.margin + 0.5);
}

TEST(TrackGrowth, BadOwnErrorsAreRejectedByName) {
  wp::BoxObservation b;
  b.id = "p";
  std::string why;
  const wp::BoxLimits limits;
  b.position_error = std::nan("");
  EXPECT_EQ(wp::checkBox(b, limits, &why), wp::Drop::kNonFinite);
  b.position_error = -0.1;
  EXPECT_EQ(wp::checkBox(b, limits, &why), wp::Drop::kPosition);
  EXPECT_NE(why.find("position_error"), std::string::npos) << why;
  b.position_error = 0.1;
  b.velocity_error = 1e9;
  EXPECT_EQ(wp::checkBox(b, limits, &why), wp::Drop::kSpeed);
  EXPECT_NE(why.find("velocity_error"), std::string::npos) << why;
  b.velocity_error = 0.2;
  EXPECT_EQ(wp::checkBox(b, limits, &why), wp::Drop::kCount);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
