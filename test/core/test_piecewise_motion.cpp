// Piecewise constant-twist motion (keyframed paths) and growing margins in the core.
//
// Every expectation comes from an independent oracle (test/shared/oracles.hpp) or an analytic
// case, never from the code under test: poses along a path from their definition (Rodrigues
// per segment), the growth formula written out, the separating-axis test and the exact box-box
// distance for rounded boxes, sampled every millisecond and bisected. One case is a recorded
// answer: the hash of every event of fixed random scenes, computed with the code before paths
// and growth existed (main at f4fe9f7), which a one-segment path without margin and a body
// that does not grow must reproduce bit for bit.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "oracles.hpp"
#include "random.hpp"
#include "scenes.hpp"
#include "workspace_proximity/contact_window.hpp"
#include "workspace_proximity/motion_path.hpp"
#include "workspace_proximity/proximity_world.hpp"
#include "workspace_proximity/time_of_impact.hpp"

namespace wp = workspace_proximity;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// ------------------------------------------------------------------------------------------
// Bit for bit: the recorded hash of fixed scenes.

// FNV-1a over bytes.
void mix(std::uint64_t* h, const void* data, std::size_t n) {
  const unsigned char* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < n; ++i) {
    *h ^= p[i];
    *h *= 1099511628211ull;
  }
}
void mixDouble(std::uint64_t* h, double x) { mix(h, &x, sizeof x); }

// 24 random scenes of 12 mixed shapes (boxes, spheres, capsules, cylinders; turning or not,
// upright or not, with and without margins), 4 cycles each at a 1.5 s horizon; every field of
// every event hashed. `pose` sets a body's motion for the cycle.
template <class Pose>
std::uint64_t sceneHash(Pose pose, int* events) {
  std::uint64_t h = 14695981039346656037ull;
  wp_test::Rng rng(2024);
  for (int scene = 0; scene < 24; ++scene) {
    wp::WorldConfig config;
    config.rules = wp::PairRules::allowAll();
    wp::ProximityWorld world(config);
    const int n = 12;
    std::vector<wp::BodyHandle> handles;
    std::vector<wp::BodyMotion> motions;
    for (int i = 0; i < n; ++i) {
      const int kind = rng.integer(0, 4);
      const wp::Shape shape = kind == 0   ? wp::Shape::sphere(rng.uniform(0.1, 0.6))
                              : kind == 1 ? wp::Shape::capsule(rng.uniform(0.1, 0.4), rng.uniform(0.1, 0.8))
                              : kind == 2 ? wp::Shape::cylinder(rng.uniform(0.1, 0.4), rng.uniform(0.1, 0.8))
                                          : wp::Shape::box(rng.vector(0.1, 0.7));
      const bool rotate = rng.chance(0.5);
      const bool upright = rng.chance(0.5);
      const double margin = rng.chance(0.5) ? rng.uniform(0.0, 0.2) : 0.0;
      const wp::BodyMotion m = wp_test::randomMotion(rng, 2.5, 2.0, rotate ? 3.0 : 0.0, upright);
      handles.push_back(world.addBody(
          {"b" + std::to_string(i), "x", wp::BodyGroup::kObject, shape, margin}, wp::BodyMotion()));
      motions.push_back(m);
    }
    for (int cycle = 0; cycle < 4; ++cycle) {
      for (int i = 0; i < n; ++i) pose(&world, handles[i], motions[i]);
      for (const wp::PairEvent& e : world.predict(1.5)) {
        ++*events;
        const auto state = static_cast<std::uint8_t>(e.state);
        mix(&h, &state, 1);
        mix(&h, &e.body_a.index, sizeof e.body_a.index);
        mix(&h, &e.body_b.index, sizeof e.body_b.index);
        mixDouble(&h, e.time_to_contact);
        mixDouble(&h, e.time_to_separation);
        mixDouble(&h, e.distance);
        for (int k = 0; k < 3; ++k) {
          mixDouble(&h, e.point_a[k]);
          mixDouble(&h, e.point_b[k]);
          mixDouble(&h, e.normal[k]);
        }
        mixDouble(&h, e.closing_speed);
      }
      for (wp::BodyMotion& m : motions) m = m.advanced(0.1);
    }
  }
  return h;
}

// Recorded with sceneHash and setMotion on main at f4fe9f7, before paths and growth existed
// (the same with -O2, -O3 and ASan + UBSan builds of that core): 307 events. Re-recorded once
// since, when the upright-box distance moved to each box's own frame (fewer products, other
// last bits in distances and points; the same 307 events): the hash was 0x0676388347020655.
constexpr std::uint64_t kRecordedHash = 0xa3a0c7b014406da1ull;
constexpr int kRecordedEvents = 307;

