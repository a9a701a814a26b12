// TrajectoryRetimer (trajectory_relay's rule) against analytic answers: plans sampled from known
// polynomials (so the plan's own spline is that polynomial), a controller model written here
// (Hermite interpolation of each chunk, replaced at every tick), and counts of wall time.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "allocation_counter.hpp"
#include "workspace_proximity/rules/trajectory_retimer.hpp"

using workspace_proximity::ChunkKind;
using workspace_proximity::PlanRejection;
using workspace_proximity::RetimedChunk;
using workspace_proximity::TrajectoryRetimer;
using workspace_proximity::TrajectoryRetimerCapacity;

namespace {

constexpr double kHorizon = 0.3;           // ~chunk's default, s
constexpr double kHold = 0.05;             // the relay's period at 20 Hz, s
constexpr double kPathTolerance = 0.01;    // ~joint_path_tolerance's default
constexpr int kJoints = 3;

// The reference motion of joint j over planned time t in [0, 4]: a quintic per joint.
double refPos(int j, double t) {
  const double a = 0.3 + 0.2 * j, b = -0.1 * j;
  return a + b * t + 0.15 * t * t - 0.02 * (j + 1) * t * t * t + 0.001 * t * t * t * t * t;
}
double refVel(int j, double t) {
  const double b = -0.1 * j;
  return b + 0.3 * t - 0.06 * (j + 1) * t * t + 0.005 * t * t * t * t;
}
double refAcc(int j, double t) { return 0.3 - 0.12 * (j + 1) * t + 0.02 * t * t * t; }
// The cubic part only (quintic term dropped), for the cubic plan.
double cubPos(int j, double t) { return refPos(j, t) - 0.001 * std::pow(t, 5); }
double cubVel(int j, double t) { return refVel(j, t) - 0.005 * std::pow(t, 4); }

enum class Order { kLinear, kCubic, kQuintic };

// Loads a plan with points at `times`, from the cubic polynomial (kLinear, kCubic: positions, and
// velocities for kCubic) or the quintic (kQuintic: positions, velocities, accelerations).
PlanRejection loadPlan(TrajectoryRetimer& r, const std::vector<double>& times, Order order) {
  const bool vel = order != Order::kLinear, acc = order == Order::kQuintic;
  PlanRejection rej = r.beginPlan(kJoints, static_cast<int>(times.size()), vel, acc);
  if (rej != PlanRejection::kNone) return rej;
  for (std::size_t i = 0; i < times.size(); ++i) {
    double q[kJoints], dq[kJoints], ddq[kJoints];
    for (int j = 0; j < kJoints; ++j) {
      const double t = times[i];
      q[j] = order == Order::kQuintic ? refPos(j, t) : cubPos(j, t);
      dq[j] = order == Order::kQuintic ? refVel(j, t) : cubVel(j, t);
      ddq[j] = refAcc(j, t);
    }
    r.setPoint(static_cast<int>(i), times[i], q, dq, ddq);
  }
  return r.finishPlan();
}

// The controller's interpolation of one chunk at wall time t (from the chunk's start), joint j:
// linear, cubic or quintic Hermite as the chunk carries, holding the last point.
double chunkPos(const RetimedChunk& c, int j, double t) {
  const int n = c.count;
  auto P = [&](int i) { return c.positions[i * c.joints + j]; };
  auto V = [&](int i) { return c.velocities[i * c.joints + j]; };
  auto A = [&](int i) { return c.accelerations[i * c.joints + j]; };
  if (t <= c.times[0]) return P(0);
  if (t >= c.times[n - 1]) return P(n - 1);
  int i = 0;
  while (c.times[i + 1] < t) ++i;
  const double T = c.times[i + 1] - c.times[i], x = t - c.times[i];
  const double h = P(i + 1) - P(i);
  if (!c.has_velocities) return P(i) + h * x / T;
  // Monomials in x, coefficients from the textbook Hermite formulas.
  const double v0 = V(i), v1 = V(i + 1);
  if (!c.has_accelerations) {
    const double a2 = (3 * h - (2 * v0 + v1) * T) / (T * T);
    const double a3 = (-2 * h + (v0 + v1) * T) / (T * T * T);
    return P(i) + v0 * x + a2 * x * x + a3 * x * x * x;
  }
  const double a0 = A(i), a1 = A(i + 1);
  const double k3 = (20 * h - (8 * v1 + 12 * v0) * T - (3 * a0 - a1) * T * T) / (2 * std::pow(T, 3));
  const double k4 = (-30 * h + (14 * v1 + 16 * v0) * T + (3 * a0 - 2 * a1) * T * T) / (2 * std::pow(T, 4));
  const double k5 = (12 * h - 6 * (v1 + v0) * T + (a1 - a0) * T * T) / (2 * std::pow(T, 5));
  return P(i) + v0 * x + 0.5 * a0 * x * x + k3 * std::pow(x, 3) + k4 * std::pow(x, 4) +
         k5 * std::pow(x, 5);
}

// Joint-space distance from q to the reference path (cubic or quintic) over planned [0, T_end],
// by dense sampling plus refinement.
double distanceToPath(const double* q, Order order, double t_end) {
  auto at = [&](int j, double t) { return order == Order::kQuintic ? refPos(j, t) : cubPos(j, t); };
  auto dist = [&](double t) {
    double d2 = 0;
    for (int j = 0; j < kJoints; ++j) d2 += std::pow(q[j] - at(j, t), 2);
    return std::sqrt(d2);
  };
  double best = std::numeric_limits<double>::infinity(), best_t = 0;
  const int n = 4000;
  for (int k = 0; k <= n; ++k) {
    const double t = t_end * k / n;
    if (dist(t) < best) best = dist(t), best_t = t;
  }
  for (int k = -100; k <= 100; ++k) {
    const double t = std::min(t_end, std::max(0.0, best_t + k * t_end / n / 100));
    best = std::min(best, dist(t));
  }
  return best;
}

const std::vector<double> kTimes = {0.0, 0.7, 1.5, 1.6, 2.8, 4.0};

}  // namespace

