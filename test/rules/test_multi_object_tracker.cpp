// The multi-object tracker (rules/multi_object_tracker.hpp) against analytic scenes and
// independent oracles:
// - the assignment against brute force over every injection of small random gated matrices;
// - the filter against a textbook 6-state Kalman filter written out with Eigen matrices (F, Q,
//   H, R), and its steady state against the closed form of the alpha-beta filter for the
//   discrete white-noise-acceleration model (Kalata's tracking index);
// - two crossing targets keep their ids, a gate that a greedy assignment would lose, far
//   detections gated out, a target that leaves dropped after K frames, velocity unknown until
//   its 3 sigma error is below the bound, no allocation after warm-up.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "allocation_counter.hpp"  // test/shared
#include "random.hpp"              // test/shared
#include "workspace_proximity/rules/multi_object_tracker.hpp"

namespace wp = workspace_proximity;

namespace {

constexpr wp::Stamp kT0 = 1000000000000LL;

wp::Stamp at(double seconds) { return kT0 + wp::nanoseconds(seconds); }

wp::TrackerParams params() {
  wp::TrackerParams p;
  p.labels = {wp::TrackerLabel{"person", 3.0, 2.0}, wp::TrackerLabel{"unknown", 3.0, 2.0}};
  return p;
}

wp::Detection detection(const Eigen::Vector3d& position, double sigma = 0.05, int label = 0) {
  wp::Detection d;
  d.position = position;
  d.dimensions = {0.5, 0.5, 1.8};
  d.sigma = sigma;
  d.label = label;
  return d;
}

// The output track with this id, or nullptr.
const wp::BoxObservation* trackWithId(const wp::MultiObjectTracker& t, const std::string& id) {
  for (const wp::BoxObservation& b : t.tracks()) {
    if (b.id == id) return &b;
  }
  return nullptr;
}

// Brute force: the largest number of gated pairs, then the least total cost, over every
// injection of the smaller side into the larger.
struct Best {
  int pairs = -1;
  double cost = 0.0;
};
void bruteForce(const std::vector<double>& c, int rows, int cols, double gated_out, int r,
                std::vector<int>& used, int pairs, double cost, Best* best) {
  if (r == rows) {
    if (pairs > best->pairs || (pairs == best->pairs && cost < best->cost - 1e-12)) {
      best->pairs = pairs;
      best->cost = cost;
    }
    return;
  }
  // Row r unmatched (only allowed when there are more rows than columns) or matched to a free
  // column; a gated-out match counts as unmatched.
  if (rows > cols) bruteForce(c, rows, cols, gated_out, r + 1, used, pairs, cost, best);
  for (int j = 0; j < cols; ++j) {
    if (used[static_cast<std::size_t>(j)]) continue;
    used[static_cast<std::size_t>(j)] = 1;
    const double x = c[static_cast<std::size_t>(r * cols + j)];
    if (x < gated_out) {
      bruteForce(c, rows, cols, gated_out, r + 1, used, pairs + 1, cost + x, best);
    } else {
      bruteForce(c, rows, cols, gated_out, r + 1, used, pairs, cost, best);
    }
    used[static_cast<std::size_t>(j)] = 0;
  }
}

// Kalata's closed form for the steady state of the alpha-beta filter of the discrete
// white-noise-acceleration model: tracking index lambda = sigma_a T^2 / sigma_m,
// r = (4 + lambda - sqrt(8 lambda + lambda^2)) / 4, alpha = 1 - r^2, beta = 2 (1 - r)^2, and
// the updated covariance P_pp = alpha s^2, P_pv = beta s^2 / T,
// P_vv = beta (alpha - beta / 2) / (1 - alpha) s^2 / T^2 (s = sigma_m).
struct SteadyState {
  double p_pp, p_pv, p_vv;
};
SteadyState kalata(double sigma_a, double sigma_m, double T) {
  const double lambda = sigma_a * T * T / sigma_m;
  const double r = (4.0 + lambda - std::sqrt(8.0 * lambda + lambda * lambda)) / 4.0;
  const double alpha = 1.0 - r * r;
  const double beta = 2.0 * (1.0 - r) * (1.0 - r);
  const double s2 = sigma_m * sigma_m;
  return {alpha * s2, beta * s2 / T, beta * (alpha - beta / 2.0) / (1.0 - alpha) * s2 / (T * T)};
}

// A textbook Kalman filter on the full state (x, y, z, vx, vy, vz), no shortcuts.
struct FullKalman {
  Eigen::Matrix<double, 6, 1> x = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<double, 6, 6> P = Eigen::Matrix<double, 6, 6>::Zero();
  void start(const Eigen::Vector3d& z, double sigma_m, double sigma_v0) {
    x.head<3>() = z;
    x.tail<3>().setZero();
    P.setZero();
    P.topLeftCorner<3, 3>() = sigma_m * sigma_m * Eigen::Matrix3d::Identity();
    P.bottomRightCorner<3, 3>() = sigma_v0 * sigma_v0 * Eigen::Matrix3d::Identity();
  }
  void step(double T, double sigma_a, const Eigen::Vector3d& z, double sigma_m) {
    Eigen::Matrix<double, 6, 6> F = Eigen::Matrix<double, 6, 6>::Identity();
    F.topRightCorner<3, 3>() = T * Eigen::Matrix3d::Identity();
    Eigen::Matrix<double, 6, 3> G;
    G.topRows<3>() = 0.5 * T * T * Eigen::Matrix3d::Identity();
    G.bottomRows<3>() = T * Eigen::Matrix3d::Identity();
    const Eigen::Matrix<double, 6, 6> Q = sigma_a * sigma_a * G * G.transpose();
    x = F * x;
    P = F * P * F.transpose() + Q;
    Eigen::Matrix<double, 3, 6> H = Eigen::Matrix<double, 3, 6>::Zero();
    H.leftCols<3>() = Eigen::Matrix3d::Identity();
    const Eigen::Matrix3d S = H * P * H.transpose() + sigma_m * sigma_m * Eigen::Matrix3d::Identity();
    const Eigen::Matrix<double, 6, 3> K = P * H.transpose() * S.inverse();
    x += K * (z - H * x);
    P = (Eigen::Matrix<double, 6, 6>::Identity() - K * H) * P;
  }
};

}  // namespace

