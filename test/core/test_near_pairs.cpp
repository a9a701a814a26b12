// Pairs within reach (ProximityWorld::setReach / nearPairs): every allowed pair whose bare
// shapes are at most reach_a + reach_b apart now is reported, and no other, with the distance
// and nearest points of an independent box-distance oracle, already after predictNear (before
// the events are predicted); a reach changes nothing else (events, swept bounds); predict in two
// halves (predictNear, predictEvents) gives what predict gives.

#include <gtest/gtest.h>

#include <map>
#include <set>
#include <stdexcept>
#include <utility>
#include <vector>

#include "oracles.hpp"
#include "random.hpp"
#include "workspace_proximity/proximity_world.hpp"

namespace wp = workspace_proximity;

namespace {

struct Body {
  wp::BodyHandle handle;
  bool robot = false;
  double reach = 0.0;
  Eigen::Vector3d half;
  wp::BodyMotion motion;
};

oracle::Obb obbOf(const Body& b) {
  return oracle::Obb{oracle::makePose(b.motion.position, b.motion.orientation), b.half};
}

double oracleDistance(const Body& a, const Body& b) {
  const oracle::Obb oa = obbOf(a), ob = obbOf(b);
  return oracle::overlaps(oa, ob) ? 0.0 : oracle::boxBoxDistance(oa, ob);
}

wp::BodyMotion randomMotion(wp_test::Rng& rng, double extent) {
  wp::BodyMotion m;
  m.position = rng.vector(-extent, extent);
  m.orientation = rng.chance(0.5) ? rng.yaw() : rng.rotation();
  m.linear_velocity = rng.chance(0.7) ? rng.vector(-2.0, 2.0) : Eigen::Vector3d::Zero();
  if (rng.chance(0.3)) m.angular_velocity = rng.vector(-1.0, 1.0);
  return m;
}

using TwinHandles = std::vector<std::pair<wp::BodyHandle, wp::BodyHandle>>;

// Each body of twin worlds `a` and `b` (handles in `handles`) moves to a new random motion, the
// same in both.
void moveTwins(wp_test::Rng& rng, wp::ProximityWorld* a, wp::ProximityWorld* b,
               const TwinHandles& handles) {
  for (const auto& h : handles) {
    const wp::BodyMotion m = randomMotion(rng, 4.0);
    a->setMotion(h.first, m);
    b->setMotion(h.second, m);
  }
}

// Twin worlds' events are the same, in the same order: the pair (by ids), state, times and
// distance to the bit.
void expectSameEvents(const wp::ProximityWorld& wa, const std::vector<wp::PairEvent>& a,
                      const wp::ProximityWorld& wb, const std::vector<wp::PairEvent>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(wa.desc(a[i].body_a).id, wb.desc(b[i].body_a).id);
    EXPECT_EQ(wa.desc(a[i].body_b).id, wb.desc(b[i].body_b).id);
    EXPECT_EQ(a[i].state, b[i].state);
    EXPECT_EQ(a[i].time_to_contact, b[i].time_to_contact);
    EXPECT_EQ(a[i].time_to_separation, b[i].time_to_separation);
    EXPECT_EQ(a[i].distance, b[i].distance);
  }
}

}  // namespace