// Every chunk point lies on the plan's polynomial at planned time s + scale * t, with its
// derivatives scaled; and the controller's interpolation of every chunk stays on the path.
TEST(TrajectoryRetimer, ChunksLieOnThePlannedPathAtEveryOrderAndScale) {
  for (Order order : {Order::kLinear, Order::kCubic, Order::kQuintic}) {
    for (double scale : {1.0, 0.5, 0.23}) {
      TrajectoryRetimer r(TrajectoryRetimerCapacity{}, kHorizon, kHold);
      ASSERT_EQ(loadPlan(r, kTimes, order), PlanRejection::kNone);
      double dt = 0.0;
      int ticks = 0;
      while (true) {
        const double s = r.progress() + (ticks > 0 ? scale * dt : 0.0);
        const RetimedChunk& c = r.tick(dt, scale);
        dt = 0.05;
        if (c.kind == ChunkKind::kNothing) break;
        ASSERT_EQ(c.kind, ChunkKind::kMotion);
        ASSERT_NEAR(r.progress(), s, 1e-12);
        ASSERT_GE(c.count, 2);
        EXPECT_EQ(c.times[0], 0.0);
        EXPECT_LE(c.times[c.count - 1], kHorizon + 1e-12);
        for (int i = 0; i < c.count; ++i) {
          if (i > 0) {
            EXPECT_GT(c.times[i], c.times[i - 1]);
          }
          const double sp = s + scale * c.times[i];
          for (int j = 0; j < kJoints; ++j) {
            const double q = c.positions[i * kJoints + j];
            if (order == Order::kLinear) {
              // On the straight line between the plan's neighbouring points.
              auto seg = std::upper_bound(kTimes.begin(), kTimes.end(), sp) - kTimes.begin() - 1;
              seg = std::min<long>(seg, kTimes.size() - 2);
              const double t0 = kTimes[seg], t1 = kTimes[seg + 1];
              const double expect = cubPos(j, t0) + (cubPos(j, t1) - cubPos(j, t0)) * (sp - t0) / (t1 - t0);
              EXPECT_NEAR(q, expect, 1e-9);
            } else if (order == Order::kCubic) {
              EXPECT_NEAR(q, cubPos(j, sp), 1e-9);
              EXPECT_NEAR(c.velocities[i * kJoints + j], cubVel(j, sp) * scale, 1e-9);
            } else {
              EXPECT_NEAR(q, refPos(j, sp), 1e-9);
              EXPECT_NEAR(c.velocities[i * kJoints + j], refVel(j, sp) * scale, 1e-9);
              EXPECT_NEAR(c.accelerations[i * kJoints + j], refAcc(j, sp) * scale * scale, 1e-9);
            }
          }
        }
        if (order != Order::kLinear) {
          // The controller's own interpolation of the chunk, sampled densely.
          for (int k = 0; k <= 20; ++k) {
            const double t = c.times[c.count - 1] * k / 20.0;
            double q[kJoints];
            for (int j = 0; j < kJoints; ++j) q[j] = chunkPos(c, j, t);
            EXPECT_LE(distanceToPath(q, order, kTimes.back()), kPathTolerance);
            for (int j = 0; j < kJoints; ++j) {
              const double sp = s + scale * t;
              EXPECT_NEAR(q[j], order == Order::kQuintic ? refPos(j, sp) : cubPos(j, sp), 1e-9);
            }
          }
        }
        ASSERT_LT(++ticks, 10000);
      }
      EXPECT_DOUBLE_EQ(r.progress(), kTimes.back());
    }
  }
}

