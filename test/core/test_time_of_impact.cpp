// Tests of axisContactInterval / boxContactInterval against analytic answers and against a
// brute-force oracle (dense time sampling + bisection on the closed-interval overlap predicate).

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "workspace_proximity/time_of_impact.hpp"

using workspace_proximity::axisContactInterval;
using workspace_proximity::boxContactInterval;
using workspace_proximity::TimeInterval;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Closed 1-D overlap of [lo_a + v_a t, hi_a + v_a t] and [lo_b + v_b t, hi_b + v_b t].
bool axisOverlapAt(double lo_a, double hi_a, double v_a, double lo_b, double hi_b, double v_b,
                   double t) {
  return lo_a + v_a * t <= hi_b + v_b * t && lo_b + v_b * t <= hi_a + v_a * t;
}

// Same with slack: true when the intervals are within `slack` of touching.
bool axisNearOverlapAt(double lo_a, double hi_a, double v_a, double lo_b, double hi_b,
                       double v_b, double t, double slack) {
  return lo_a + v_a * t <= hi_b + v_b * t + slack && lo_b + v_b * t <= hi_a + v_a * t + slack;
}

struct Box3 {
  Eigen::Vector3d c, h, v;
};

bool boxOverlapAt(const Box3& a, const Box3& b, double t, double slack = 0.0) {
  for (int k = 0; k < 3; ++k) {
    if (!axisNearOverlapAt(a.c[k] - a.h[k], a.c[k] + a.h[k], a.v[k], b.c[k] - b.h[k],
                           b.c[k] + b.h[k], b.v[k], t, slack))
      return false;
  }
  return true;
}

// Allowed distance of a returned end from the exact end: the 1e-12 s of the spec plus a few
// ulps of rounding (the implementation may pad by up to that much; it must never shrink).
double endTolerance(double t) {
  return 1e-12 + 16.0 * std::numeric_limits<double>::epsilon() * std::abs(t);
}

// Checks that `got` encloses the exact [first, last] and is at most endTolerance wider.
void expectEnclosesExactly(const TimeInterval& got, double first, double last) {
  ASSERT_FALSE(got.empty());
  EXPECT_LE(got.first, first);
  EXPECT_GE(got.last, last);
  EXPECT_NEAR(got.first, first, endTolerance(first));
  EXPECT_NEAR(got.last, last, endTolerance(last));
}

// Clips an interval to [0, h]; the result may be empty.
TimeInterval clip(TimeInterval in, double h) {
  return TimeInterval{std::max(in.first, 0.0), std::min(in.last, h)};
}