TEST(OptimalAssignment, MatchesBruteForceOnRandomGatedMatrices) {
  wp_test::Rng rng(23);
  wp::OptimalAssignment solver(8);
  for (int trial = 0; trial < 400; ++trial) {
    const int rows = rng.integer(1, 6), cols = rng.integer(1, 6);
    const double gate = 9.0;
    const double gated_out = gate * (std::min(rows, cols) + 1) + 1.0;
    std::vector<double> c(static_cast<std::size_t>(rows * cols));
    for (double& x : c) x = rng.uniform(0.0, 1.0) < 0.4 ? gated_out : rng.uniform(0.0, gate);
    std::vector<int> match(static_cast<std::size_t>(rows));
    solver.solve(c.data(), rows, cols, match.data());
    int pairs = 0;
    double cost = 0.0;
    std::vector<int> seen(static_cast<std::size_t>(cols), 0);
    for (int r = 0; r < rows; ++r) {
      const int j = match[static_cast<std::size_t>(r)];
      if (j < 0) continue;
      ASSERT_LT(j, cols);
      ASSERT_EQ(seen[static_cast<std::size_t>(j)]++, 0) << "a column used twice";
      const double x = c[static_cast<std::size_t>(r * cols + j)];
      if (x < gated_out) {
        ++pairs;
        cost += x;
      }
    }
    Best best;
    std::vector<int> used(static_cast<std::size_t>(cols), 0);
    bruteForce(c, rows, cols, gated_out, 0, used, 0, 0.0, &best);
    EXPECT_EQ(pairs, best.pairs) << "trial " << trial;
    EXPECT_NEAR(cost, best.cost, 1e-9) << "trial " << trial;
  }
}