TEST(NearPairs, EveryAllowedPairWithinReachAndNoOtherAgainstTheBoxOracle) {
  wp_test::Rng rng(11);
  int reported = 0, checked_far = 0, overlapping = 0;
  for (int scene = 0; scene < 40; ++scene) {
    wp::ProximityWorld world;  // default rules: robot-robot pairs skipped
    std::vector<Body> bodies;
    const int n = rng.integer(4, 30);
    const double extent = rng.uniform(1.0, 6.0);
    for (int i = 0; i < n; ++i) {
      Body b;
      b.robot = rng.chance(0.3);
      b.half = rng.vector(0.05, 0.8);
      b.motion = randomMotion(rng, extent);
      // Margins must not matter: the distance is between the bare shapes.
      b.handle = world.addBody({"b" + std::to_string(i), b.robot ? "robot" : "thing",
                                b.robot ? wp::BodyGroup::kRobot : wp::BodyGroup::kObject,
                                wp::Shape::box(b.half), rng.uniform(0.0, 0.3)},
                               b.motion);
      bodies.push_back(b);
    }
    for (int cycle = 0; cycle < 6; ++cycle) {
      for (Body& b : bodies) {
        if (cycle > 0 && rng.chance(0.7)) {
          b.motion = randomMotion(rng, extent);
          world.setMotion(b.handle, b.motion);
        }
        if (rng.chance(0.5)) {
          b.reach = rng.chance(0.3) ? 0.0 : rng.uniform(0.0, 3.0);
          world.setReach(b.handle, b.reach);
        }
        ASSERT_EQ(world.reach(b.handle), b.reach);
      }
      // The first half only: the pairs within reach must be complete before the events.
      const std::vector<wp::NearPair> near =
          world.predictNear(rng.chance(0.2) ? 0.0 : rng.uniform(0.1, 3.0));
      std::map<std::pair<int, int>, const wp::NearPair*> got;
      for (const wp::NearPair& p : near) {
        const int a = p.body_a.index, b = p.body_b.index;
        ASSERT_TRUE(got.emplace(std::minmax(a, b), &p).second) << "pair reported twice";
      }
      EXPECT_EQ(world.stats().near_pairs, static_cast<int>(got.size()));
      // The second half leaves them as they were.
      world.predictEvents();
      ASSERT_EQ(world.nearPairs().size(), near.size());
      for (std::size_t k = 0; k < near.size(); ++k) {
        EXPECT_EQ(world.nearPairs()[k].body_a, near[k].body_a);
        EXPECT_EQ(world.nearPairs()[k].body_b, near[k].body_b);
        EXPECT_EQ(world.nearPairs()[k].distance, near[k].distance);
      }
      for (int i = 0; i < n; ++i) {
        for (int j = i + 1; j < n; ++j) {
          const Body &a = bodies[i], &b = bodies[j];
          const double reach = a.reach + b.reach;
          const double d = oracleDistance(a, b);
          const auto it = got.find(std::minmax(a.handle.index, b.handle.index));
          const bool allowed = !(a.robot && b.robot);
          // Within 1e-7 m of the boundary either answer is right.
          if (!allowed || reach == 0.0 || d > reach + 1e-7) {
            EXPECT_TRUE(it == got.end()) << "pair " << i << "-" << j << " at " << d
                                         << " m reported with reach " << reach;
            ++checked_far;
            continue;
          }
          if (d < reach - 1e-7) {
            ASSERT_TRUE(it != got.end()) << "pair " << i << "-" << j << " at " << d
                                         << " m missing with reach " << reach;
          }
          if (it == got.end()) continue;
          ++reported;
          const wp::NearPair& p = *it->second;
          EXPECT_NEAR(p.distance, d, 1e-6);
          // Apart: the nearest points lie on their boxes and are the distance apart.
          const bool a_first = p.body_a == a.handle;
          const Body& pa = a_first ? a : b;
          const Body& pb = a_first ? b : a;
          EXPECT_NEAR(p.normal.norm(), 1.0, 1e-9);
          if (d > 1e-6) {
            EXPECT_LE(oracle::pointBoxDistance(p.point_a, obbOf(pa)), 1e-6) << d;
            EXPECT_LE(oracle::pointBoxDistance(p.point_b, obbOf(pb)), 1e-6) << d;
            EXPECT_NEAR((p.point_b - p.point_a).norm(), d, 1e-6);
            EXPECT_GT(p.normal.dot(p.point_b - p.point_a), 0.0);
          } else {
            ++overlapping;
          }
        }
      }
    }
  }
  EXPECT_GT(reported, 500);
  EXPECT_GT(checked_far, 500);
  EXPECT_GT(overlapping, 10);
}