// Pauses and speed changes: the plan still ends at its final point, progress never moves at
// scale 0 (after the tick that accounts for the last motion chunk), and a hold is one point at
// the progress's state with zero velocity.
TEST(TrajectoryRetimer, EndsAtTheFinalPointAfterPausesAndNeverAdvancesAtZero) {
  TrajectoryRetimer r(TrajectoryRetimerCapacity{}, kHorizon, kHold);
  ASSERT_EQ(loadPlan(r, kTimes, Order::kCubic), PlanRejection::kNone);
  const double dt = 0.05;
  int tick = 0;
  double prev_scale = 0.0;
  double last_motion_end[kJoints] = {0, 0, 0};
  int motion_chunks = 0;
  while (tick < 100000) {
    // 1 for 20 ticks, 0 for 15, 0.5 for 10, 0 for 5, then 0.8.
    const int k = tick;
    double scale = 0.8;
    if (k < 20) scale = 1.0;
    else if (k < 35) scale = 0.0;
    else if (k < 45) scale = 0.5;
    else if (k < 50) scale = 0.0;
    const double before = r.progress();
    const RetimedChunk& c = r.tick(tick == 0 ? 0.0 : dt, scale);
    ++tick;
    if (c.kind == ChunkKind::kNothing) break;
    if (prev_scale == 0.0 && scale == 0.0) {
      EXPECT_EQ(r.progress(), before) << "tick " << tick;
    }
    if (scale == 0.0) {
      ASSERT_EQ(c.kind, ChunkKind::kHold);
      ASSERT_EQ(c.count, 1);
      EXPECT_EQ(c.times[0], kHold);
      for (int j = 0; j < kJoints; ++j) {
        EXPECT_NEAR(c.positions[j], cubPos(j, r.progress()), 1e-9);
        EXPECT_EQ(c.velocities[j], 0.0);
      }
    } else {
      ASSERT_EQ(c.kind, ChunkKind::kMotion);
      ++motion_chunks;
      for (int j = 0; j < kJoints; ++j) {
        last_motion_end[j] = c.positions[(c.count - 1) * kJoints + j];
      }
    }
    prev_scale = scale;
  }
  EXPECT_GT(motion_chunks, 0);
  EXPECT_DOUBLE_EQ(r.progress(), kTimes.back());
  EXPECT_TRUE(r.finished());
  for (int j = 0; j < kJoints; ++j) EXPECT_NEAR(last_motion_end[j], cubPos(j, kTimes.back()), 1e-12);
  // Planned 4 s: 20 ticks at 1 (1 s), 10 at 0.5 (0.25 s), the remaining 2.75 s at 0.8.
  const double expect_ticks = 50 + std::ceil(2.75 / 0.8 / dt) + 1;
  EXPECT_NEAR(tick, expect_ticks, 1.0);
}

// Wall time to the end: T / scale, to within a tick.
TEST(TrajectoryRetimer, HalfScaleTakesTwiceAsLong) {
  auto wall_time = [](double scale) {
    TrajectoryRetimer r(TrajectoryRetimerCapacity{}, kHorizon, kHold);
    EXPECT_EQ(loadPlan(r, kTimes, Order::kQuintic), PlanRejection::kNone);
    const double dt = 0.01;
    double t = 0.0;
    r.tick(0.0, scale);
    while (r.tick(dt, scale).kind != ChunkKind::kNothing) t += dt;
    return t + dt;  // the tick that found the end accounts for the last dt
  };
  const double full = wall_time(1.0), half = wall_time(0.5);
  EXPECT_NEAR(full, kTimes.back(), 0.011);
  EXPECT_NEAR(half, 2.0 * kTimes.back(), 0.011);
}