TEST(MultiObjectTracker, TheFilterIsTheTextbookKalmanFilterAndReachesItsSteadyState) {
  // One target at constant velocity, measured every 50 ms with noise sigma_m = 0.05 m.
  const double T = 0.05, sigma_m = 0.05, sigma_a = 3.0 / 3.0;  // max_accel 3 as 3 sigma
  wp::TrackerParams p = params();
  p.confirm_hits = 1;
  wp::MultiObjectTracker tracker(p);
  FullKalman oracle;
  wp_test::Rng rng(7);
  const Eigen::Vector3d v(1.0, -0.5, 0.2), x0(-3.0, 1.0, 0.9);
  double sum_sq_velocity = 0.0;
  int samples = 0, within = 0;
  for (int k = 0; k < 600; ++k) {
    const double t = k * T;
    const Eigen::Vector3d noise(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    // Uniform noise of variance sigma_m^2 (half-width sqrt(3) sigma_m): the filter's numbers
    // do not depend on the noise's law, only its estimates do.
    const Eigen::Vector3d z = x0 + v * t + std::sqrt(3.0) * sigma_m * noise;
    ASSERT_TRUE(tracker.update(at(t), {detection(z, sigma_m)}));
    if (k == 0) {
      oracle.start(z, sigma_m, 2.0);
    } else {
      oracle.step(T, sigma_a, z, sigma_m);
    }
    ASSERT_EQ(tracker.tracks().size(), 1u);
    const wp::BoxObservation& b = tracker.tracks()[0];
    EXPECT_EQ(b.id, "t1");
    // Same estimate and covariance as the full filter, to rounding.
    EXPECT_LT((b.position - oracle.x.head<3>()).norm(), 1e-9) << "k " << k;
    EXPECT_LT((b.linear_velocity - oracle.x.tail<3>()).norm(), 1e-9) << "k " << k;
    EXPECT_NEAR(b.position_error, 3.0 * std::sqrt(oracle.P(0, 0)), 1e-9) << "k " << k;
    EXPECT_NEAR(b.velocity_error, 3.0 * std::sqrt(oracle.P(3, 3)), 1e-9) << "k " << k;
    if (k >= 100) {  // converged
      const Eigen::Vector3d error = b.linear_velocity - v;
      sum_sq_velocity += error.squaredNorm() / 3.0;
      ++samples;
      if ((error.cwiseAbs().array() <= b.velocity_error).all()) ++within;
    }
  }
  // The steady state in closed form.
  const SteadyState ss = kalata(sigma_a, sigma_m, T);
  const wp::BoxObservation& b = tracker.tracks()[0];
  EXPECT_NEAR(b.position_error, 3.0 * std::sqrt(ss.p_pp), 1e-9);
  EXPECT_NEAR(b.velocity_error, 3.0 * std::sqrt(ss.p_vv), 1e-9);
  EXPECT_NEAR(oracle.P(0, 3), ss.p_pv, 1e-9);
  // The estimates' errors as the covariance says (white noise: the filter is consistent up to
  // the model's process noise, which overstates a target without acceleration): RMS per axis
  // at most sqrt(P_vv), and every component within 3 sigma in nearly every frame.
  EXPECT_LE(std::sqrt(sum_sq_velocity / samples), std::sqrt(ss.p_vv));
  EXPECT_GE(within, samples * 99 / 100);
  EXPECT_TRUE(b.velocity_known);
}

TEST(MultiObjectTracker, NoiseFreeConstantVelocityConvergesToTheVelocity) {
  wp::TrackerParams p = params();
  wp::MultiObjectTracker tracker(p);
  const Eigen::Vector3d v(0.8, 0.3, 0.0), x0(2.0, -1.0, 0.9);
  for (int k = 0; k < 400; ++k) {
    ASSERT_TRUE(tracker.update(at(0.05 * k), {detection(x0 + v * 0.05 * k)}));
  }
  ASSERT_EQ(tracker.tracks().size(), 1u);
  EXPECT_LT((tracker.tracks()[0].linear_velocity - v).norm(), 1e-6);
  EXPECT_LT((tracker.tracks()[0].position - (x0 + v * 0.05 * 399)).norm(), 1e-6);
}

TEST(MultiObjectTracker, ANewTrackHasAnUnknownVelocityUntilItsErrorIsBelowTheBound) {
  wp::TrackerParams p = params();
  p.confirm_hits = 2;
  p.known_velocity_error = 0.5;
  wp::MultiObjectTracker tracker(p);
  tracker.update(at(0.0), {detection({1, 1, 0.9})});
  EXPECT_TRUE(tracker.tracks().empty()) << "tentative after one hit";
  bool was_known = false;
  double previous = std::numeric_limits<double>::infinity();
  int unknown_frames = 0;
  for (int k = 1; k < 40; ++k) {
    tracker.update(at(0.05 * k), {detection({1.0 + 0.05 * k, 1, 0.9})});
    ASSERT_EQ(tracker.tracks().size(), 1u);
    const wp::BoxObservation& b = tracker.tracks()[0];
    EXPECT_LT(b.velocity_error, previous);  // shrinking while it converges
    previous = b.velocity_error;
    EXPECT_EQ(b.velocity_known, b.velocity_error <= 0.5) << "k " << k;
    if (!b.velocity_known) {
      EXPECT_FALSE(was_known) << "unknown again at k " << k;
      ++unknown_frames;
    }
    was_known = was_known || b.velocity_known;
  }
  EXPECT_GE(unknown_frames, 1);  // confirmed before its velocity is known
  EXPECT_TRUE(was_known);
}

TEST(MultiObjectTracker, TwoCrossingTargetsKeepTheirIds) {
  wp::TrackerParams p = params();
  wp::MultiObjectTracker tracker(p);
  wp_test::Rng rng(11);
  // A walks along +x at y = 0.15, B along +y at x = 0: 0.15 m apart at t = 4 s.
  auto truthA = [](double t) { return Eigen::Vector3d(-4.0 + t, 0.15, 0.9); };
  auto truthB = [](double t) { return Eigen::Vector3d(0.0, -4.0 + t, 0.9); };
  std::string idA, idB;
  for (int k = 0; k <= 160; ++k) {
    const double t = 0.05 * k;
    auto noisy = [&](const Eigen::Vector3d& x) {
      return Eigen::Vector3d(x + 0.02 * Eigen::Vector3d(rng.uniform(-1, 1), rng.uniform(-1, 1), 0));
    };
    // Alternate the order of the detections: ids must not follow the order.
    std::vector<wp::Detection> d{detection(noisy(truthA(t)), 0.03),
                                 detection(noisy(truthB(t)), 0.03)};
    if (k % 2) std::swap(d[0], d[1]);
    ASSERT_TRUE(tracker.update(at(t), d));
    ASSERT_LE(tracker.tracks().size(), 2u);
    if (tracker.tracks().size() < 2) continue;
    for (const wp::BoxObservation& b : tracker.tracks()) {
      const bool nearerA = (b.position - truthA(t)).norm() < (b.position - truthB(t)).norm();
      std::string& id = nearerA ? idA : idB;
      if (id.empty()) id = std::string(b.id);
      // Where the truths are well apart the nearest truth must be the id's own.
      if ((truthA(t) - truthB(t)).norm() > 0.5) {
        EXPECT_EQ(std::string(b.id), id) << "t " << t;
      }
    }
  }
  EXPECT_FALSE(idA.empty());
  EXPECT_FALSE(idB.empty());
  EXPECT_NE(idA, idB);
  EXPECT_EQ(tracker.stats().live, 2);
  ASSERT_NE(trackWithId(tracker, idA), nullptr);
  EXPECT_LT((trackWithId(tracker, idA)->position - truthA(8.0)).norm(), 0.1);
  EXPECT_LT((trackWithId(tracker, idB)->position - truthB(8.0)).norm(), 0.1);
}

TEST(MultiObjectTracker, AnOptimalAssignmentKeepsBothTracksWhereAGreedyOneWouldLoseOne) {
  // Two standing tracks at x = 0 and x = 1 (gate 1 m). Detections at 0.6 (gated for both, the
  // nearest to the second) and 1.9 (gated for the second only). Greedy by cost gives 0.6 to
  // the second track, and the first loses its detection; the optimum matches both.
  wp::TrackerParams p = params();
  p.gate_distance = 1.0;
  p.gate_chi2 = 1e6;  // the metric gate decides here
  wp::MultiObjectTracker tracker(p);
  for (int k = 0; k < 3; ++k) {
    tracker.update(at(0.05 * k), {detection({0, 0, 0.9}, 0.5), detection({1, 0, 0.9}, 0.5)});
  }
  ASSERT_EQ(tracker.tracks().size(), 2u);
  tracker.update(at(0.15), {detection({0.6, 0, 0.9}, 0.5), detection({1.9, 0, 0.9}, 0.5)});
  EXPECT_EQ(tracker.stats().matched, 2);
  EXPECT_EQ(tracker.stats().born, 0);
}

TEST(MultiObjectTracker, TheGateRejectsFarDetectionsAndOtherLabels) {
  wp::TrackerParams p = params();
  wp::MultiObjectTracker tracker(p);
  for (int k = 0; k < 30; ++k) tracker.update(at(0.05 * k), {detection({0, 0, 0.9}, 0.02)});
  ASSERT_EQ(tracker.tracks().size(), 1u);
  const std::string id(tracker.tracks()[0].id);
  // 3 m away: beyond the metric gate (2 m). A new tentative track, the old one misses.
  tracker.update(at(1.5), {detection({3, 0, 0.9}, 0.02)});
  EXPECT_EQ(tracker.stats().matched, 0);
  EXPECT_EQ(tracker.stats().born, 1);
  // 0.5 m away, within the metric gate but d^2 = 0.25 / (P_pp + 0.02^2), far beyond 16.27 for
  // a track known to a few cm: gated out too.
  tracker.update(at(1.55), {detection({0.5, 0, 0.9}, 0.02)});
  EXPECT_EQ(tracker.stats().matched, 0);
  // At the track's place but another label: not its detection.
  tracker.update(at(1.6), {detection({0, 0, 0.9}, 0.02, 1)});
  EXPECT_EQ(tracker.stats().matched, 0);
  // Back where it was, its own label: matched, same id (3 misses would have deleted it).
  wp::TrackerParams q = params();
  q.max_misses = 10;
  wp::MultiObjectTracker patient(q);
  for (int k = 0; k < 30; ++k) patient.update(at(0.05 * k), {detection({0, 0, 0.9}, 0.02)});
  patient.update(at(1.5), {detection({3, 0, 0.9}, 0.02)});
  patient.update(at(1.55), {detection({0.01, 0, 0.9}, 0.02)});
  EXPECT_EQ(patient.stats().matched, 1);
  EXPECT_NE(trackWithId(patient, id), nullptr);
}

TEST(MultiObjectTracker, ATargetThatLeavesIsDroppedAfterKFramesAndItsIdIsNotReused) {
  wp::TrackerParams p = params();
  p.max_misses = 4;
  wp::MultiObjectTracker tracker(p);
  for (int k = 0; k < 20; ++k) tracker.update(at(0.05 * k), {detection({0.05 * k, 0, 0.9})});
  ASSERT_EQ(tracker.tracks().size(), 1u);
  const std::string id(tracker.tracks()[0].id);
  double error = tracker.tracks()[0].position_error;
  // Frames without it: it coasts (predicted, its error growing) for K - 1 = 3 frames.
  for (int miss = 1; miss < 4; ++miss) {
    tracker.update(at(1.0 + 0.05 * miss), {});
    ASSERT_EQ(tracker.tracks().size(), 1u) << "miss " << miss;
    EXPECT_GT(tracker.tracks()[0].position_error, error);
    error = tracker.tracks()[0].position_error;
    EXPECT_NEAR(tracker.tracks()[0].position.x(), 1.0 + 0.05 * miss, 0.01);  // x = t, predicted
  }
  tracker.update(at(1.2), {});
  EXPECT_TRUE(tracker.tracks().empty());
  EXPECT_EQ(tracker.stats().deleted, 1);
  EXPECT_EQ(tracker.stats().live, 0);
  // Back at the same place: a new track, a new id.
  for (int k = 0; k < 3; ++k) tracker.update(at(1.25 + 0.05 * k), {detection({1, 0, 0.9})});
  ASSERT_EQ(tracker.tracks().size(), 1u);
  EXPECT_NE(std::string(tracker.tracks()[0].id), id);
  // The timeout deletes too: 2 s later (timeout 1 s), even on its first miss.
  tracker.update(at(3.5), {});
  EXPECT_TRUE(tracker.tracks().empty());
}

TEST(MultiObjectTracker, BadInputIsRejectedAndCounted) {
  wp::TrackerParams bad = params();
  bad.capacity = 0;
  bad.labels.clear();
  EXPECT_EQ(wp::validate(bad).size(), 2u);
  EXPECT_THROW(wp::MultiObjectTracker{bad}, std::invalid_argument);

  wp::TrackerParams p = params();
  p.max_detections = 2;
  wp::MultiObjectTracker tracker(p);
  wp::Detection nan = detection({std::nan(""), 0, 0});
  wp::Detection no_sigma = detection({0, 0, 0}, 0.0);
  wp::Detection wrong_label = detection({0, 0, 0}, 0.05, 7);
  wp::Detection flat = detection({0, 0, 0});
  flat.dimensions.z() = 0.0;
  EXPECT_TRUE(tracker.update(at(0), {nan, no_sigma, wrong_label, flat, detection({1, 0, 0}),
                                     detection({2, 0, 0}), detection({3, 0, 0})}));
  EXPECT_EQ(tracker.stats().rejected, 4);
  EXPECT_EQ(tracker.stats().detections, 2);
  EXPECT_EQ(tracker.stats().dropped, 1);
  EXPECT_EQ(tracker.stats().born, 2);
  EXPECT_FALSE(tracker.update(at(-1.0), {})) << "a frame older than the last";
  EXPECT_EQ(tracker.stats().live, 2);
}

TEST(MultiObjectTracker, NoAllocationAfterWarmUp) {
  wp::TrackerParams p = params();
  p.capacity = 64;
  p.max_detections = 64;
  wp::MultiObjectTracker tracker(p);
  wp_test::Rng rng(5);
  // 30 targets walking in a 20 m square, each seen in 90 % of the frames, with noise, and 2
  // clutter detections per frame (born, never confirmed, deleted: ids keep being made).
  struct Target {
    Eigen::Vector3d x, v;
  };
  std::vector<Target> targets(30);
  for (Target& t : targets) {
    t.x = Eigen::Vector3d(rng.uniform(-10, 10), rng.uniform(-10, 10), 0.9);
    t.v = Eigen::Vector3d(rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5), 0.0);
  }
  std::vector<wp::Detection> frame;
  frame.reserve(64);
  auto step = [&](int k) {
    frame.clear();
    for (Target& t : targets) {
      t.x += 0.05 * t.v;
      for (int a = 0; a < 2; ++a) {
        if (std::abs(t.x[a]) > 10.0) t.v[a] = -t.v[a];
      }
      if (rng.uniform(0, 1) < 0.9) {
        frame.push_back(detection(t.x + 0.03 * Eigen::Vector3d(rng.uniform(-1, 1), rng.uniform(-1, 1), 0), 0.03));
      }
    }
    for (int c = 0; c < 2; ++c) {
      frame.push_back(detection({rng.uniform(-30, 30), rng.uniform(30, 40), 0.9}, 0.03));
    }
    ASSERT_TRUE(tracker.update(at(0.05 * k), frame));
  };
  for (int k = 0; k < 100; ++k) step(k);  // warm-up
  const long before = wp_test::allocationCount();
  for (int k = 100; k < 400; ++k) step(k);
  EXPECT_EQ(wp_test::allocationCount() - before, 0);
  EXPECT_GE(static_cast<int>(tracker.tracks().size()), 28);
  // What it outputs is what the track table takes.
  std::string why;
  for (const wp::BoxObservation& b : tracker.tracks()) {
    EXPECT_EQ(wp::checkBox(b, wp::BoxLimits(), &why), wp::Drop::kCount) << b.id << ": " << why;
  }
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