TEST(NearPairs, AReachChangesNeitherTheEventsNorTheSweptBounds) {
  wp_test::Rng rng(5);
  wp::ProximityWorld plain, reaching;
  TwinHandles handles;
  for (int i = 0; i < 40; ++i) {
    const bool robot = i < 8;
    const wp::BodyDesc desc{"b" + std::to_string(i), robot ? "robot" : "thing",
                            robot ? wp::BodyGroup::kRobot : wp::BodyGroup::kObject,
                            wp::Shape::box(rng.vector(0.1, 0.5)), 0.05};
    const wp::BodyMotion m = randomMotion(rng, 4.0);
    handles.emplace_back(plain.addBody(desc, m), reaching.addBody(desc, m));
    if (robot) reaching.setReach(handles.back().second, 2.5);
  }
  int events = 0;
  for (int cycle = 0; cycle < 20; ++cycle) {
    moveTwins(rng, &plain, &reaching, handles);
    const std::vector<wp::PairEvent> a = plain.predict(2.0);
    const std::vector<wp::PairEvent>& b = reaching.predict(2.0);
    ASSERT_NO_FATAL_FAILURE(expectSameEvents(plain, a, reaching, b));
    events += static_cast<int>(a.size());
    for (const auto& h : handles) {
      EXPECT_EQ(plain.sweptBounds(h.first).lower, reaching.sweptBounds(h.second).lower);
      EXPECT_EQ(plain.sweptBounds(h.first).upper, reaching.sweptBounds(h.second).upper);
    }
    EXPECT_TRUE(plain.nearPairs().empty());
    EXPECT_GT(reaching.stats().broad_pairs, plain.stats().broad_pairs);
  }
  EXPECT_GT(events, 20);
}

TEST(NearPairs, PredictInTwoHalvesGivesPredictsPairsAndEvents) {
  // predictNear then predictEvents (the monitor's cycle: the speed and separation verdict
  // between them) against predict on a twin world: the same pairs within reach, distances and
  // nearest points, and the same events, cycle after cycle (adds and removals included).
  wp_test::Rng rng(17);
  wp::ProximityWorld whole, halves;
  TwinHandles handles;
  int serial = 0;
  auto add = [&](bool robot) {
    const wp::BodyDesc desc{"b" + std::to_string(serial++), robot ? "robot" : "thing",
                            robot ? wp::BodyGroup::kRobot : wp::BodyGroup::kObject,
                            wp::Shape::box(rng.vector(0.1, 0.6)), 0.05};
    const wp::BodyMotion m = randomMotion(rng, 4.0);
    handles.emplace_back(whole.addBody(desc, m), halves.addBody(desc, m));
    if (robot) {
      const double reach = rng.uniform(0.5, 3.0);
      whole.setReach(handles.back().first, reach);
      halves.setReach(handles.back().second, reach);
    }
  };
  for (int i = 0; i < 50; ++i) add(i < 6);
  int events = 0, near = 0;
  for (int cycle = 0; cycle < 30; ++cycle) {
    moveTwins(rng, &whole, &halves, handles);
    if (cycle % 5 == 4) {  // a few leave, a few come
      for (int k = 0; k < 3; ++k) {
        const std::size_t i = 6 + static_cast<std::size_t>(rng.integer(0, static_cast<int>(handles.size()) - 7));
        whole.removeBody(handles[i].first);
        halves.removeBody(handles[i].second);
        handles.erase(handles.begin() + static_cast<long>(i));
        add(false);
      }
    }
    const double horizon = rng.uniform(0.5, 2.5);
    const std::vector<wp::PairEvent> a = whole.predict(horizon);
    const std::vector<wp::NearPair> near_a = whole.nearPairs();
    const std::vector<wp::NearPair> near_b = halves.predictNear(horizon);
    const std::vector<wp::PairEvent>& b = halves.predictEvents();
    ASSERT_EQ(near_a.size(), near_b.size());
    for (std::size_t i = 0; i < near_a.size(); ++i) {
      EXPECT_EQ(whole.desc(near_a[i].body_a).id, halves.desc(near_b[i].body_a).id);
      EXPECT_EQ(whole.desc(near_a[i].body_b).id, halves.desc(near_b[i].body_b).id);
      EXPECT_EQ(near_a[i].distance, near_b[i].distance);
      EXPECT_EQ(near_a[i].point_a, near_b[i].point_a);
      EXPECT_EQ(near_a[i].point_b, near_b[i].point_b);
    }
    ASSERT_NO_FATAL_FAILURE(expectSameEvents(whole, a, halves, b));
    events += static_cast<int>(a.size());
    near += static_cast<int>(near_a.size());
  }
  EXPECT_GT(events, 50);
  EXPECT_GT(near, 50);
}

