// The whole pipeline through ProximityWorld, on scenes with analytic answers.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <stdexcept>

#include "random.hpp"
#include "scenes.hpp"
#include "workspace_proximity/proximity_world.hpp"

namespace wp = workspace_proximity;

namespace {

wp::BodyMotion at(const Eigen::Vector3d& p, const Eigen::Vector3d& v = Eigen::Vector3d::Zero()) {
  wp::BodyMotion m;
  m.position = p;
  m.linear_velocity = v;
  return m;
}

wp::BodyDesc object(const std::string& id, const wp::Shape& shape, double margin = 0.0) {
  return wp::BodyDesc{id, "thing", wp::BodyGroup::kObject, shape, margin};
}

const wp::Shape kCube = wp::Shape::box({0.5, 0.5, 0.5});

// Unit cubes "a" and "b" 5 m apart centre to centre, closing head-on at 2 m/s.
void addHeadOnCubes(wp::ProximityWorld* world) {
  world->addBody(object("a", kCube), at({0, 0, 0}, {1, 0, 0}));
  world->addBody(object("b", kCube), at({5, 0, 0}, {-1, 0, 0}));
}

}  // namespace

TEST(ProximityWorld, HeadOnApproachHasTheAnalyticTimes) {
  wp::ProximityWorld world;
  addHeadOnCubes(&world);
  const auto& events = world.predict(5.0);
  ASSERT_EQ(events.size(), 1u);
  const wp::PairEvent& e = events[0];
  // Gap 4 m closing at 2 m/s: contact at 2 s. They pass through each other and separate when
  // the relative displacement reaches 4 + 2 = 6 m: at 3 s.
  EXPECT_LE(e.time_to_contact, 2.0);
  EXPECT_GE(e.time_to_contact, 2.0 - 1e-3);
  EXPECT_GE(e.time_to_separation, 3.0);
  EXPECT_LE(e.time_to_separation, 3.0 + 1e-3);
  EXPECT_NEAR(e.distance, 4.0, 1e-6);
  EXPECT_NEAR(e.closing_speed, 2.0, 1e-6);
  EXPECT_NEAR(e.normal.x(), 1.0, 1e-6);
  EXPECT_NEAR(e.point_a.x(), 0.5, 1e-6);
  EXPECT_NEAR(e.point_b.x(), 4.5, 1e-6);
}

TEST(ProximityWorld, SeparationIsTheHorizonWhenContactOutlastsIt) {
  wp::ProximityWorld world;
  addHeadOnCubes(&world);
  const auto& events = world.predict(2.5);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_DOUBLE_EQ(events[0].time_to_separation, 2.5);
}

TEST(ProximityWorld, NearMissGivesNoEvent) {
  wp::ProximityWorld world;
  // Crossing paths at different times: a overlaps b's x range during [1, 2] s, b reaches
  // a's y range during [2.25, 3.25] s. The swept bounds overlap, the boxes never meet.
  world.addBody(object("a", kCube), at({0, 0, 0}, {2, 0, 0}));
  world.addBody(object("b", kCube), at({3, 5.5, 0}, {0, -2, 0}));
  EXPECT_TRUE(world.predict(3.0).empty());
  EXPECT_EQ(world.stats().broad_pairs, 1);
}