TEST(PiecewiseMotion, ConstantTwistIsBitForBitAsBefore) {
  int events = 0;
  const std::uint64_t h = sceneHash(
      [](wp::ProximityWorld* w, wp::BodyHandle b, const wp::BodyMotion& m) { w->setMotion(b, m); },
      &events);
  EXPECT_EQ(events, kRecordedEvents);
  EXPECT_EQ(h, kRecordedHash);
}

TEST(PiecewiseMotion, OneSegmentWithoutMarginAndNoGrowthIsBitForBitAsBefore) {
  int events = 0;
  const std::uint64_t h = sceneHash(
      [](wp::ProximityWorld* w, wp::BodyHandle b, const wp::BodyMotion& m) {
        wp::MotionSegment segment;
        segment.motion = m;
        w->setPath(b, &segment, 1);
        wp::MarginGrowth none;  // no growth, whatever the age and the cap
        none.age = 0.3;
        none.speed_cap = 2.0;
        w->setGrowth(b, none);
      },
      &events);
  EXPECT_EQ(events, kRecordedEvents);
  EXPECT_EQ(h, kRecordedHash);
}

// ------------------------------------------------------------------------------------------
// The growth model.

TEST(MarginGrowth, ValuesRatesAndCapFollowTheFormula) {
  wp_test::Rng rng(31);
  for (int i = 0; i < 2000; ++i) {
    wp::MarginGrowth g;
    g.velocity_error = rng.chance(0.2) ? 0.0 : rng.uniform(0.0, 2.0);
    g.max_accel = rng.chance(0.2) ? 0.0 : rng.uniform(0.0, 6.0);
    g.speed_cap = rng.chance(0.4) ? kInf : rng.uniform(0.0, 3.0);
    g.age = rng.chance(0.3) ? 0.0 : rng.uniform(0.0, 0.5);
    ASSERT_TRUE(g.valid());
    double previous = -1.0;
    double largest_slope_seen = 0.0;
    const double h = 1e-4;
    for (int k = 0; k <= 300; ++k) {
      const double t = k * 0.01;
      const double expected =
          oracle::grownMargin(g.velocity_error, g.max_accel, g.speed_cap, g.age, t);
      ASSERT_NEAR(g.at(t), expected, 1e-12 * (1.0 + expected));
      ASSERT_GE(g.at(t), previous);  // non-decreasing
      previous = g.at(t);
      const double slope =
          (oracle::grownMargin(g.velocity_error, g.max_accel, g.speed_cap, g.age, t + h) -
           oracle::grownMargin(g.velocity_error, g.max_accel, g.speed_cap, g.age, t)) / h;
      largest_slope_seen = std::max(largest_slope_seen, slope);
      // The polynomial of a stretch is exact away from the cap's onset and never below.
      const double t1 = t + 0.05;
      const wp::GrowthPiece p = wp::growthPiece(g, t, t1);
      for (double x : {0.0, 0.02, 0.05}) {
        const double truth = oracle::grownMargin(g.velocity_error, g.max_accel, g.speed_cap, g.age, t + x);
        ASSERT_GE(p.at(x), truth - 1e-12 * (1.0 + truth));
        if (!(g.capTime() > t && g.capTime() < t1)) {
          ASSERT_NEAR(p.at(x), truth, 1e-12 * (1.0 + truth));
        }
      }
    }
    EXPECT_GE(g.maxRate(0.0, 3.0) + 1e-9, largest_slope_seen - 1e-3);
    if (g.age > 0.0) {
      EXPECT_EQ(g.at(0.0) == 0.0, g.none());
    }
  }
  // The cap takes over where the quadratic meets the line: e = 0, a = 4, c = 1 -> t = 0.5.
  wp::MarginGrowth g;
  g.max_accel = 4.0;
  g.speed_cap = 1.0;
  EXPECT_DOUBLE_EQ(g.capTime(), 0.5);
  EXPECT_DOUBLE_EQ(g.at(0.25), 0.125);
  EXPECT_DOUBLE_EQ(g.at(1.5), 1.5);
  EXPECT_DOUBLE_EQ(g.maxRate(0.0, 2.0), 2.0);  // 4 * 0.5, just before the cap
  EXPECT_DOUBLE_EQ(g.maxRate(0.6, 2.0), 1.0);
  g.age = 0.2;
  EXPECT_DOUBLE_EQ(g.capTime(), 0.3);
}