// Oracle for the exact contact set {t in [0, H] : overlap(t)} (an interval, as the
// constraints are linear in t). Samples a grid, then refines both ends by bisection.
// Returns empty when no grid point overlaps; `grid_dt` receives the grid spacing.
template <class Pred>
TimeInterval bruteForceInterval(const Pred& overlap, double horizon, int steps) {
  int first = -1, last = -1;
  for (int i = 0; i <= steps; ++i) {
    double t = horizon * i / steps;
    if (overlap(t)) {
      if (first < 0) first = i;
      last = i;
    }
  }
  if (first < 0) return TimeInterval{1.0, 0.0};
  auto grid = [&](int i) { return horizon * i / steps; };
  double lo = grid(first), hi = grid(last);
  if (first > 0) {  // refine the start: overlap false at a, true at b
    double a = grid(first - 1), b = lo;
    for (int it = 0; it < 200 && b - a > 0; ++it) {
      double m = 0.5 * (a + b);
      if (m <= a || m >= b) break;
      (overlap(m) ? b : a) = m;
    }
    lo = b;
  }
  if (last < steps) {  // refine the end: overlap true at a, false at b
    double a = hi, b = grid(last + 1);
    for (int it = 0; it < 200 && b - a > 0; ++it) {
      double m = 0.5 * (a + b);
      if (m <= a || m >= b) break;
      (overlap(m) ? a : b) = m;
    }
    hi = a;
  }
  return TimeInterval{lo, hi};
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// The lecture's worked example (analytic): A centred (1,1), width 2, velocity (4,3);
// B centred (4,2), width 2, velocity (-1,0).
// x: A = [0,2], B = [3,5], relative velocity 5 -> first contact (3-2)/5 = 1/5, last (5-0)/5 = 1.
// y: A = [0,2], B = [1,3], relative velocity 3 -> first (1-2)/3 = -1/3, last (3-0)/3 = 1.
TEST(TimeOfImpactLecture, XAxisFirstAndLastContact) {
  TimeInterval x = axisContactInterval(0.0, 2.0, 4.0, 3.0, 5.0, -1.0);
  expectEnclosesExactly(x, 0.2, 1.0);
  EXPECT_FALSE(x.empty());
}

TEST(TimeOfImpactLecture, YAxisInterval) {
  TimeInterval y = axisContactInterval(0.0, 2.0, 3.0, 1.0, 3.0, 0.0);
  expectEnclosesExactly(y, -1.0 / 3.0, 1.0);
}

TEST(TimeOfImpactLecture, CombinedBoxIntervalHorizonOne) {
  // z is shared and static, so the combined interval is x ∩ y ∩ [0, 1] = [1/5, 1].
  TimeInterval c = boxContactInterval({1, 1, 0}, {1, 1, 1}, {4, 3, 0}, {4, 2, 0}, {1, 1, 1},
                                      {-1, 0, 0}, 1.0);
  ASSERT_FALSE(c.empty());
  expectEnclosesExactly(c, 0.2, 1.0);
  // A shorter horizon clips the end: [1/5, 1/2].
  TimeInterval h = boxContactInterval({1, 1, 0}, {1, 1, 1}, {4, 3, 0}, {4, 2, 0}, {1, 1, 1},
                                      {-1, 0, 0}, 0.5);
  ASSERT_FALSE(h.empty());
  expectEnclosesExactly(h, 0.2, 0.5);
  // A horizon before first contact: empty.
  EXPECT_TRUE(boxContactInterval({1, 1, 0}, {1, 1, 1}, {4, 3, 0}, {4, 2, 0}, {1, 1, 1},
                                 {-1, 0, 0}, 0.19)
                  .empty());
}

// ---------------------------------------------------------------------------------------------
// Analytic 1-D cases.

TEST(AxisContactInterval, AlreadyOverlappingContainsZero) {
  // A = [0,2] moving +1, B = [1,3] static: overlap for t in [-1, 3].
  TimeInterval r = axisContactInterval(0.0, 2.0, 1.0, 1.0, 3.0, 0.0);
  expectEnclosesExactly(r, -1.0, 3.0);
  EXPECT_LE(r.first, 0.0);
  EXPECT_GE(r.last, 0.0);
}

TEST(AxisContactInterval, ZeroRelativeVelocityOverlappingIsUnbounded) {
  TimeInterval r = axisContactInterval(0.0, 2.0, 0.7, 1.0, 3.0, 0.7);
  EXPECT_EQ(r.first, -kInf);
  EXPECT_EQ(r.last, kInf);
  // Both static and merely touching: still always in contact (closed intervals).
  TimeInterval t = axisContactInterval(0.0, 1.0, 0.0, 1.0, 2.0, 0.0);
  EXPECT_EQ(t.first, -kInf);
  EXPECT_EQ(t.last, kInf);
  // Clipped by the box version to [0, H].
  TimeInterval b = boxContactInterval({0, 0, 0}, {1, 1, 1}, {2, 0, 0}, {1.5, 0, 0}, {1, 1, 1},
                                      {2, 0, 0}, 3.0);
  ASSERT_FALSE(b.empty());
  EXPECT_EQ(b.first, 0.0);
  EXPECT_EQ(b.last, 3.0);
}

TEST(AxisContactInterval, ZeroRelativeVelocitySeparatedIsEmpty) {
  EXPECT_TRUE(axisContactInterval(0.0, 1.0, 0.0, 1.5, 2.0, 0.0).empty());
  EXPECT_TRUE(axisContactInterval(0.0, 1.0, -3.0, -2.0, -1e-9, -3.0).empty());
  EXPECT_TRUE(boxContactInterval({0, 0, 0}, {1, 1, 1}, {1, 1, 1}, {0, 0, 2.5}, {1, 1, 1},
                                 {1, 1, 1}, 10.0)
                  .empty());
}

TEST(AxisContactInterval, SeparatingMotionIsInThePast) {
  // A = [0,1] moving -1 away from B = [2,3]: contact only for t in [-3, -1].
  TimeInterval r = axisContactInterval(0.0, 1.0, -1.0, 2.0, 3.0, 0.0);
  expectEnclosesExactly(r, -3.0, -1.0);
  EXPECT_TRUE(boxContactInterval({0.5, 0, 0}, {0.5, 1, 1}, {-1, 0, 0}, {2.5, 0, 0},
                                 {0.5, 1, 1}, {0, 0, 0}, 100.0)
                  .empty());
}

TEST(AxisContactInterval, ApproachFromEitherSide) {
  // A left of B moving right at 2: gap 2 closes at t=1, A passes B's far side at t=(3+1-0)/2.
  TimeInterval l = axisContactInterval(0.0, 1.0, 2.0, 3.0, 4.0, 0.0);
  expectEnclosesExactly(l, 1.0, 2.0);
  // Mirror image: A right of B moving left at 2.
  TimeInterval r = axisContactInterval(3.0, 4.0, -2.0, 0.0, 1.0, 0.0);
  expectEnclosesExactly(r, 1.0, 2.0);
  // B doing the moving instead of A gives the same times.
  TimeInterval b = axisContactInterval(3.0, 4.0, 0.0, 0.0, 1.0, 2.0);
  expectEnclosesExactly(b, 1.0, 2.0);
  // Both moving, relative speed 4.
  TimeInterval m = axisContactInterval(0.0, 1.0, 1.0, 3.0, 4.0, -3.0);
  expectEnclosesExactly(m, 0.5, 1.0);
}

TEST(AxisContactInterval, TouchingExactlyAtOneInstant) {
  // Two points: A = {0} moving +1, B = {2} static meet only at t = 2.
  TimeInterval p = axisContactInterval(0.0, 0.0, 1.0, 2.0, 2.0, 0.0);
  ASSERT_FALSE(p.empty());
  EXPECT_LE(p.first, 2.0);
  EXPECT_GE(p.last, 2.0);
  EXPECT_LE(p.last - p.first, 2.0 * endTolerance(2.0));
  // Boxes touching at t = 0 and separating: interval ends exactly at 0 (closed).
  TimeInterval s = axisContactInterval(0.0, 1.0, -1.0, 1.0, 2.0, 0.0);
  ASSERT_FALSE(s.empty());
  EXPECT_GE(s.last, 0.0);
  EXPECT_LE(s.last, endTolerance(0.0));
  TimeInterval sb = boxContactInterval({0.5, 0, 0}, {0.5, 1, 1}, {-1, 0, 0}, {1.5, 0, 0},
                                       {0.5, 1, 1}, {0, 0, 0}, 5.0);
  ASSERT_FALSE(sb.empty());
  EXPECT_EQ(sb.first, 0.0);
  EXPECT_LE(sb.last, endTolerance(0.0));
  // First touch exactly at the horizon counts; just past it does not.
  TimeInterval h = boxContactInterval({0, 0, 0}, {1, 1, 1}, {1, 0, 0}, {4, 0, 0}, {1, 1, 1},
                                      {0, 0, 0}, 2.0);
  ASSERT_FALSE(h.empty());
  expectEnclosesExactly(h, 2.0, 2.0);
  EXPECT_TRUE(boxContactInterval({0, 0, 0}, {1, 1, 1}, {1, 0, 0}, {4, 0, 0}, {1, 1, 1},
                                 {0, 0, 0}, 1.9)
                  .empty());
}

TEST(BoxContactInterval, ZeroHorizon) {
  // Overlapping now: [0, 0]. Not overlapping now: empty, however fast they approach.
  TimeInterval a = boxContactInterval({0, 0, 0}, {1, 1, 1}, {5, 0, 0}, {1, 1, 1}, {1, 1, 1},
                                      {0, 0, 0}, 0.0);
  ASSERT_FALSE(a.empty());
  EXPECT_EQ(a.first, 0.0);
  EXPECT_EQ(a.last, 0.0);
  EXPECT_TRUE(boxContactInterval({0, 0, 0}, {1, 1, 1}, {50, 0, 0}, {2.5, 0, 0}, {1, 1, 1},
                                 {0, 0, 0}, 0.0)
                  .empty());
}

TEST(BoxContactInterval, AxesMustOverlapSimultaneously) {
  // x overlaps during [1, 2] and y during [2.5, 4.5]: never all at once.
  TimeInterval r = boxContactInterval({0, 0, 0}, {0.5, 0.5, 1}, {2, 1, 0}, {3, 3.5, 0},
                                      {0.5, 0.5, 1}, {0, 0, 0}, 10.0);
  EXPECT_TRUE(r.empty());
}

// ---------------------------------------------------------------------------------------------
// Brute force on random cases: every sampled t with contact lies inside the returned
// interval (conservative), and the ends match the bisected true ends within 1e-9.

// The draws of the random brute-force cases.
struct Draws {
  explicit Draws(unsigned seed) : rng(seed) {}
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
  bool oneInTen() { return std::uniform_int_distribution<int>(0, 9)(rng) == 0; }
  std::mt19937_64 rng;
};

// Conservative: every instant of [0, h] sampled `steps` times at which `overlaps` holds lies
// inside `got`.
template <class Overlaps>
void expectSampledContactsInside(const TimeInterval& got, double h, int steps, Overlaps overlaps) {
  for (int i = 0; i <= steps; ++i) {
    const double t = h * i / steps;
    if (overlaps(t)) {
      ASSERT_FALSE(got.empty()) << "contact at t=" << t;
      ASSERT_LE(got.first, t);
      ASSERT_GE(got.last, t);
    }
  }
}

TEST(AxisContactInterval, MatchesBruteForceOnRandomCases) {
  Draws draw(12345);
  const int kSteps = 2000;
  for (int trial = 0; trial < 3000; ++trial) {
    double lo_a = draw.uniform(-10, 10), hi_a = lo_a + (draw.oneInTen() ? 0.0 : draw.uniform(0, 4));
    double lo_b = draw.uniform(-10, 10), hi_b = lo_b + (draw.oneInTen() ? 0.0 : draw.uniform(0, 4));
    double v_a = draw.uniform(-5, 5), v_b = draw.oneInTen() ? v_a : draw.uniform(-5, 5);
    double h = draw.uniform(0.1, 5);
    SCOPED_TRACE(testing::Message() << "trial " << trial << " A=[" << lo_a << "," << hi_a
                                    << "] va=" << v_a << " B=[" << lo_b << "," << hi_b
                                    << "] vb=" << v_b << " H=" << h);
    TimeInterval got = axisContactInterval(lo_a, hi_a, v_a, lo_b, hi_b, v_b);
    auto pred = [&](double t) { return axisOverlapAt(lo_a, hi_a, v_a, lo_b, hi_b, v_b, t); };
    ASSERT_NO_FATAL_FAILURE(expectSampledContactsInside(got, h, kSteps, pred));
    // Tight: clipped ends equal the true ends. Rounding of the predicate near a transition
    // blurs the true end by ~eps * |coordinate| / |relative velocity|.
    double dv = std::abs(v_a - v_b);
    double tol = 1e-9 + (dv > 0 ? 1e-13 * 20.0 / dv : 0.0);
    TimeInterval truth = bruteForceInterval(pred, h, kSteps);
    TimeInterval clipped = clip(got, h);
    if (truth.empty()) {
      // Only a contact shorter than one grid step can hide between samples.
      if (!clipped.empty()) {
        EXPECT_LT(clipped.last - clipped.first, h / kSteps + tol);
        double mid = 0.5 * (clipped.first + clipped.last);
        EXPECT_TRUE(axisNearOverlapAt(lo_a, hi_a, v_a, lo_b, hi_b, v_b, mid, 1e-9));
      }
    } else {
      ASSERT_FALSE(clipped.empty());
      EXPECT_NEAR(clipped.first, truth.first, tol);
      EXPECT_NEAR(clipped.last, truth.last, tol);
    }
  }
}

// Exact-arithmetic oracle: with double inputs, the true interval ends are quotients of exact
// differences. binary128 holds those differences exactly and rounds the quotient ~1e-34
// relative, so the returned (double) interval must enclose the binary128 interval: rounding
// may widen the answer, never shrink it.
TEST(AxisContactInterval, EnclosesExactIntervalFromQuadPrecision) {
  using Quad = __float128;
  std::mt19937_64 rng(4711);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), len(0.0, 1.0);
  std::uniform_int_distribution<int> scale_exp(-3, 4);
  int checked = 0;
  for (int trial = 0; trial < 200000; ++trial) {
    double s = std::pow(10.0, scale_exp(rng)), vs = std::pow(10.0, scale_exp(rng));
    double lo_a = s * unit(rng), hi_a = lo_a + s * len(rng);
    double lo_b = s * unit(rng), hi_b = lo_b + s * len(rng);
    double v_a = vs * unit(rng), v_b = vs * unit(rng);
    TimeInterval got = axisContactInterval(lo_a, hi_a, v_a, lo_b, hi_b, v_b);
    Quad dv = Quad(v_a) - Quad(v_b);
    if (dv == 0) continue;
    Quad behind = Quad(lo_b) - Quad(hi_a), ahead = Quad(hi_b) - Quad(lo_a);
    Quad first = (dv > 0 ? behind : ahead) / dv, last = (dv > 0 ? ahead : behind) / dv;
    ++checked;
    ASSERT_FALSE(got.empty()) << "trial " << trial;
    ASSERT_TRUE(Quad(got.first) <= first)
        << "trial " << trial << std::hexfloat << " first " << got.first << " exact "
        << static_cast<double>(first) << " inputs " << lo_a << " " << hi_a << " " << v_a << " "
        << lo_b << " " << hi_b << " " << v_b;
    ASSERT_TRUE(Quad(got.last) >= last)
        << "trial " << trial << std::hexfloat << " last " << got.last << " exact "
        << static_cast<double>(last) << " inputs " << lo_a << " " << hi_a << " " << v_a << " "
        << lo_b << " " << hi_b << " " << v_b;
  }
  EXPECT_GT(checked, 190000);
}