TEST(ProximityWorld, RotatedBoxesWhoseBoundsOverlapButNeverTouchGiveNoEvent) {
  // Two long thin boxes turned 45 degrees, side by side 0.85 m apart centre to centre
  // across their long axes, sliding along them. Their axis-aligned bounds overlap the whole
  // time, so only the narrow phase can tell they never touch (gap 0.85 - 0.2 = 0.65 m).
  wp::ProximityWorld world;
  const Eigen::Quaterniond q(Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitZ()));
  const Eigen::Vector3d along = q * Eigen::Vector3d::UnitX();
  const Eigen::Vector3d across = q * Eigen::Vector3d::UnitY();
  wp::BodyMotion a = at({0, 0, 0}, along * 1.0);
  a.orientation = q;
  wp::BodyMotion b = at(across * 0.85, -along * 1.0);
  b.orientation = q;
  world.addBody(object("a", wp::Shape::box({2.0, 0.1, 0.5})), a);
  world.addBody(object("b", wp::Shape::box({2.0, 0.1, 0.5})), b);
  EXPECT_TRUE(world.predict(2.0).empty());
  EXPECT_EQ(world.stats().broad_pairs, 1);
  EXPECT_EQ(world.stats().axis_candidates, 1);
  EXPECT_EQ(world.stats().contacts, 0);
}

TEST(ProximityWorld, MarginsBringContactForward) {
  wp::ProximityWorld world;
  // Spheres of radius 0.5, 1 m apart surface to surface, margins 0.25 each: the inflated gap
  // is 0.5 m, closed at 1 m/s in 0.5 s.
  world.addBody(object("a", wp::Shape::sphere(0.5), 0.25), at({0, 0, 0}, {1, 0, 0}));
  world.addBody(object("b", wp::Shape::sphere(0.5), 0.25), at({2, 0, 0}));
  const auto& events = world.predict(2.0);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_NEAR(events[0].distance, 0.5, 1e-6);
  EXPECT_LE(events[0].time_to_contact, 0.5);
  EXPECT_GE(events[0].time_to_contact, 0.5 - 1e-3);
}

TEST(ProximityWorld, RobotRobotPairsAreSkippedUnlessARuleAllowsThem) {
  wp::ProximityWorld world;
  wp::BodyDesc l1{"link1", "robot", wp::BodyGroup::kRobot, kCube, 0.0};
  wp::BodyDesc l2{"link2", "robot", wp::BodyGroup::kRobot, kCube, 0.0};
  world.addBody(l1, at({0, 0, 0}));
  world.addBody(l2, at({0.5, 0, 0}));
  EXPECT_TRUE(world.predict(1.0).empty());
  wp::PairRules rules;
  rules.add("id:link1", "id:link2", true);
  world.setRules(rules);
  EXPECT_EQ(world.predict(1.0).size(), 1u);
}

TEST(ProximityWorld, BeginOngoingEndAsBodiesMoveApart) {
  wp::ProximityWorld world;
  const wp::BodyHandle a = world.addBody(object("a", kCube), at({0, 0, 0}));
  world.addBody(object("b", kCube), at({0.9, 0, 0}));
  ASSERT_EQ(world.predict(1.0).size(), 1u);
  EXPECT_EQ(world.predict(1.0)[0].state, wp::ContactState::kOngoing);
  EXPECT_EQ(world.predict(1.0)[0].time_to_contact, 0.0);
  world.setMotion(a, at({-5, 0, 0}));
  const auto& events = world.predict(1.0);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].state, wp::ContactState::kEnd);
  EXPECT_TRUE(world.predict(1.0).empty());
}

TEST(ProximityWorld, RemovedBodyEndsItsPairsAndStaysNameableForOneCycle) {
  wp::ProximityWorld world;
  const wp::BodyHandle a = world.addBody(object("a", kCube), at({0, 0, 0}));
  world.addBody(object("b", kCube), at({0.9, 0, 0}));
  ASSERT_EQ(world.predict(1.0).size(), 1u);
  world.removeBody(a);
  const auto& events = world.predict(1.0);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].state, wp::ContactState::kEnd);
  EXPECT_EQ(world.desc(events[0].body_a).id, "a");
  world.predict(1.0);
  EXPECT_FALSE(world.contains(a));
  EXPECT_THROW(world.desc(a), std::invalid_argument);
  // The slot is reused with a new generation: the old handle stays stale.
  const wp::BodyHandle c = world.addBody(object("c", kCube), at({0.9, 0, 0}));
  EXPECT_NE(c, a);
  EXPECT_FALSE(world.contains(a));
}