TEST(MarginGrowth, InvalidValuesAreRefused) {
  wp::MarginGrowth g;
  EXPECT_TRUE(g.valid());
  g.velocity_error = -0.1;
  EXPECT_FALSE(g.valid());
  g.velocity_error = std::nan("");
  EXPECT_FALSE(g.valid());
  g = wp::MarginGrowth();
  g.max_accel = kInf;
  EXPECT_FALSE(g.valid());
  g = wp::MarginGrowth();
  g.age = -1.0;
  EXPECT_FALSE(g.valid());
  g = wp::MarginGrowth();
  g.speed_cap = -1.0;
  EXPECT_FALSE(g.valid());
}

// ------------------------------------------------------------------------------------------
// Per-axis times with growth: the closed form against sampling and bisection.

TEST(GrowingAxisInterval, MatchesSamplingAndBisection) {
  wp_test::Rng rng(41);
  int overlapping = 0;
  for (int i = 0; i < 20000; ++i) {
    const double ca = rng.uniform(-3, 3), cb = rng.uniform(-3, 3);
    const double ha = rng.uniform(0.01, 0.5), hb = rng.uniform(0.01, 0.5);
    const double va = rng.uniform(-3, 3), vb = rng.uniform(-3, 3);
    const double ga[3] = {rng.chance(0.3) ? 0.0 : rng.uniform(0, 0.3),
                          rng.chance(0.3) ? 0.0 : rng.uniform(0, 2), rng.chance(0.5) ? 0.0 : rng.uniform(0, 2)};
    const double gb[3] = {rng.chance(0.5) ? 0.0 : rng.uniform(0, 0.3),
                          rng.chance(0.5) ? 0.0 : rng.uniform(0, 2), rng.chance(0.7) ? 0.0 : rng.uniform(0, 2)};
    const double length = rng.uniform(0.0, 2.0);
    auto overlap = [&](double x) {
      const double sa = ha + ga[0] + x * (ga[1] + x * ga[2]);
      const double sb = hb + gb[0] + x * (gb[1] + x * gb[2]);
      return std::abs((cb + vb * x) - (ca + va * x)) <= sa + sb;
    };
    const wp::TimeInterval r = wp::growingAxisInterval(ca, ha, va, ga, cb, hb, vb, gb, length);
    double first = 0.0, last = 0.0;
    const bool any = oracle::contactTimes(overlap, 0.0, length, 1e-3, &first, &last);
    if (!any) {
      // An overlap the samples cannot see is shorter than their step.
      if (!r.empty()) {
        EXPECT_LT(r.last - r.first, 1.1e-3) << "case " << i;
      }
      continue;
    }
    ++overlapping;
    ASSERT_FALSE(r.empty()) << "case " << i << ": missed an overlap at " << first;
    EXPECT_LE(r.first, first + 1e-12) << "case " << i;
    EXPECT_GE(r.last, last - 1e-12) << "case " << i;
    // Tight: the closed form is the hull itself, up to rounding.
    EXPECT_GE(r.first, first - 1e-9) << "case " << i;
    EXPECT_LE(r.last, last + 1e-9) << "case " << i;
  }
  EXPECT_GT(overlapping, 3000);
}

// ------------------------------------------------------------------------------------------
// Random multi-segment scenes against the sampled oracle.

// A box on a path, with a margin that may grow: the test's own record of its motion.
struct PathBox {
  Eigen::Vector3d half = Eigen::Vector3d::Constant(0.3);
  double margin = 0.0;
  std::vector<wp::MotionSegment> path;
  bool grows = false;
  double velocity_error = 0.0, max_accel = 0.0, speed_cap = kInf, age = 0.0;
  wp::BodyHandle handle;

  oracle::Obb at(double t) const { return oracle::Obb{oracle::pathPoseAt(path, t), half}; }
  // Margin at t: the body's, the segment's, and (with growth) the grown uncertainty.
  double marginAt(double t, bool with_growth) const {
    double m = margin + oracle::pathMarginAt(path, t);
    if (with_growth && grows) m += oracle::grownMargin(velocity_error, max_accel, speed_cap, age, t);
    return m;
  }
  wp::MarginGrowth growth() const {
    wp::MarginGrowth g;
    if (!grows) return g;
    g.velocity_error = velocity_error;
    g.max_accel = max_accel;
    g.speed_cap = speed_cap;
    g.age = age;
    return g;
  }
};

// The margin-inflated boxes touch at t (the exact box-box distance within the margins).
bool touching(const PathBox& a, const PathBox& b, double t, bool with_growth) {
  const oracle::Obb oa = a.at(t), ob = b.at(t);
  const double m = a.marginAt(t, with_growth) + b.marginAt(t, with_growth);
  const double centres = (oa.pose.translation() - ob.pose.translation()).norm();
  if (centres > a.half.norm() + b.half.norm() + m) return false;  // bounding spheres apart
  if (oracle::overlaps(oa, ob)) return true;
  return m > 0.0 && oracle::boxBoxDistance(oa, ob) <= m;
}

