// Speed and separation monitoring through the monitor's cycle: the scale of analytic scenes
// (a person walking at a robot box, walking away, standing still inside the protective
// separation without any predicted contact), label rules (~ssm/labels, ssm_min_speed), the
// DEGRADED cap, the hysteresis after the person leaves, and, on random scenes, the scale
// against a brute-force minimum over every robot-object pair (so no pair within reach is
// missed by the broad phase). Every cycle runs through the CycleRunner, and the verdict the
// safety output receives (before the contacts are predicted) is the one checked; it is also the
// whole cycle's.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "monitor_scenes.hpp"  // test/shared
#include "workspace_proximity/rules/cycle_runner.hpp"
#include "workspace_proximity/rules/monitor.hpp"

namespace wp = workspace_proximity;

namespace {

constexpr wp::Stamp kSecond = 1000000000;
constexpr wp::Stamp kT0 = 1000 * kSecond;

wp::Stamp at(double seconds) { return kT0 + wp::nanoseconds(seconds); }

// ~ssm/ with the defaults: T_r 0.1, T_s 0.3, C 0.1, Z_d 0.1, Z_r 0.02.
wp::MonitorParams params() {
  return wp_test::marginFreeParams(2.0, wp::LabelSettings{0.0, 1.0, 0.4, 0.5, 0.2});
}

// The bridge would apply the offset; here the body's pose is its centre.
wp::RobotBodySpec box(const std::string& name, const Eigen::Vector3d& centre,
                      const Eigen::Vector3d& half) {
  return wp_test::robotBox(name, half, centre);
}

struct Person {
  std::string id;
  std::string label = "person";
  Eigen::Vector3d position;
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d size = Eigen::Vector3d(0.5, 0.5, 1.8);
  double position_error = 0.0;  // the tracker's own (0: none)
  double velocity_error = 0.0;
  bool velocity_known = true;
};

// What the safety output received: the verdict as it went out, and whether the cycle's events
// had been predicted by then.
class EarlySafety : public wp::CycleOutput {
 public:
  void safety(const wp::CycleReport& report, const wp::ProximityWorld&, const wp::CycleRun&) override {
    verdict = report.ssm;
    events_then = report.eventCount();
    ++calls;
  }
  void contacts(const wp::CycleReport&, const wp::ProximityWorld&) override {}
  wp::SsmVerdict verdict;
  std::size_t events_then = 0;
  int calls = 0;
};

class Cell {
 public:
  Cell(const wp::MonitorParams& p, std::vector<wp::RobotBodySpec> robot)
      : specs_(robot), monitor_(p, std::move(robot), {"/boxes"}, false, nullptr),
        runner_(&monitor_) {}

  // Every robot body at its spec's offset, standing still; the people as observed at `now`.
  const wp::CycleReport& cycle(wp::Stamp now, const std::vector<Person>& people) {
    for (int i = 0; i < static_cast<int>(specs_.size()); ++i) {
      wp::BodyMotion m;
      m.position = specs_[static_cast<std::size_t>(i)].offset.translation();
      EXPECT_TRUE(monitor_.poseRobot(i, m));
    }
    std::vector<wp::BoxObservation> boxes;
    for (const Person& p : people) {
      wp::BoxObservation b;
      b.id = p.id;
      b.label = p.label;
      b.position = p.position;
      b.dimensions = p.size;
      b.linear_velocity = p.velocity;
      b.position_error = p.position_error;
      b.velocity_error = p.velocity_error;
      b.velocity_known = p.velocity_known;
      boxes.push_back(b);
    }
    monitor_.noteReceipt(0, now);
    EXPECT_TRUE(monitor_.ingest(0, now, now, Eigen::Isometry3d::Identity(), boxes));
    // The node's cycle: the safety output goes out between the two halves.
    const int calls = early_.calls;
    EXPECT_FALSE(runner_.run(now, nullptr, &early_).failed);
    EXPECT_EQ(early_.calls, calls + 1);
    const wp::CycleReport& r = monitor_.report();
    // What went out early is the whole cycle's verdict, to the bit.
    EXPECT_EQ(early_.verdict.speed_scale, r.ssm.speed_scale);
    EXPECT_EQ(early_.verdict.raw_scale, r.ssm.raw_scale);
    EXPECT_EQ(early_.verdict.pairs, r.ssm.pairs);
    EXPECT_EQ(early_.verdict.reason, r.ssm.reason);
    return r;
  }
  wp::Monitor& monitor() { return monitor_; }
  const EarlySafety& early() const { return early_; }