TEST(ProximityWorld, ZeroHorizonReportsOnlyWhatTouchesNow) {
  wp::ProximityWorld world;
  world.addBody(object("a", kCube), at({0, 0, 0}, {10, 0, 0}));
  world.addBody(object("b", kCube), at({1.0, 0, 0}));  // faces touch exactly
  world.addBody(object("c", kCube), at({0, 1.5, 0}, {0, -10, 0}));
  const auto& events = world.predict(0.0);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(world.desc(events[0].body_b).id, "b");
  EXPECT_EQ(events[0].time_to_contact, 0.0);
}

TEST(ProximityWorld, EventsAreOrderedEarliestFirst) {
  wp::ProximityWorld world;
  world.addBody(object("r", kCube), at({0, 0, 0}));
  // Approaching from three directions, arriving at 1.5 s, 0.5 s and 1.0 s.
  world.addBody(object("x", kCube), at({2.5, 0, 0}, {-1, 0, 0}));
  world.addBody(object("y", kCube), at({0, 1.5, 0}, {0, -1, 0}));
  world.addBody(object("z", kCube), at({0, 0, 2.0}, {0, 0, -1}));
  const auto& events = world.predict(3.0);
  for (std::size_t i = 1; i < events.size(); ++i) {
    EXPECT_LE(events[i - 1].time_to_contact, events[i].time_to_contact);
  }
  // x, y and z also meet each other near the origin; r's own contacts come in this order.
  std::vector<std::string> order;
  for (const auto& e : events) {
    if (world.desc(e.body_a).id == "r") order.push_back(world.desc(e.body_b).id);
  }
  EXPECT_EQ(order, (std::vector<std::string>{"y", "z", "x"}));
}

TEST(ProximityWorld, IdsOrderTheBodiesOfAnEventAndTheNormalFollows) {
  wp::ProximityWorld world;
  world.addBody(object("zeta", kCube), at({0, 0, 0}));
  world.addBody(object("alpha", kCube), at({2, 0, 0}, {-1, 0, 0}));
  const auto& events = world.predict(2.0);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(world.desc(events[0].body_a).id, "alpha");
  EXPECT_NEAR(events[0].normal.x(), -1.0, 1e-6);  // from alpha (at x=2) towards zeta
  EXPECT_NEAR(events[0].point_a.x(), 1.5, 1e-6);
  EXPECT_NEAR(events[0].closing_speed, 1.0, 1e-6);
}

TEST(ProximityWorld, EveryShapeTypeMeetsABox) {
  const wp::Shape shapes[] = {wp::Shape::sphere(0.4), wp::Shape::cylinder(0.3, 1.0),
                              wp::Shape::capsule(0.25, 0.8), wp::Shape::box({0.3, 0.2, 0.1})};
  // Each shape's x extent: the gap to the cube's face at x = 2.5 is known exactly.
  const double half_x[] = {0.4, 0.3, 0.25, 0.3};
  for (int i = 0; i < 4; ++i) {
    wp::ProximityWorld world;
    world.addBody(object("s", shapes[i]), at({0, 0, 0}, {1, 0, 0}));
    world.addBody(object("t", kCube), at({3, 0, 0}));
    const auto& events = world.predict(5.0);
    ASSERT_EQ(events.size(), 1u) << i;
    const double gap = 2.5 - half_x[i];
    EXPECT_NEAR(events[0].distance, gap, 1e-5) << i;
    EXPECT_LE(events[0].time_to_contact, gap + 1e-9) << i;
    EXPECT_GE(events[0].time_to_contact, gap - 1e-3) << i;
  }
}