struct SceneOptions {
  bool rotate = true;
  bool upright = false;
  bool continuous = true;
  bool segment_margins = true;
  double growth_share = 0.0;  // share of bodies whose margin grows
  int max_segments = 5;
};

struct SceneCounts {
  int contacts = 0;       // pairs the oracle sees touching
  int tight_first = 0;    // ... whose predicted first contact is within 2 ms of the oracle's
  int growth_pairs = 0;   // ... with a growing body
};

// Random scenes of `n` boxes on random paths (some growing); a few cycles each, every pair
// checked against the oracle sampled every millisecond over the horizon.
void checkScenes(int scenes, int n, const SceneOptions& o, unsigned seed, SceneCounts* counts);

// Prints what a scene test checked (for the log).
struct Report {
  const SceneCounts& c;
  ~Report() {
    std::printf("  %d contacts checked, %d with a growing body, %d first contacts within 2 ms\n",
                c.contacts, c.growth_pairs, c.tight_first);
  }
};

void checkScenes(int scenes, int n, const SceneOptions& o, unsigned seed, SceneCounts* counts) {
  const Report report{*counts};
  wp_test::Rng rng(seed);
  const double horizon = 1.5;
  const double dt = 1e-3;
  for (int scene = 0; scene < scenes; ++scene) {
    wp::WorldConfig config;
    config.rules = wp::PairRules::allowAll();
    wp::ProximityWorld world(config);
    std::vector<PathBox> bodies(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      PathBox& b = bodies[static_cast<std::size_t>(i)];
      b.half = rng.vector(0.1, 0.6);
      b.margin = rng.chance(0.5) ? rng.uniform(0.0, 0.1) : 0.0;
      b.handle = world.addBody({"b" + std::to_string(i), "box", wp::BodyGroup::kObject,
                                wp::Shape::box(b.half), b.margin},
                               wp::BodyMotion());
    }
    std::vector<wp::BodyMotion> starts;
    for (int i = 0; i < n; ++i) {
      starts.push_back(wp_test::randomMotion(rng, 2.0, 1.5, o.rotate ? 3.0 : 0.0, o.upright));
    }
    for (int cycle = 0; cycle < 3; ++cycle) {
      for (int i = 0; i < n; ++i) {
        PathBox& b = bodies[static_cast<std::size_t>(i)];
        b.path = wp_test::randomPath(rng, starts[static_cast<std::size_t>(i)],
                                     rng.integer(1, o.max_segments), horizon, 1.5,
                                     o.rotate ? 3.0 : 0.0, o.upright, o.continuous,
                                     o.segment_margins && rng.chance(0.5));
        b.grows = rng.chance(o.growth_share);
        if (b.grows) {
          b.velocity_error = rng.uniform(0.0, 1.0);
          b.max_accel = rng.chance(0.7) ? rng.uniform(0.0, 3.0) : 0.0;
          b.speed_cap = rng.chance(0.5)
                            ? rng.uniform(0.5, 1.5) + b.path[0].motion.linear_velocity.norm()
                            : kInf;
          b.age = rng.chance(0.5) ? rng.uniform(0.0, 0.1) : 0.0;
        }
        world.setPath(b.handle, b.path.data(), static_cast<int>(b.path.size()));
        world.setGrowth(b.handle, b.growth());
      }
      std::map<std::pair<int, int>, wp::PairEvent> predicted;
      for (const wp::PairEvent& e : world.predict(horizon)) {
        if (e.state == wp::ContactState::kEnd) continue;
        predicted[{std::min(e.body_a.index, e.body_b.index), std::max(e.body_a.index, e.body_b.index)}] = e;
      }
      for (int i = 0; i < n; ++i) {
        for (int j = i + 1; j < n; ++j) {
          const PathBox& a = bodies[static_cast<std::size_t>(i)];
          const PathBox& b = bodies[static_cast<std::size_t>(j)];
          const int hi = a.handle.index, hj = b.handle.index;
          const auto it = predicted.find({std::min(hi, hj), std::max(hi, hj)});
          double first = 0.0, last = 0.0;
          const bool grown = oracle::contactTimes([&](double t) { return touching(a, b, t, true); },
                                                  0.0, horizon, dt, &first, &last);
          if (!grown) continue;
          ++counts->contacts;
          counts->growth_pairs += (a.grows || b.grows) ? 1 : 0;
          ASSERT_NE(it, predicted.end()) << "missed contact: scene " << scene << " cycle " << cycle
                                         << " pair " << i << "," << j << " touching at " << first;
          const wp::PairEvent& e = it->second;
          ASSERT_LE(e.time_to_contact, first + 1e-9)
              << "late: scene " << scene << " cycle " << cycle << " pair " << i << "," << j;
          counts->tight_first += e.time_to_contact >= first - 2e-3 ? 1 : 0;
          // The last contact is that of the shapes without growth (the constant-velocity one).
          double nominal_first = 0.0, nominal_last = 0.0;
          if (oracle::contactTimes([&](double t) { return touching(a, b, t, false); }, 0.0,
                                   horizon, dt, &nominal_first, &nominal_last)) {
            ASSERT_GE(e.time_to_separation, nominal_last - 1e-9)
                << "early: scene " << scene << " cycle " << cycle << " pair " << i << "," << j;
          }
          ASSERT_GE(e.time_to_separation, e.time_to_contact);
          ASSERT_LE(e.time_to_separation, horizon);
        }
      }
      // Next cycle: every body from where its path had it 0.1 s on, with new segments.
      for (int i = 0; i < n; ++i) {
        const PathBox& b = bodies[static_cast<std::size_t>(i)];
        const Eigen::Isometry3d pose = oracle::pathPoseAt(b.path, 0.1);
        wp::BodyMotion& m = starts[static_cast<std::size_t>(i)];
        m.position = pose.translation();
        m.orientation = Eigen::Quaterniond(pose.linear()).normalized();
      }
    }
  }
}