 private:
  std::vector<wp::RobotBodySpec> specs_;
  wp::Monitor monitor_;
  wp::CycleRunner runner_;
  EarlySafety early_;
};

// The robot: a 1 m cube centred at the origin.
std::vector<wp::RobotBodySpec> post() { return {box("post", {0, 0, 0.5}, {0.5, 0.5, 0.5})}; }

}  // namespace

TEST(SsmCycle, APersonWalkingAtTheRobotGetsTheFormulaUntilTheStop) {
  const wp::MonitorParams p = params();
  Cell cell(p, post());
  // The person (0.5 m square) walks along -x at 1 m/s from a gap of 4 m: d(t) = 4 - t.
  int limited = 0, stopped = 0, full = 0;
  for (int k = 0; k <= 80; ++k) {
    const double t = 0.05 * k;
    const double d = std::max(0.0, 4.0 - t);
    Person person{"p1", "person", {0.5 + 0.25 + d, 0.0, 0.9}, {-1.0, 0.0, 0.0}};
    const wp::CycleReport& r = cell.cycle(at(t), {person});
    const wp::SsmVerdict& v = r.ssm;
    ASSERT_TRUE(v.enabled);
    EXPECT_FALSE(r.degraded) << r.status_lines.front();
    // v_h = 1 m/s straight at the robot: S_p(v_r) = 0.4 + 0.25 v_r + 0.22.
    const double expected = std::clamp((d - 0.4 - 0.22) / 0.25 / 1.0, 0.0, 1.0);
    EXPECT_NEAR(v.raw_scale, expected, 1e-9) << "t " << t;
    if (d <= 0.87 + 1e-9) {  // within S_p(v_max) = 0.87 m: the pair must be there
      ASSERT_TRUE(v.limited) << "t " << t;
      EXPECT_EQ(cell.monitor().world().desc(v.object).id, "p1");
      EXPECT_EQ(cell.monitor().world().desc(v.robot).id, "post");
      EXPECT_NEAR(v.separation, d, 1e-9);
      EXPECT_NEAR(v.approach_speed, 1.0, 1e-12);
      EXPECT_NEAR(v.required_separation, 0.87, 1e-12);
      ++limited;
    }
    if (expected == 0.0) {
      EXPECT_EQ(v.speed_scale, 0.0);
      ++stopped;
    }
    if (expected == 1.0) ++full;
  }
  EXPECT_GT(limited, 10);
  EXPECT_GT(stopped, 10);
  EXPECT_GT(full, 40);
}