// A new plan replaces the old: progress from 0, the first chunk starts at its first point.
TEST(TrajectoryRetimer, NewPlanReplacesTheOld) {
  TrajectoryRetimer r(TrajectoryRetimerCapacity{}, kHorizon, kHold);
  ASSERT_EQ(loadPlan(r, kTimes, Order::kCubic), PlanRejection::kNone);
  r.tick(0.0, 1.0);
  for (int i = 0; i < 10; ++i) r.tick(0.05, 1.0);
  EXPECT_NEAR(r.progress(), 0.5, 1e-12);
  ASSERT_EQ(loadPlan(r, {0.0, 2.0}, Order::kQuintic), PlanRejection::kNone);
  EXPECT_EQ(r.progress(), 0.0);
  const RetimedChunk& c = r.tick(0.05, 1.0);  // the old chunk's time is not the new plan's
  EXPECT_EQ(r.progress(), 0.0);
  for (int j = 0; j < kJoints; ++j) EXPECT_NEAR(c.positions[j], refPos(j, 0.0), 1e-12);
  EXPECT_DOUBLE_EQ(r.duration(), 2.0);
}

// Every bad plan is refused by name and the plan in force stays.
TEST(TrajectoryRetimer, BadPlansAreRefusedAndTheOldOneStays) {
  TrajectoryRetimerCapacity cap;
  cap.max_joints = 4;
  cap.max_points = 8;
  TrajectoryRetimer r(cap, kHorizon, kHold);
  ASSERT_EQ(loadPlan(r, {0.0, 1.0, 2.0}, Order::kCubic), PlanRejection::kNone);
  EXPECT_EQ(r.beginPlan(0, 3, false, false), PlanRejection::kNoJoints);
  EXPECT_EQ(r.beginPlan(5, 3, false, false), PlanRejection::kTooManyJoints);
  EXPECT_EQ(r.beginPlan(3, 0, false, false), PlanRejection::kNoPoints);
  EXPECT_EQ(r.beginPlan(3, 9, false, false), PlanRejection::kTooManyPoints);
  EXPECT_EQ(loadPlan(r, {0.5, 1.0}, Order::kCubic), PlanRejection::kFirstTimeNotZero);
  EXPECT_EQ(loadPlan(r, {0.0, 1.0, 1.0}, Order::kCubic), PlanRejection::kTimesNotIncreasing);
  EXPECT_EQ(loadPlan(r, {0.0, 1.0, std::nan("")}, Order::kCubic), PlanRejection::kNotFinite);
  ASSERT_EQ(r.beginPlan(3, 2, false, false), PlanRejection::kNone);
  const double bad[3] = {0.0, std::numeric_limits<double>::infinity(), 0.0};
  r.setPoint(0, 0.0, bad, nullptr, nullptr);
  r.setPoint(1, 1.0, bad, nullptr, nullptr);
  EXPECT_EQ(r.finishPlan(), PlanRejection::kNotFinite);
  EXPECT_STRNE(workspace_proximity::planRejectionName(PlanRejection::kNotFinite), "unknown");
  // The first plan is still in force.
  EXPECT_DOUBLE_EQ(r.duration(), 2.0);
  EXPECT_EQ(r.tick(0.0, 1.0).kind, ChunkKind::kMotion);
  // NaN scale counts as 0: a hold.
  EXPECT_EQ(r.tick(0.05, std::nan("")).kind, ChunkKind::kHold);
}

// Once a plan is loaded, neither ticks nor loading the next plan allocate.
TEST(TrajectoryRetimer, NoAllocationPerTick) {
  TrajectoryRetimer r(TrajectoryRetimerCapacity{}, kHorizon, kHold);
  ASSERT_EQ(loadPlan(r, kTimes, Order::kQuintic), PlanRejection::kNone);
  const long before = wp_test::allocationCount();
  r.tick(0.0, 1.0);
  for (int i = 0; i < 200; ++i) r.tick(0.02, (i / 20) % 2 == 0 ? 0.7 : 0.0);
  const double q[kJoints] = {0, 0, 0};
  r.beginPlan(kJoints, 2, false, false);
  r.setPoint(0, 0.0, q, nullptr, nullptr);
  r.setPoint(1, 1.0, q, nullptr, nullptr);
  EXPECT_EQ(r.finishPlan(), PlanRejection::kNone);
  r.tick(0.0, 1.0);
  EXPECT_EQ(wp_test::allocationCount(), before);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