TEST(ProximityWorld, InvalidInputIsRejectedWithAnException) {
  wp::ProximityWorld world;
  EXPECT_THROW(world.addBody(object("", kCube), at({0, 0, 0})), std::invalid_argument);
  EXPECT_THROW(world.addBody(object("a", wp::Shape::box({0.5, -1, 0.5})), at({0, 0, 0})),
               std::invalid_argument);
  EXPECT_THROW(world.addBody(object("a", wp::Shape::sphere(0)), at({0, 0, 0})),
               std::invalid_argument);
  EXPECT_THROW(world.addBody(object("a", kCube, -0.1), at({0, 0, 0})), std::invalid_argument);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(world.addBody(object("a", kCube), at({nan, 0, 0})), std::invalid_argument);
  wp::BodyMotion bad_q = at({0, 0, 0});
  bad_q.orientation = Eigen::Quaterniond(2, 0, 0, 0);
  EXPECT_THROW(world.addBody(object("a", kCube), bad_q), std::invalid_argument);
  const wp::BodyHandle ok = world.addBody(object("a", kCube), at({0, 0, 0}));
  EXPECT_THROW(world.setMotion(ok, at({0, 0, 0}, {nan, 0, 0})), std::invalid_argument);
  EXPECT_THROW(world.predict(-1.0), std::invalid_argument);
  EXPECT_THROW(world.predict(std::numeric_limits<double>::infinity()), std::invalid_argument);
  EXPECT_THROW(world.setMotion(wp::BodyHandle{42, 0}, at({0, 0, 0})), std::invalid_argument);
  EXPECT_EQ(world.bodyCount(), 1);
  EXPECT_TRUE(world.predict(1.0).empty());
}

// Found by fuzzing: a body rejected for out-of-range numbers must leave no trace, and
// degenerate shapes FCL cannot handle must be rejected or mapped, never reach FCL.
TEST(ProximityWorld, RejectedBodiesLeaveNoTraceAndLimitsHold) {
  wp::ProximityWorld world;
  EXPECT_THROW(world.addBody(object("huge_margin", wp::Shape::sphere(1.0), 1e308), at({1e6, 0, 0})),
               std::invalid_argument);
  EXPECT_THROW(world.addBody(object("far", kCube), at({1e308, 0, 0})), std::invalid_argument);
  EXPECT_THROW(world.addBody(object("fast", kCube), at({0, 0, 0}, {1e300, 0, 0})),
               std::invalid_argument);
  EXPECT_THROW(world.addBody(object("denormal", wp::Shape::box({std::numeric_limits<double>::denorm_min(), 1, 1})), at({0, 0, 0})),
               std::invalid_argument);
  EXPECT_THROW(world.addBody(object("enormous", wp::Shape::box({1e15, 1, 1})), at({0, 0, 0})),
               std::invalid_argument);
  EXPECT_EQ(world.bodyCount(), 0);
  EXPECT_FALSE(world.contains(wp::BodyHandle{0, 0}));
  EXPECT_THROW(world.predict(1e300), std::invalid_argument);
  EXPECT_TRUE(world.predict(1.0).empty());

  // The fuzzer's abort: a zero-length capsule (a sphere) against a long thin cylinder.
  world.addBody(object("capsule", wp::Shape::capsule(0.0625, 0.0), 0.0996),
                at({0.125, 0, 0}, {0.5, 0, 0}));
  wp::BodyMotion cyl = at({0.25, 0, 0});
  cyl.orientation = Eigen::Quaterniond(0.99969, 0, 0, 0.02499).normalized();
  world.addBody(object("cylinder", wp::Shape::cylinder(0.0625, 6.3125)), cyl);
  const auto& events = world.predict(1.0);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].time_to_contact, 0.0);
}