TEST(SsmCycle, WalkingAwayTheScaleComesFromTheDistanceAloneOrTheLabelsMinimum) {
  wp::MonitorParams p = params();
  p.labels["visitor"] = p.labels["person"];
  p.labels["visitor"].ssm_min_speed = 1.6;  // the standard's walking speed
  Cell cell(p, post());
  for (int k = 0; k <= 20; ++k) {
    const double t = 0.05 * k;
    const double d = 0.3 + 0.5 * t;  // walking away along +y at 0.5 m/s
    Person walker{"w", "person", {0.0, 0.5 + 0.25 + d, 0.9}, {0.3, 0.5, 0.0}};
    Person visitor{"v", "visitor", {0.0, -(0.5 + 0.25 + 2.0 + d), 0.9}, {0.0, -0.5, 0.0}};
    const wp::CycleReport& r = cell.cycle(at(t), {walker, visitor});
    // v_h = 0 for the walker (its sideways 0.3 m/s does not approach): (d - 0.22) / 0.25. The
    // visitor, 2 m farther and also leaving, is assumed at its label's 1.6 m/s:
    // (d + 2 - 0.64 - 0.22) / 0.25, above 1 here.
    const double walker_scale = std::clamp((d - 0.22) / 0.25, 0.0, 1.0);
    const double visitor_scale = std::clamp((d + 2.0 - 0.64 - 0.22) / 0.25, 0.0, 1.0);
    EXPECT_NEAR(r.ssm.raw_scale, std::min(walker_scale, visitor_scale), 1e-9) << "t " << t;
    if (r.ssm.raw_scale < 1.0) {
      EXPECT_EQ(cell.monitor().world().desc(r.ssm.object).id, "w");
      EXPECT_EQ(r.ssm.approach_speed, 0.0);
    }
  }
  // The visitor alone, standing 1.0 m away: 1.6 m/s assumed, S_p(v_max) = 1.11 m.
  Cell alone(p, post());
  Person visitor{"v", "visitor", {1.75, 0.0, 0.9}};
  const wp::CycleReport& r = alone.cycle(at(0), {visitor});
  EXPECT_NEAR(r.ssm.raw_scale, (1.0 - 0.64 - 0.22) / 0.25, 1e-9);
  EXPECT_NEAR(r.ssm.approach_speed, 1.6, 1e-12);
  EXPECT_NEAR(r.ssm.required_separation, 1.11, 1e-12);
}

TEST(SsmCycle, AnUnknownVelocityApproachesAtTheLabelsMinimum) {
  wp::MonitorParams p = params();
  p.labels["unknown"] = p.labels["person"];
  p.labels["unknown"].ssm_min_speed = 1.6;
  // 1.0 m away, reported at 3 m/s straight at the robot but with velocity_known false: not a
  // velocity; the label's 1.6 m/s: (1.0 - 0.64 - 0.22) / 0.25 = 0.56.
  Cell cell(p, post());
  Person u{"u", "unknown", {0.5 + 0.25 + 1.0, 0.0, 0.9}, {-3.0, 0.0, 0.0}};
  u.velocity_known = false;
  const wp::CycleReport& r = cell.cycle(at(0), {u});
  EXPECT_NEAR(r.ssm.raw_scale, 0.56, 1e-9);
  EXPECT_NEAR(r.ssm.approach_speed, 1.6, 1e-12);
  // Known, the same 3 m/s: S_p(0) = 1.2 + 0.22 > 1.0, a stop.
  Cell known(p, post());
  u.velocity_known = true;
  EXPECT_EQ(known.cycle(at(0), {u}).ssm.raw_scale, 0.0);
}

TEST(SsmCycle, AFloorUntilMeasuredHoldsOnlyWhileTheVelocityIsUnknown) {
  // The `unknown` label as shipped: ssm_min_speed 1.6 until the velocity is known, then none.
  wp::MonitorParams p = params();
  p.labels["unknown"] = p.labels["person"];
  p.labels["unknown"].ssm_min_speed = 1.6;
  p.labels["unknown"].ssm_min_speed_measured = 0.0;
  // 1.0 m away, standing still. Unknown: v_h = 1.6, (1.0 - 0.64 - 0.22) / 0.25 = 0.56.
  Person u{"u", "unknown", {0.5 + 0.25 + 1.0, 0.0, 0.9}};
  u.velocity_known = false;
  Cell unknown(p, post());
  EXPECT_NEAR(unknown.cycle(at(0), {u}).ssm.raw_scale, 0.56, 1e-9);
  EXPECT_NEAR(unknown.monitor().report().ssm.approach_speed, 1.6, 1e-12);
  // Known, with its filter's own error 0.5 m/s: v_h = 0.5, (1.0 - 0.2 - 0.22) / 0.25 = 2.32:
  // full speed.
  u.velocity_known = true;
  u.velocity_error = 0.5;
  Cell measured(p, post());
  EXPECT_EQ(measured.cycle(at(0), {u}).ssm.raw_scale, 1.0);
  // 0.6 m away, known: (0.6 - 0.2 - 0.22) / 0.25 = 0.72, v_h the error alone.
  u.position = {0.5 + 0.25 + 0.6, 0.0, 0.9};
  Cell near(p, post());
  const wp::CycleReport& r = near.cycle(at(0), {u});
  EXPECT_NEAR(r.ssm.raw_scale, 0.72, 1e-9);
  EXPECT_NEAR(r.ssm.approach_speed, 0.5, 1e-12);
  // A floor between: 1.0 once measured, (0.6 - 0.4 - 0.22) < 0: a stop.
  p.labels["unknown"].ssm_min_speed_measured = 1.0;
  Cell between(p, post());
  const wp::CycleReport& rb = between.cycle(at(0), {u});
  EXPECT_EQ(rb.ssm.raw_scale, 0.0);
  EXPECT_NEAR(rb.ssm.approach_speed, 1.0, 1e-12);
  // The default (20) keeps ssm_min_speed for life: known or not, v_h = 1.6.
  p.labels["unknown"].ssm_min_speed_measured = 20.0;
  u.position = {0.5 + 0.25 + 1.0, 0.0, 0.9};
  Cell life(p, post());
  EXPECT_NEAR(life.cycle(at(0), {u}).ssm.raw_scale, 0.56, 1e-9);
}