// The random-scene cases: what each varies, and what its counts must reach so that the scenes
// exercised what they are about (enough contacts or growing pairs, enough tight first contacts).
struct RandomSceneCase {
  const char* name;
  SceneOptions options;
  int scenes;
  unsigned seed;
  bool count_growth_pairs;  // the floor applies to pairs with a growing body, else to contacts
  int tight_tenths;         // tight first contacts > this many tenths of the contacts (0: any)
};

SceneOptions sceneOptions(bool continuous, bool upright, bool rotate, double growth_share) {
  SceneOptions o;
  o.continuous = continuous;  // false: segments start anywhere near where the last one ended
  o.upright = upright;        // the closed form's path (and Newton steps where they translate)
  o.rotate = rotate;
  o.growth_share = growth_share;
  return o;
}

class RandomScenes : public ::testing::TestWithParam<RandomSceneCase> {};

TEST_P(RandomScenes, MissNothingNeverLateNeverEarly) {
  const RandomSceneCase& c = GetParam();
  SceneCounts counts;
  checkScenes(c.scenes, 10, c.options, c.seed, &counts);
  EXPECT_GT(c.count_growth_pairs ? counts.growth_pairs : counts.contacts, 150);
  if (c.tight_tenths > 0) {
    EXPECT_GT(counts.tight_first, counts.contacts * c.tight_tenths / 10);
  }
}

INSTANTIATE_TEST_SUITE_P(
    PiecewiseMotion, RandomScenes,
    ::testing::Values(
        RandomSceneCase{"TurningPaths", sceneOptions(true, false, true, 0.0), 16, 101, false, 8},
        RandomSceneCase{"BrokenPaths", sceneOptions(false, false, true, 0.0), 16, 102, false, 0},
        RandomSceneCase{"UprightPaths", sceneOptions(true, true, true, 0.0), 16, 103, false, 8},
        RandomSceneCase{"GrowingMargins", sceneOptions(true, false, true, 0.6), 10, 104, true, 8},
        // Exact gaps: Newton steps where the growth is linear.
        RandomSceneCase{"TranslatingUprightGrowing", sceneOptions(true, true, false, 0.6), 10, 105,
                        true, 9}),
    [](const ::testing::TestParamInfo<RandomSceneCase>& info) { return std::string(info.param.name); });

// ------------------------------------------------------------------------------------------
// Swept bounds of a path hold the body, margins and growth at every instant.