// Random churn: bodies appear, move and vanish. Every END must follow a BEGIN/ONGOING of the
// same pair in the previous cycle, every BEGIN must be new, and every event carries the pair
// number its BEGIN gave it.
TEST(ProximityWorld, EventsStayConsistentUnderChurn) {
  wp::ProximityWorld world;
  wp_test::Rng rng(3);
  std::uniform_real_distribution<double> pos(-4, 4), vel(-2, 2);
  std::vector<wp::BodyHandle> live;
  std::set<std::pair<std::string, std::string>> active;
  std::map<std::pair<std::string, std::string>, std::int32_t> number;  // of the active pairs
  int id = 0;
  for (int cycle = 0; cycle < 300; ++cycle) {
    const int adds = static_cast<int>(rng() % 4);
    for (int i = 0; i < adds; ++i) {
      live.push_back(world.addBody(object("b" + std::to_string(id++), kCube),
                                   at({pos(rng), pos(rng), pos(rng)}, {vel(rng), vel(rng), 0})));
    }
    if (!live.empty() && rng() % 2) {
      const std::size_t k = rng() % live.size();
      world.removeBody(live[k]);
      live.erase(live.begin() + static_cast<long>(k));
    }
    for (const wp::BodyHandle& h : live) {
      wp::BodyMotion m = world.motion(h);
      m.position += m.linear_velocity * 0.1;
      if (m.position.cwiseAbs().maxCoeff() > 5) m.linear_velocity = -m.linear_velocity;
      world.setMotion(h, m);
    }
    const auto& events = world.predict(1.0);
    std::set<std::pair<std::string, std::string>> now;
    std::set<std::int32_t> numbers_now;
    for (const auto& e : events) {
      const auto pair = std::make_pair(world.desc(e.body_a).id, world.desc(e.body_b).id);
      ASSERT_LT(pair.first, pair.second);
      // A pair keeps its number from BEGIN to END; no two events of a cycle share one.
      ASSERT_GE(e.pair, 0);
      ASSERT_TRUE(numbers_now.insert(e.pair).second) << "pair number shared in one cycle";
      if (e.state == wp::ContactState::kBegin) {
        number[pair] = e.pair;
      } else {
        ASSERT_EQ(number.at(pair), e.pair) << "pair number changed";
      }
      if (e.state == wp::ContactState::kEnd) {
        ASSERT_TRUE(active.count(pair)) << "END without a prior contact";
      } else {
        ASSERT_EQ(e.state == wp::ContactState::kBegin, active.count(pair) == 0);
        ASSERT_GE(e.time_to_contact, 0.0);
        ASSERT_LE(e.time_to_contact, e.time_to_separation);
        ASSERT_LE(e.time_to_separation, 1.0);
        now.insert(pair);
      }
    }
    for (const auto& pair : active) {
      if (!now.count(pair)) {
        bool ended = false;
        for (const auto& e : events) {
          ended |= e.state == wp::ContactState::kEnd && world.desc(e.body_a).id == pair.first &&
                   world.desc(e.body_b).id == pair.second;
        }
        ASSERT_TRUE(ended) << "pair vanished without END";
      }
    }
    active = now;
  }
}