TEST(NearPairs, TheEventsHalfNeedsTheNearHalfFirst) {
  wp::ProximityWorld world;
  const wp::BodyHandle a = world.addBody(
      {"a", "thing", wp::BodyGroup::kObject, wp::Shape::box({0.5, 0.5, 0.5}), 0.0}, wp::BodyMotion());
  wp::BodyMotion m;
  m.position = Eigen::Vector3d(1.5, 0.0, 0.0);
  m.linear_velocity = Eigen::Vector3d(-1.0, 0.0, 0.0);
  world.addBody({"b", "thing", wp::BodyGroup::kObject, wp::Shape::box({0.5, 0.5, 0.5}), 0.0}, m);
  EXPECT_THROW(world.predictEvents(), std::logic_error);
  world.predictNear(2.0);
  ASSERT_EQ(world.predictEvents().size(), 1u);  // a BEGIN: they meet after 0.5 s
  EXPECT_THROW(world.predictEvents(), std::logic_error);  // once per predictNear
  // A predictNear whose events were never asked for: the next one predicts them first, so
  // the pair's history stays whole (ONGOING now, not a second BEGIN).
  world.predictNear(2.0);
  world.predictNear(2.0);
  const std::vector<wp::PairEvent>& events = world.predictEvents();
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].state, wp::ContactState::kOngoing);
  (void)a;
}

TEST(NearPairs, AnInvalidReachIsRefused) {
  wp::ProximityWorld world;
  const wp::BodyHandle h = world.addBody(
      {"a", "thing", wp::BodyGroup::kObject, wp::Shape::box({0.5, 0.5, 0.5}), 0.0}, wp::BodyMotion());
  EXPECT_THROW(world.setReach(h, -1.0), std::invalid_argument);
  EXPECT_THROW(world.setReach(h, std::nan("")), std::invalid_argument);
  EXPECT_THROW(world.setReach(h, 1e9), std::invalid_argument);
  world.setReach(h, 1.0);
  world.removeBody(h);
  EXPECT_THROW(world.setReach(h, 1.0), std::invalid_argument);
}

// A body added into a freed slot starts without a reach, whatever the slot's last body had:
// fuzz_world found a new body inheriting it (a near pair 1.19 m apart with no reach on either
// side). Its bounds in the broad phase are its own swept bounds, and no pair is near.
TEST(NearPairs, ABodyInAReusedSlotStartsWithoutAReach) {
  wp::ProximityWorld world;
  const wp::BodyHandle robot = world.addBody(
      {"link", "arm", wp::BodyGroup::kRobot, wp::Shape::box({0.25, 0.25, 0.25}), 0.0}, wp::BodyMotion());
  world.setReach(robot, 2.0);
  wp::BodyMotion far;
  far.position = Eigen::Vector3d(1.5, 0.0, 0.0);  // 1 m apart: within the old body's reach alone
  const wp::BodyHandle old = world.addBody(
      {"old", "thing", wp::BodyGroup::kObject, wp::Shape::box({0.25, 0.25, 0.25}), 0.0}, far);
  world.setReach(old, 1.0);
  world.predict(1.0);
  ASSERT_EQ(world.nearPairs().size(), 1u);
  world.setReach(robot, 0.0);
  world.removeBody(old);
  world.predict(1.0);  // "old" is nameable through this one (its END events)
  world.predict(1.0);  // and its slot is free after it
  const wp::BodyHandle reused = world.addBody(
      {"new", "thing", wp::BodyGroup::kObject, wp::Shape::box({0.25, 0.25, 0.25}), 0.0}, far);
  ASSERT_EQ(reused.index, old.index) << "the test needs the freed slot";
  EXPECT_EQ(world.reach(reused), 0.0);
  world.predict(1.0);
  EXPECT_TRUE(world.nearPairs().empty());
  EXPECT_EQ(world.stats().near_pairs, 0);
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