TEST(SsmCycle, ATracksOwnErrorsWidenTheSeparation) {
  Cell cell(params(), post());
  // Walking at 1 m/s at the robot from 1.0 m with its tracker's own velocity error 0.5 m/s:
  // v_h = 1.5, (1.0 - 0.6 - 0.22) / 0.25 = 0.72 (without the error: (1 - 0.4 - 0.22) / 0.25 =
  // 1.52, full speed).
  Person walker{"w", "person", {0.5 + 0.25 + 1.0, 0.0, 0.9}, {-1.0, 0.0, 0.0}};
  walker.velocity_error = 0.5;
  const wp::CycleReport& r = cell.cycle(at(0), {walker});
  EXPECT_NEAR(r.ssm.raw_scale, 0.72, 1e-9);
  EXPECT_NEAR(r.ssm.approach_speed, 1.5, 1e-12);
  // Standing 0.6 m away with its own position error 0.3 m, 0.2 m beyond Z_d = 0.1: the pair
  // needs 0.2 m more, (0.6 - 0.2 - 0.22) / 0.25 = 0.72, S_p(v_max) = 0.47 + 0.2 = 0.67. The
  // reach must hold the extra too (0.47 < 0.6: without it the pair would not be seen).
  Cell standing(params(), post());
  Person still{"s", "person", {0.5 + 0.25 + 0.6, 0.0, 0.9}};
  still.position_error = 0.3;
  const wp::CycleReport& rs = standing.cycle(at(0), {still});
  ASSERT_TRUE(rs.ssm.limited);
  EXPECT_NEAR(rs.ssm.raw_scale, 0.72, 1e-9);
  EXPECT_NEAR(rs.ssm.required_separation, 0.67, 1e-12);
  // An own error within Z_d changes nothing: (0.6 - 0.22) / 0.25 > 1.
  Cell within(params(), post());
  still.position_error = 0.05;
  EXPECT_EQ(within.cycle(at(0), {still}).ssm.raw_scale, 1.0);
}

TEST(SsmCycle, StandingStillInsideTheProtectiveSeparationStopsWithoutAnyContact) {
  Cell cell(params(), post());
  // d = 0.2 m < C + Z_d + Z_r = 0.22 m, nobody moves: no contact within any horizon.
  Person person{"p1", "person", {0.5 + 0.2 + 0.25, 0.0, 0.9}};
  for (int k = 0; k < 10; ++k) {
    const wp::CycleReport& r = cell.cycle(at(0.1 * k), {person});
    EXPECT_EQ(r.eventCount(), 0u);
    EXPECT_EQ(r.ssm.raw_scale, 0.0);
    EXPECT_EQ(r.ssm.speed_scale, 0.0);
    EXPECT_NEAR(r.ssm.separation, 0.2, 1e-12);
    EXPECT_NE(r.ssm.reason.find("p1 at 0.20 m from post"), std::string::npos) << r.ssm.reason;
  }
}