// The per-pair stages on several threads (WorldConfig::pair_threads) report exactly what one
// thread reports: the same events in the same order, bit for bit, with the same pair numbers
// and counts. A robot cell with every kind of pair: links on keyframed paths (the piecewise
// stages), objects whose margins grow from the middle on, upright boxes against upright boxes (the
// closed form) and against turning links (FCL), pairs beginning and ending all along, and
// objects removed and added again (slots reused).
TEST(ProximityWorld, PairThreadsReportExactlyWhatOneThreadReports) {
  struct Run {
    explicit Run(int threads) : world(config(threads)), cell(&world, 24, 160, 5) {}
    static wp::WorldConfig config(int threads) {
      wp::WorldConfig c;
      c.pair_threads = threads;
      c.parallel_pairs = 1;  // every cycle in parallel, in chunks of 16 pairs or more
      return c;
    }
    wp::ProximityWorld world;
    wp_test::RobotCell cell;
  };
  Run one(1), two(2), three(3);
  Run* runs[] = {&one, &two, &three};
  wp::MarginGrowth growth;
  growth.velocity_error = 0.1;
  growth.max_accel = 0.4;
  growth.speed_cap = 0.3;
  int events = 0, parallel_cycles = 0;
  for (int k = 0; k < 150; ++k) {
    for (Run* r : runs) {
      if (k == 40) r->cell.setKeyframes(6, 2.0);
      if (k == 90) r->cell.setObjectGrowth(growth);
      if (k % 40 == 20) {  // an object leaves and comes back under a new handle
        const wp::BodyHandle h = r->cell.object(k % 7);
        const wp::BodyDesc desc = r->world.desc(h);
        const wp::BodyMotion motion = r->world.motion(h);
        r->world.removeBody(h);
        r->world.predict(2.0);
        r->cell.replaceObject(k % 7, r->world.addBody(desc, motion));
      }
      r->cell.step(k / 30.0, 1.0 / 30.0);
    }
    const std::vector<wp::PairEvent> expected = one.world.predict(2.0);
    events += static_cast<int>(expected.size());
    parallel_cycles += one.world.stats().broad_pairs > 64;  // several chunks
    for (Run* r : {&two, &three}) {
      const std::vector<wp::PairEvent>& got = r->world.predict(2.0);
      ASSERT_EQ(got.size(), expected.size()) << "cycle " << k;
      for (std::size_t i = 0; i < got.size(); ++i) {
        const wp::PairEvent& e = expected[i];
        const wp::PairEvent& g = got[i];
        ASSERT_EQ(g.body_a.index, e.body_a.index) << "cycle " << k << " event " << i;
        ASSERT_EQ(g.body_b.index, e.body_b.index);
        ASSERT_EQ(g.state, e.state);
        ASSERT_EQ(g.pair, e.pair);
        // Bit for bit: the same arithmetic on the same inputs, whichever thread did it.
        ASSERT_EQ(g.time_to_contact, e.time_to_contact);
        ASSERT_EQ(g.time_to_separation, e.time_to_separation);
        ASSERT_EQ(g.distance, e.distance);
        ASSERT_EQ(g.closing_speed, e.closing_speed);
        ASSERT_TRUE(g.point_a == e.point_a && g.point_b == e.point_b && g.normal == e.normal);
      }
      const wp::WorldStats& s1 = one.world.stats();
      const wp::WorldStats& sn = r->world.stats();
      ASSERT_EQ(sn.broad_pairs, s1.broad_pairs);
      ASSERT_EQ(sn.allowed_pairs, s1.allowed_pairs);
      ASSERT_EQ(sn.axis_candidates, s1.axis_candidates);
      ASSERT_EQ(sn.contacts, s1.contacts);
      ASSERT_EQ(sn.narrow_iterations, s1.narrow_iterations);
    }
  }
  EXPECT_GT(events, 3000);
  EXPECT_GT(parallel_cycles, 120);
}

TEST(ProximityWorld, PairThreadsOutsideTheirRangeAreRejected) {
  for (const int threads : {0, -1, wp::WorldConfig::kMaxPairThreads + 1}) {
    wp::WorldConfig c;
    c.pair_threads = threads;
    EXPECT_THROW(wp::ProximityWorld world(c), std::invalid_argument) << threads;
  }
  wp::WorldConfig c;
  c.parallel_pairs = 0;
  EXPECT_THROW(wp::ProximityWorld world(c), std::invalid_argument);
  c.parallel_pairs = 1;
  c.pair_threads = wp::WorldConfig::kMaxPairThreads;
  EXPECT_NO_THROW(wp::ProximityWorld world(c));
}