TEST(PiecewiseMotion, SweptBoundsHoldTheBodyAlongThePath) {
  wp_test::Rng rng(55);
  for (int i = 0; i < 300; ++i) {
    wp::ProximityWorld world;
    PathBox b;
    b.half = rng.vector(0.05, 0.6);
    b.margin = rng.uniform(0.0, 0.1);
    b.handle = world.addBody({"b", "box", wp::BodyGroup::kObject, wp::Shape::box(b.half), b.margin},
                             wp::BodyMotion());
    const double horizon = rng.uniform(0.0, 2.0);
    b.path = wp_test::randomPath(rng, wp_test::randomMotion(rng, 3.0, 2.0, 4.0), rng.integer(1, 8),
                                 std::max(horizon, 0.05), 2.0, 4.0, rng.chance(0.3),
                                 rng.chance(0.5), true);
    b.grows = rng.chance(0.5);
    b.velocity_error = rng.uniform(0, 1);
    b.max_accel = rng.uniform(0, 3);
    b.speed_cap = rng.chance(0.5) ? 1.5 : kInf;
    b.age = rng.uniform(0, 0.2);
    world.setPath(b.handle, b.path.data(), static_cast<int>(b.path.size()));
    world.setGrowth(b.handle, b.growth());
    world.predict(horizon);
    const wp::Aabb box = world.sweptBounds(b.handle);
    for (int k = 0; k <= 400; ++k) {
      const double t = horizon * k / 400.0;
      const double m = b.marginAt(t, true);
      for (const Eigen::Vector3d& v : oracle::vertices(b.at(t))) {
        for (int axis = 0; axis < 3; ++axis) {
          ASSERT_LE(box.lower[axis], v[axis] - m + 1e-9) << "case " << i << " t " << t;
          ASSERT_GE(box.upper[axis], v[axis] + m - 1e-9) << "case " << i << " t " << t;
        }
      }
    }
  }
}

// ------------------------------------------------------------------------------------------
// Analytic cases.

// A static post (0.2 x 0.2 x 1 m at the origin) and a person (0.5 x 0.5 x 1.8 m) whose near
// face is `gap` m away along x, standing still or walking at `speed` m/s towards the post.
struct PostAndPerson {
  wp::ProximityWorld world;
  wp::BodyHandle post, person;
  PostAndPerson(double gap, double speed) {
    post = world.addBody({"post", "robot", wp::BodyGroup::kRobot, wp::Shape::box({0.1, 0.1, 0.5}), 0.0},
                         wp::BodyMotion());
    wp::BodyMotion m;
    m.position = {0.1 + gap + 0.25, 0.0, 0.0};
    m.linear_velocity = {-speed, 0.0, 0.0};
    person = world.addBody({"person", "person", wp::BodyGroup::kObject,
                            wp::Shape::box({0.25, 0.25, 0.9}), 0.0},
                           m);
  }
  const wp::PairEvent* predict(const wp::MarginGrowth& g, double horizon = 2.0) {
    world.setGrowth(person, g);
    const std::vector<wp::PairEvent>& events = world.predict(horizon);
    return events.empty() ? nullptr : &events.front();
  }
};

// Growth of velocity error `e` (m/s) and acceleration bound `a` (m/s^2), capped at `cap` (m/s),
// measured `age` s before the prediction instant.
wp::MarginGrowth growth(double e, double a, double cap = kInf, double age = 0.0) {
  wp::MarginGrowth g;
  g.velocity_error = e;
  g.max_accel = a;
  g.speed_cap = cap;
  g.age = age;
  return g;
}

// A growing pair's first contact at the analytic `expected` s: reported, never later, at most
// 0.1 ms earlier.
::testing::AssertionResult firstContactAt(const wp::PairEvent* e, double expected) {
  if (e == nullptr) return ::testing::AssertionFailure() << "no event, expected contact at " << expected;
  if (e->time_to_contact > expected || e->time_to_contact < expected - 1e-4) {
    return ::testing::AssertionFailure() << "first contact at " << e->time_to_contact << " s, expected "
                                         << expected << " s (never later, at most 0.1 ms earlier)";
  }
  return ::testing::AssertionSuccess();
}

TEST(GrowingMargin, VelocityErrorReachesAStandingPersonsGapAtGapOverError) {
  // 1.6 m/s of velocity error, standing 1.6 m away: the uncertainty reaches the post at 1 s.
  PostAndPerson scene(1.6, 0.0);
  const wp::PairEvent* e = scene.predict(growth(1.6, 0.0));
  ASSERT_TRUE(firstContactAt(e, 1.0));
  // Standing still: the constant-velocity shapes never touch, so the separation is the contact.
  EXPECT_DOUBLE_EQ(e->time_to_separation, e->time_to_contact);
  EXPECT_NEAR(e->distance, 1.6, 1e-9);
}

TEST(GrowingMargin, AccelerationReachesAStandingPersonsGapAtSqrtTwoGapOverAccel) {
  // 2 m/s^2 from rest, 1 m away: a t^2 / 2 = 1 at 1 s.
  PostAndPerson scene(1.0, 0.0);
  ASSERT_TRUE(firstContactAt(scene.predict(growth(0.0, 2.0)), 1.0));
}

