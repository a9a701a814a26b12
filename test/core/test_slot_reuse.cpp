// A body added into a freed slot behaves as one added to a fresh world: the slot's last body
// (its reach, growing margin, path, shape and margin, pairs and events) leaves nothing behind.
// The oracle is a second world without that history, fed the same bodies: the same pairs
// within reach and contact events (by ids), the same swept bounds, reach, growth and path.
// (fuzz_world found a reach kept across reuse; this test asks it of every per-body setting.)

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "random.hpp"
#include "workspace_proximity/motion_path.hpp"
#include "workspace_proximity/proximity_world.hpp"

namespace wp = workspace_proximity;

namespace {

constexpr double kHorizon = 1.5;  // s

wp::BodyMotion randomMotion(wp_test::Rng& rng) {
  wp::BodyMotion m;
  m.position = rng.vector(-3.0, 3.0);
  m.orientation = rng.chance(0.5) ? rng.yaw() : rng.rotation();
  m.linear_velocity = rng.chance(0.7) ? rng.vector(-1.5, 1.5) : Eigen::Vector3d::Zero();
  if (rng.chance(0.3)) m.angular_velocity = rng.vector(-1.0, 1.0);
  return m;
}

wp::Shape randomShape(wp_test::Rng& rng) {
  switch (rng.integer(0, 2)) {
    case 0:
      return wp::Shape::box(rng.vector(0.05, 0.6));
    case 1:
      return wp::Shape::sphere(rng.uniform(0.05, 0.5));
    default:
      return wp::Shape::capsule(rng.uniform(0.05, 0.3), rng.uniform(0.1, 1.0));
  }
}

// Whatever a body can carry: a reach, a growing margin, a path of a few segments, a new
// shape and margin; and pairs (it starts among the others).
void giveEverything(wp_test::Rng& rng, wp::ProximityWorld* w, wp::BodyHandle h) {
  w->setReach(h, rng.uniform(0.5, 3.0));
  wp::MarginGrowth g;
  g.velocity_error = rng.uniform(0.1, 1.0);
  g.max_accel = rng.uniform(0.5, 3.0);
  g.age = rng.uniform(0.0, 0.2);
  w->setGrowth(h, g);
  std::vector<wp::MotionSegment> path(3);
  for (int s = 0; s < 3; ++s) {
    path[s].start = 0.4 * s;
    path[s].motion = randomMotion(rng);
    path[s].margin = rng.uniform(0.0, 0.3);
  }
  w->setPath(h, path.data(), static_cast<int>(path.size()));
  if (rng.chance(0.5)) w->setShape(h, randomShape(rng), rng.uniform(0.0, 0.2));
}

using IdPair = std::pair<std::string, std::string>;

IdPair idsOf(const wp::ProximityWorld& w, wp::BodyHandle a, wp::BodyHandle b) {
  std::string x = w.desc(a).id, y = w.desc(b).id;
  if (y < x) std::swap(x, y);
  return {x, y};
}

struct EventSeen {
  int state;
  double ttc, tts, distance;
};

std::map<IdPair, EventSeen> eventsById(const wp::ProximityWorld& w, const std::vector<wp::PairEvent>& events) {
  std::map<IdPair, EventSeen> out;
  for (const wp::PairEvent& e : events) {
    const bool inserted = out.emplace(idsOf(w, e.body_a, e.body_b),
                                      EventSeen{static_cast<int>(e.state), e.time_to_contact,
                                                e.time_to_separation, e.distance})
                              .second;
    EXPECT_TRUE(inserted) << "a pair reported twice";
  }
  return out;
}

std::map<IdPair, double> nearById(const wp::ProximityWorld& w) {
  std::map<IdPair, double> out;
  for (const wp::NearPair& p : w.nearPairs()) out.emplace(idsOf(w, p.body_a, p.body_b), p.distance);
  return out;
}

// Times or distances alike: both infinite, or within `tol`.
bool near(double a, double b, double tol) { return a == b || std::abs(a - b) <= tol; }

// The per-pair stages name a pair by the broad phase's proxy order, which differs between
// the worlds, and FCL's distance is iterative: times and distances are compared to 1e-6 (the
// narrow phase's arguments swapped gave 2e-9), the pairs and states exactly; but a pair of
// two bodies `used` had before the new ones came is ONGOING there and BEGINs in `fresh` at
// the first round.
bool bothOld(const IdPair& p) { return p.first.rfind("old", 0) == 0 && p.second.rfind("old", 0) == 0; }

void expectSame(std::map<IdPair, EventSeen> a, const std::map<IdPair, EventSeen>& b, int round) {
  // (and may END there at the first round, having never begun in `fresh`)
  if (round == 0) {
    for (auto i = a.begin(); i != a.end();) {
      i = bothOld(i->first) && i->second.state == static_cast<int>(wp::ContactState::kEnd) ? a.erase(i) : std::next(i);
    }
  }
  for (const auto& e : a) {
    if (b.count(e.first) == 0) ADD_FAILURE() << "only in used: " << e.first.first << "-" << e.first.second << " state " << e.second.state << " round " << round;
  }
  for (const auto& e : b) {
    if (a.count(e.first) == 0) ADD_FAILURE() << "only in fresh: " << e.first.first << "-" << e.first.second << " state " << e.second.state << " round " << round;
  }
  ASSERT_EQ(a.size(), b.size()) << "round " << round;
  auto j = b.begin();
  for (auto i = a.begin(); i != a.end(); ++i, ++j) {
    ASSERT_EQ(i->first, j->first) << "round " << round;
    const std::string where = i->first.first + "-" + i->first.second + " round " + std::to_string(round);
    if (round > 0 || !bothOld(i->first)) {
      EXPECT_EQ(i->second.state, j->second.state) << where;
    }
    EXPECT_TRUE(near(i->second.ttc, j->second.ttc, 1e-6)) << where << " " << i->second.ttc << " " << j->second.ttc;
    EXPECT_TRUE(near(i->second.tts, j->second.tts, 1e-6)) << where << " " << i->second.tts << " " << j->second.tts;
    EXPECT_TRUE(near(i->second.distance, j->second.distance, 1e-6)) << where;
  }
}

}  // namespace