TEST(SsmCycle, OnlyMonitoredLabelsCountAndOffMeansFullSpeed) {
  wp::MonitorParams p = params();
  p.ssm.labels = {"person"};
  Cell cell(p, post());
  Person cart{"c", "cart", {0.8, 0.0, 0.9}};      // 0.05 m away, not monitored
  Person person{"p", "person", {0.0, 1.15, 0.9}};  // 0.4 m away, still
  const wp::CycleReport& r = cell.cycle(at(0), {cart, person});
  EXPECT_NEAR(r.ssm.raw_scale, (0.4 - 0.22) / 0.25, 1e-9);
  EXPECT_EQ(r.ssm.pairs, 1);
  EXPECT_EQ(cell.monitor().world().desc(r.ssm.object).id, "p");

  p.ssm.enabled = false;
  Cell off(p, post());
  const wp::CycleReport& r_off = off.cycle(at(0), {Person{"p", "person", {0.8, 0.0, 0.9}}});
  EXPECT_FALSE(r_off.ssm.enabled);
  EXPECT_EQ(r_off.ssm.speed_scale, 1.0);
  // Nothing grows the robot's bounds while SSM is off.
  EXPECT_EQ(off.monitor().world().reach(off.monitor().robot().handle(0)), 0.0);
}

TEST(SsmCycle, DegradedCapsTheScaleAndSaysWhy) {
  wp::MonitorParams p = params();
  p.ssm.degraded_scale = 0.3;
  p.ssm.hold_time = 0.0;
  p.ssm.max_increase_rate = 100.0;
  Cell cell(p, post());
  Person far{"p", "person", {5.0, 0.0, 0.9}};
  for (int k = 0; k < 5; ++k) cell.cycle(at(0.05 * k), {far});
  EXPECT_EQ(cell.monitor().report().ssm.speed_scale, 1.0);
  // The tracker goes silent (no array for 0.6 s > track_timeout 0.5 s).
  wp::Monitor& m = cell.monitor();
  wp::BodyMotion still;
  still.position = {0, 0, 0.5};
  m.poseRobot(0, still);
  wp::CycleTiming timing;
  wp::StageClock clock(&timing);
  const wp::CycleReport& r = m.cycle(at(0.8), &clock);
  ASSERT_TRUE(r.degraded);
  EXPECT_EQ(r.ssm.raw_scale, 1.0);  // nothing within reach any more
  EXPECT_EQ(r.ssm.speed_scale, 0.3);
  EXPECT_NE(r.ssm.reason.find("DEGRADED, scale at most 0.30: source /boxes: no data for"),
            std::string::npos)
      << r.ssm.reason;
  // A failed cycle: nothing known, degraded_scale.
  m.cycleFailed(at(0.85), "boom");
  EXPECT_EQ(m.report().ssm.speed_scale, 0.3);
  EXPECT_TRUE(m.report().ssm.degraded);
  EXPECT_NE(m.report().ssm.reason.find("cycle failed: boom"), std::string::npos);
  // The clock goes back: the history is reset, the scale starts from 0 again.
  m.reset();
  const wp::CycleReport& after = cell.cycle(at(0.1), {far});
  EXPECT_EQ(after.ssm.speed_scale, 0.0);
}

TEST(SsmCycle, AfterThePersonLeavesTheScaleRisesOnlyAfterTheHoldAndAtTheRate) {
  wp::MonitorParams p = params();  // hold 0.5 s, rate 0.5 / s
  Cell cell(p, post());
  Person person{"p1", "person", {0.95, 0.0, 0.9}};  // standing 0.2 m away: stop
  double t = 0.0;
  for (; t < 1.0; t += 0.05) EXPECT_EQ(cell.cycle(at(t), {person}).ssm.speed_scale, 0.0);
  // Gone (walked 10 m away at once): the raw scale is 1 from here.
  person.position.x() = 10.0;
  const double left = t;
  double last = 0.0;
  for (; t < left + 3.5; t += 0.05) {
    const wp::CycleReport& r = cell.cycle(at(t), {person});
    EXPECT_EQ(r.ssm.raw_scale, 1.0);
    const double out = r.ssm.speed_scale;
    const double since = t - left;
    if (since < 0.5 - 1e-9) {
      EXPECT_EQ(out, 0.0) << since;
    } else {
      EXPECT_NEAR(out, std::min(1.0, 0.5 * (since - 0.5)), 1e-6) << since;
    }
    EXPECT_LE(out - last, 0.5 * 0.05 + 1e-9);
    last = out;
  }
  EXPECT_EQ(last, 1.0);
}