TEST(BoxContactInterval, MatchesBruteForceOnRandomCases) {
  Draws draw(777);
  const int kSteps = 2000;
  int nonempty = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    Box3 a, b;
    for (int k = 0; k < 3; ++k) {
      a.c[k] = draw.uniform(-4, 4);
      b.c[k] = draw.uniform(-4, 4);
      a.h[k] = draw.oneInTen() ? 0.0 : draw.uniform(0, 2);
      b.h[k] = draw.uniform(0, 2);
      a.v[k] = draw.uniform(-4, 4);
      b.v[k] = draw.oneInTen() ? a.v[k] : draw.uniform(-4, 4);
    }
    double h = draw.uniform(0.05, 4);
    SCOPED_TRACE(testing::Message() << "trial " << trial);
    TimeInterval got = boxContactInterval(a.c, a.h, a.v, b.c, b.h, b.v, h);
    // The box version is already clipped to [0, H].
    if (!got.empty()) {
      EXPECT_GE(got.first, 0.0);
      EXPECT_LE(got.last, h);
    }
    auto pred = [&](double t) { return boxOverlapAt(a, b, t); };
    ASSERT_NO_FATAL_FAILURE(expectSampledContactsInside(got, h, kSteps, pred));
    double min_dv = kInf;
    for (int k = 0; k < 3; ++k) {
      double dv = std::abs(a.v[k] - b.v[k]);
      if (dv > 0) min_dv = std::min(min_dv, dv);
    }
    double tol = 1e-9 + (std::isfinite(min_dv) ? 1e-13 * 20.0 / min_dv : 0.0);
    TimeInterval truth = bruteForceInterval(pred, h, kSteps);
    if (truth.empty()) {
      if (!got.empty()) {
        EXPECT_LT(got.last - got.first, h / kSteps + tol);
        EXPECT_TRUE(boxOverlapAt(a, b, 0.5 * (got.first + got.last), 1e-9));
      }
    } else {
      ++nonempty;
      ASSERT_FALSE(got.empty());
      EXPECT_NEAR(got.first, truth.first, tol);
      EXPECT_NEAR(got.last, truth.last, tol);
    }
  }
  // The generator must actually exercise contacts.
  EXPECT_GT(nonempty, 300);
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