TEST(SlotReuse, ABodyInAFreedSlotIsABodyInAFreshWorld) {
  wp_test::Rng rng(20261128);
  int reused_total = 0;
  for (int trial = 0; trial < 40; ++trial) {
    wp::ProximityWorld used;
    wp::ProximityWorld fresh;
    // The history: bodies with everything, predicted a few times, then removed; two predicts
    // later their slots are free.
    std::vector<wp::BodyHandle> old;
    const int n_old = rng.integer(4, 24);
    for (int i = 0; i < n_old; ++i) {
      const wp::BodyGroup group = rng.chance(0.3) ? wp::BodyGroup::kRobot : wp::BodyGroup::kObject;
      old.push_back(used.addBody({"old" + std::to_string(i), "thing", group, randomShape(rng), rng.uniform(0.0, 0.1)},
                                 randomMotion(rng)));
      giveEverything(rng, &used, old.back());
    }
    used.predict(kHorizon);
    used.predict(kHorizon);
    std::vector<wp::BodyHandle> kept;
    for (const wp::BodyHandle h : old) {
      if (rng.chance(0.25)) {
        kept.push_back(h);
      } else {
        used.removeBody(h);
      }
    }
    used.predict(kHorizon);  // END events of the removed
    used.predict(kHorizon);  // and their slots free after it
    // The ones kept live on in `used`; `fresh` gets the same, without the history.
    for (const wp::BodyHandle h : kept) {
      wp::BodyHandle f = fresh.addBody(used.desc(h), used.motion(h));
      fresh.setReach(f, used.reach(h));
      fresh.setGrowth(f, used.growth(h));
      // (used's path: its segments as prepared; a constant twist in both is enough here)
      used.setMotion(h, used.motion(h));
      fresh.setMotion(f, used.motion(h));
    }
    // The new bodies: plain (no reach, growth or path), some of the robot's with a reach
    // given afterwards in both worlds.
    std::vector<std::pair<wp::BodyHandle, wp::BodyHandle>> pairs;
    const int n_new = rng.integer(4, 24);
    for (int i = 0; i < n_new; ++i) {
      const bool robot = rng.chance(0.2);
      const wp::BodyDesc desc{"new" + std::to_string(i), "thing", robot ? wp::BodyGroup::kRobot : wp::BodyGroup::kObject,
                              randomShape(rng), rng.uniform(0.0, 0.1)};
      const wp::BodyMotion m = randomMotion(rng);
      const wp::BodyHandle u = used.addBody(desc, m);
      const wp::BodyHandle f = fresh.addBody(desc, m);
      for (const wp::BodyHandle h : old) reused_total += h.index == u.index;
      if (robot) {
        const double reach = rng.uniform(0.5, 2.0);
        used.setReach(u, reach);
        fresh.setReach(f, reach);
      }
      pairs.emplace_back(u, f);
    }
    for (int round = 0; round < 4; ++round) {
      for (const auto& p : pairs) {
        EXPECT_EQ(used.reach(p.first), fresh.reach(p.second));
        EXPECT_TRUE(used.growth(p.first).none());
      }
      const std::map<IdPair, EventSeen> eu = eventsById(used, used.predict(kHorizon));
      const std::map<IdPair, EventSeen> ef = eventsById(fresh, fresh.predict(kHorizon));
      expectSame(eu, ef, round);
      const std::map<IdPair, double> nu = nearById(used), nf = nearById(fresh);
      EXPECT_EQ(nu.size(), nf.size()) << "round " << round;
      for (auto i = nu.begin(), j = nf.begin(); i != nu.end() && j != nf.end(); ++i, ++j) {
        ASSERT_EQ(i->first, j->first);
        EXPECT_NEAR(i->second, j->second, 1e-6);
      }
      for (const auto& p : pairs) {
        EXPECT_EQ(used.pathSize(p.first), 0);
        const wp::Aabb a = used.sweptBounds(p.first), b = fresh.sweptBounds(p.second);
        EXPECT_EQ(a.lower, b.lower);
        EXPECT_EQ(a.upper, b.upper);
      }
      for (const auto& p : pairs) {  // every body moves on
        const wp::BodyMotion m = randomMotion(rng);
        used.setMotion(p.first, m);
        fresh.setMotion(p.second, m);
      }
    }
    if (HasFatalFailure() || HasFailure()) {
      ADD_FAILURE() << "trial " << trial;
      return;
    }
  }
  EXPECT_GT(reused_total, 200) << "the test needs the freed slots reused";
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