// Random cells: several robot boxes, people and carts of assorted sizes, speeds and minimum
// speeds, all axis-aligned so that the vector between nearest points is known exactly (for
// convex sets it is unique: per axis, the gap between the intervals). The monitor's raw scale
// must equal the minimum of the formula over every robot-object pair, wherever they are.
TEST(SsmCycle, TheScaleIsTheMinimumOverEveryPairAgainstBruteForce) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * u(rng); };
  int limiting = 0, zero = 0, partial = 0, early_with_events = 0;
  for (int scene = 0; scene < 30; ++scene) {
    wp::MonitorParams p = params();
    p.labels["cart"] = p.labels["default"];
    p.labels["cart"].ssm_min_speed = uniform(0.0, 2.0);
    // Every velocity here is known (measured): the floor is at most ssm_min_speed_measured.
    p.labels["cart"].ssm_min_speed_measured = scene % 3 ? uniform(0.0, 2.0) : 20.0;
    p.labels["person"].ssm_min_speed = scene % 2 ? 1.6 : 0.0;
    p.ssm.reaction_time = uniform(0.05, 0.3);
    p.ssm.stopping_time = uniform(0.1, 0.6);
    p.ssm.robot_max_speed = uniform(0.3, 2.0);
    std::vector<wp::RobotBodySpec> robot;
    const int links = 1 + scene % 5;
    for (int i = 0; i < links; ++i) {
      robot.push_back(box("link" + std::to_string(i),
                          {uniform(-1, 1), uniform(-1, 1), uniform(0.3, 1.5)},
                          {uniform(0.05, 0.4), uniform(0.05, 0.4), uniform(0.05, 0.4)}));
    }
    Cell cell(p, robot);
    for (int cycle = 0; cycle < 8; ++cycle) {
      std::vector<Person> people;
      const int n = 5 + scene % 20;
      for (int i = 0; i < n; ++i) {
        Person q;
        q.id = "o" + std::to_string(i);
        q.label = i % 3 ? "person" : "cart";
        q.size = {uniform(0.2, 1.5), uniform(0.2, 1.5), uniform(0.5, 2.0)};
        q.position = {uniform(-4, 4), uniform(-4, 4), uniform(0.0, 2.0)};
        q.velocity = {uniform(-2.5, 2.5), uniform(-2.5, 2.5), uniform(-0.2, 0.2)};
        people.push_back(q);
      }
      const wp::CycleReport& r = cell.cycle(at(0.05 * cycle), people);
      // Brute force over every pair, with nothing but the formula.
      double expected = 1.0, best_slack = HUGE_VAL;
      bool overlap = false;
      for (const wp::RobotBodySpec& link : robot) {
        const Eigen::Vector3d c = link.offset.translation(), h = link.shape.half_extents;
        for (const Person& q : people) {
          const Eigen::Vector3d hq = 0.5 * q.size;
          Eigen::Vector3d gap;  // from the object towards the robot
          for (int k = 0; k < 3; ++k) {
            const double lo_r = c[k] - h[k], hi_r = c[k] + h[k];
            const double lo_o = q.position[k] - hq[k], hi_o = q.position[k] + hq[k];
            gap[k] = std::max(0.0, lo_r - hi_o) - std::max(0.0, lo_o - hi_r);
          }
          const double d = gap.norm();
          const double min_speed =
              std::min(p.label(q.label).ssm_min_speed, p.label(q.label).ssm_min_speed_measured);
          const double along = d > 0 ? q.velocity.dot(gap / d) : 0.0;
          const double v_h = std::max({0.0, along, min_speed});
          overlap = overlap || d == 0.0;
          const wp::SsmParams& s = p.ssm;
          const double spare = d - v_h * (s.reaction_time + s.stopping_time) -
                               s.intrusion_distance - s.sensor_uncertainty - s.robot_uncertainty;
          const double scale = std::clamp(
              spare / (s.reaction_time + s.stopping_time / 2) / s.robot_max_speed, 0.0, 1.0);
          expected = std::min(expected, scale);
          const double slack = spare - s.robot_max_speed * (s.reaction_time + s.stopping_time / 2);
          best_slack = std::min(best_slack, slack);
        }
      }
      EXPECT_NEAR(r.ssm.raw_scale, expected, 1e-9) << "scene " << scene << " cycle " << cycle;
      // ... and so was the scale the safety output sent before any event was predicted.
      EXPECT_NEAR(cell.early().verdict.raw_scale, expected, 1e-9);
      EXPECT_EQ(cell.early().events_then, 0u);
      early_with_events += r.eventCount() > 0;
      if (expected < 1.0) {
        ASSERT_TRUE(r.ssm.limited);
        // The limiting pair has the smallest d - S_p(v_max) (for overlapping shapes the
        // direction of v_h is the contact normal's, which the brute force does not know).
        if (!overlap) {
          EXPECT_NEAR(r.ssm.separation - r.ssm.required_separation, best_slack, 1e-9);
        }
        ++limiting;
      }
      zero += expected == 0.0;
      partial += expected > 0.0 && expected < 1.0;
    }
  }
  EXPECT_GT(limiting, 50);
  EXPECT_GT(zero, 10);
  EXPECT_GT(partial, 10);
  EXPECT_GT(early_with_events, 50);  // cycles whose events came only after the scale went out
}