TEST(GrowingMargin, TheSpeedCapAndTheAgeShiftTheContact) {
  {
    // min(2 t^2, t): the cap takes over at 0.5 s; 1.5 m is reached at 1.5 s on the line.
    PostAndPerson scene(1.5, 0.0);
    ASSERT_TRUE(firstContactAt(scene.predict(growth(0.0, 4.0, 1.0)), 1.5));
  }
  {
    // Observed 0.25 s before the prediction instant: 1.6 (0.25 + t) = 1.6 at t = 0.75, and
    // the distance now already includes the 0.4 m grown since.
    PostAndPerson scene(1.6, 0.0);
    const wp::PairEvent* e = scene.predict(growth(1.6, 0.0, kInf, 0.25));
    ASSERT_TRUE(firstContactAt(e, 0.75));
    EXPECT_NEAR(e->distance, 1.2, 1e-9);
  }
  {
    // Beyond the horizon: nothing.
    PostAndPerson scene(1.6, 0.0);
    EXPECT_EQ(scene.predict(growth(0.5, 0.0)), nullptr);
  }
}

TEST(GrowingMargin, AWalkingPersonIsReachedEarlierAndLeavesAtTheConstantVelocityTime) {
  // Walking at 1 m/s towards the post from 1 m: nominal contact [1.0, 1.7] (0.7 m of
  // combined width along x). With 0.5 m/s of velocity error: first contact where
  // 1 - t = 0.5 t, t = 2/3; the separation stays the constant-velocity 1.7.
  PostAndPerson scene(1.0, 1.0);
  const wp::PairEvent* e = scene.predict(growth(0.5, 0.0));
  ASSERT_TRUE(firstContactAt(e, 2.0 / 3.0));
  EXPECT_GE(e->time_to_separation, 1.7 - 1e-12);
  EXPECT_LE(e->time_to_separation, 1.7 + 1e-4);
}

// A link swinging about the vertical at 0.8 rad/s: one constant twist extrapolates its centre
// along the tangent, the keyframed path follows the arc. A box on the arc 1.2 rad ahead is
// met at the analytic time only by the path.
TEST(PiecewiseMotion, KeyframedArcMeetsABoxOnTheArcAtTheAnalyticTime) {
  const double omega = 0.8, radius = 1.0, horizon = 2.0;
  const Eigen::Vector3d link_half(0.1, 0.05, 0.05);
  // A thin post on the circle at angle phi: the link's near end (at radius, half-length
  // 0.1 along the tangent... the link box is along x, turned with yaw) first touches it when
  // the link's leading face reaches it.
  const double phi = 1.2;
  const Eigen::Vector3d post_half(0.02, 0.02, 0.5);
  wp::ProximityWorld world;
  const wp::BodyHandle link = world.addBody(
      {"link", "robot", wp::BodyGroup::kRobot, wp::Shape::box(link_half), 0.0}, wp::BodyMotion());
  wp::BodyMotion post_motion;
  post_motion.position = {radius * std::cos(phi), radius * std::sin(phi), 0.0};
  world.addBody({"post", "post", wp::BodyGroup::kObject, wp::Shape::box(post_half), 0.0}, post_motion);
  // Oracle: the link's true motion (turningLink at time t), sampled and bisected.
  auto touchingAt = [&](double t) {
    const wp::BodyMotion m = wp_test::turningLink(t, radius, 0.0, omega);
    return oracle::overlaps(oracle::Obb{oracle::poseAt(m, 0.0), link_half},
                            oracle::Obb{oracle::makePose(post_motion.position), post_half});
  };
  double first = 0.0, last = 0.0;
  ASSERT_TRUE(oracle::contactTimes(touchingAt, 0.0, horizon, 1e-3, &first, &last));

  // One constant twist: the straight-line extrapolation is far off (or misses).
  world.setMotion(link, wp_test::turningLink(0.0, radius, 0.0, omega));
  const std::vector<wp::PairEvent>& straight = world.predict(horizon);
  const bool straight_far = straight.empty() || std::abs(straight.front().time_to_contact - first) > 0.3;
  EXPECT_TRUE(straight_far);

  // Keyframes every 0.1 s with the sagitta as margin: never late, within 5 ms.
  std::vector<wp::MotionSegment> path;
  wp_test::turningLinkPath(0.0, radius, 0.0, omega, 0.0, horizon, 20, link_half.norm(), &path);
  world.setPath(link, path.data(), static_cast<int>(path.size()));
  const std::vector<wp::PairEvent>& events = world.predict(horizon);
  ASSERT_FALSE(events.empty());
  EXPECT_LE(events.front().time_to_contact, first + 1e-9);
  EXPECT_GE(events.front().time_to_contact, first - 5e-3);
  EXPECT_GE(events.front().time_to_separation, last - 1e-9);
}