// What a world keeps between cycles (each body's pose and the rotation it was built from, the
// pairs' naming order, the events' last order) must not change any answer: a world that
// lives through the cycles and one built afresh from the same bodies every cycle give the
// same contacts (up to the rounding of which body the narrow phase sees first). Orientations stay put for some cycles and turn in others, some
// bodies spin, and removed bodies' slots are reused by new ones.
TEST(ProximityWorld, AnswersEqualAFreshWorldsAsOrientationsStayAndChange) {
  wp::ProximityWorld world;
  wp_test::Rng rng(21);
  std::uniform_real_distribution<double> pos(-3, 3), vel(-1.5, 1.5), yaw(-M_PI, M_PI);
  struct Body {
    wp::BodyDesc desc;
    wp::BodyMotion motion;
    wp::BodyHandle handle;
  };
  std::vector<Body> bodies;
  int id = 0;
  auto turned = [&](double angle) {
    return Eigen::Quaterniond(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()));
  };
  std::size_t contacts = 0;
  for (int cycle = 0; cycle < 200; ++cycle) {
    const int adds = cycle == 0 ? 12 : static_cast<int>(rng() % 3);
    for (int i = 0; i < adds; ++i) {
      Body b;
      ++id;
      b.desc = object("b" + std::to_string(id - 1), wp::Shape::box({0.4, 0.3, 0.9}), 0.05 * (id % 3));
      b.motion = at({pos(rng), pos(rng), 0.0}, {vel(rng), vel(rng), 0.0});
      b.motion.orientation = turned(yaw(rng));
      if (id % 5 == 0) b.motion.angular_velocity = Eigen::Vector3d(0, 0, 0.7);
      b.handle = world.addBody(b.desc, b.motion);
      bodies.push_back(b);
    }
    if (bodies.size() > 4 && rng() % 3 == 0) {
      const std::size_t k = rng() % bodies.size();
      world.removeBody(bodies[k].handle);
      bodies.erase(bodies.begin() + static_cast<long>(k));
    }
    for (Body& b : bodies) {
      b.motion.position += b.motion.linear_velocity / 30.0;
      if (b.motion.position.head<2>().cwiseAbs().maxCoeff() > 3.5) b.motion.linear_velocity *= -1.0;
      if (rng() % 4 == 0) b.motion.orientation = turned(yaw(rng));  // else it stays as it was
      world.setMotion(b.handle, b.motion);
    }
    wp::ProximityWorld fresh;
    for (const Body& b : bodies) fresh.addBody(b.desc, b.motion);
    const auto& kept_events = world.predict(2.0);
    const auto& fresh_events = fresh.predict(2.0);
    auto contactsOf = [](const wp::ProximityWorld& w, const std::vector<wp::PairEvent>& events) {
      std::map<std::pair<std::string, std::string>, std::vector<double>> out;
      for (const wp::PairEvent& e : events) {
        if (e.state == wp::ContactState::kEnd) continue;
        out[{w.desc(e.body_a).id, w.desc(e.body_b).id}] = {
            e.time_to_contact, e.time_to_separation, e.distance, e.point_a.x(), e.point_a.y(),
            e.point_b.x(), e.point_b.y(), e.normal.x(), e.normal.y(), e.closing_speed};
      }
      return out;
    };
    const auto kept = contactsOf(world, kept_events);
    const auto anew = contactsOf(fresh, fresh_events);
    ASSERT_EQ(kept.size(), anew.size()) << "cycle " << cycle;
    for (const auto& kv : kept) {
      ASSERT_EQ(anew.count(kv.first), 1u) << kv.first.first << " " << kv.first.second;
      // Within rounding: the two worlds may hand a pair's bodies to the narrow phase in either
      // order, and a contact point computed from b's side differs from a's in the last bits.
      for (std::size_t q = 0; q < kv.second.size(); ++q) {
        ASSERT_NEAR(kv.second[q], anew.at(kv.first)[q], 1e-9)
            << "cycle " << cycle << ", " << kv.first.first << " " << kv.first.second << ", field " << q;
      }
    }
    contacts += kept.size();
  }
  EXPECT_GT(contacts, 200u);
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