TEST(SsmCycle, AMutedObjectDoesNotLowerTheScaleUntilTheMuteEnds) {
  wp::MonitorParams p = params();
  p.ssm.max_mute_time = 2.5;
  Cell cell(p, post());
  // A forklift drives at the post at 1 m/s from a gap of 4 m: d(t) = 4 - t; S_p(v_max) = 0.87 m
  // (as the walking person above), so it is within from t = 3.13 and at the stop (raw 0) from
  // d <= 0.62, t >= 3.38. Muted from t = 1.0 for 2.5 s: until 3.5.
  std::string why;
  int muted_within = 0;
  for (int k = 0; k <= 80; ++k) {
    const double t = 0.05 * k;
    if (k == 20) {
      EXPECT_TRUE(cell.monitor().latch().requestMute(at(t), {"forklift"}, {}, 2.5, &why)) << why;
    }
    const double d = std::max(0.0, 4.0 - t);
    Person forklift{"f1", "forklift", {0.5 + 0.25 + d, 0.0, 0.9}, {-1.0, 0.0, 0.0}};
    const wp::SsmVerdict& v = cell.cycle(at(t), {forklift}).ssm;
    const bool within = d < 0.87 - 1e-9;
    EXPECT_EQ(v.within, within ? 1 : 0) << "t " << t;
    if (t >= 1.0 - 1e-9 && t < 3.5 - 1e-9) {
      ASSERT_NE(v.latch, nullptr);
      EXPECT_TRUE(v.latch->muted) << "t " << t;
      EXPECT_EQ(v.raw_scale, 1.0) << "t " << t;  // muted: the pair does not count
      ASSERT_NE(v.muted_slots, nullptr);
      EXPECT_EQ(std::count(v.muted_slots->begin(), v.muted_slots->end(), 1), 1) << "t " << t;
      if (within) {
        EXPECT_EQ(v.muted_pairs, 1);
        EXPECT_GT(v.speed_scale, 0.0) << "t " << t;
        ++muted_within;
      }
    }
    if (t >= 3.5 - 1e-9) {
      // The mute is over in the cycle at 3.5 itself: raw (0.5 - 0.62) / 0.25 < 0, a stop.
      EXPECT_FALSE(v.latch->muted) << "t " << t;
      EXPECT_EQ(std::count(v.muted_slots->begin(), v.muted_slots->end(), 1), 0) << "t " << t;
      EXPECT_EQ(v.speed_scale, 0.0) << "t " << t;
    }
  }
  EXPECT_GE(muted_within, 6);
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