// ------------------------------------------------------------------------------------------
// Pieces and input checks.

TEST(PairPieces, BreakpointsAreBothPathsStartsAndTheCapOnsets) {
  std::vector<wp::PathSegment> a(3), b(2);
  a[0].start = 0.0;
  a[1].start = 0.5;
  a[2].start = 1.5;
  b[0].start = 0.0;
  b[1].start = 0.5;  // shared with a
  const wp::Shape shape = wp::Shape::box({0.1, 0.1, 0.1});
  wp::MarginGrowth g;
  g.max_accel = 4.0;
  g.speed_cap = 1.0;  // onset at 0.5 - 0.2 = 0.3
  g.age = 0.2;
  wp::preparePath(shape, 0.0, wp::MarginGrowth(), 2.0, a.data(), 3);
  wp::preparePath(shape, 0.0, g, 2.0, b.data(), 2);
  wp::PairBody pa, pb;
  pa.shape = pb.shape = &shape;
  pa.motion = &a[0].motion;
  pb.motion = &b[0].motion;
  pa.segments = a.data();
  pa.segment_count = 3;
  pb.segments = b.data();
  pb.segment_count = 2;
  pb.growth = &g;
  const wp::PairPieces pieces(pa, pb, 2.0);
  const double expected[] = {0.0, 0.3, 0.5, 1.5, 2.0};
  ASSERT_EQ(pieces.size(), 4);
  const int seg_a[] = {0, 0, 1, 2}, seg_b[] = {0, 0, 1, 1};
  for (int i = 0; i < 4; ++i) {
    const wp::Piece p = pieces.piece(i);
    EXPECT_DOUBLE_EQ(p.u0, expected[i]);
    EXPECT_DOUBLE_EQ(p.u1, expected[i + 1]);
    EXPECT_EQ(p.a.segment, &a[static_cast<std::size_t>(seg_a[i])]);
    EXPECT_EQ(p.b.segment, &b[static_cast<std::size_t>(seg_b[i])]);
    EXPECT_EQ(p.b.growth.linear(), i >= 1);  // quadratic before the onset, the line after
  }
  EXPECT_EQ(pieces.pieceAt(0.5), 2);
  EXPECT_EQ(pieces.pieceAt(2.0), 3);
  // A shorter horizon uses the segments that start before it.
  const wp::PairPieces short_pieces(pa, pb, 0.4);
  EXPECT_EQ(short_pieces.size(), 2);
}

TEST(PiecewiseMotion, InvalidPathsAndGrowthAreRejected) {
  wp::ProximityWorld world;
  const wp::BodyHandle h =
      world.addBody({"b", "box", wp::BodyGroup::kObject, wp::Shape::box({0.1, 0.1, 0.1}), 0.0},
                    wp::BodyMotion());
  std::vector<wp::MotionSegment> path(2);
  path[1].start = 0.5;
  EXPECT_NO_THROW(world.setPath(h, path.data(), 2));
  path[0].start = 0.1;  // must start at 0
  EXPECT_THROW(world.setPath(h, path.data(), 2), std::invalid_argument);
  path[0].start = 0.0;
  path[1].start = 0.0;  // not increasing
  EXPECT_THROW(world.setPath(h, path.data(), 2), std::invalid_argument);
  path[1].start = 0.5;
  path[1].margin = -1.0;
  EXPECT_THROW(world.setPath(h, path.data(), 2), std::invalid_argument);
  path[1].margin = 0.0;
  path[1].motion.linear_velocity.x() = std::nan("");
  EXPECT_THROW(world.setPath(h, path.data(), 2), std::invalid_argument);
  EXPECT_THROW(world.setPath(h, path.data(), 0), std::invalid_argument);
  std::vector<wp::MotionSegment> many(wp::Limits::kMaxSegments + 1);
  for (std::size_t k = 0; k < many.size(); ++k) many[k].start = 0.01 * static_cast<double>(k);
  EXPECT_THROW(world.setPath(h, many.data(), static_cast<int>(many.size())), std::invalid_argument);
  EXPECT_NO_THROW(world.setPath(h, many.data(), wp::Limits::kMaxSegments));
  wp::MarginGrowth g;
  g.velocity_error = -1.0;
  EXPECT_THROW(world.setGrowth(h, g), std::invalid_argument);
  EXPECT_NO_THROW(world.predict(2.0));
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
