// Safety: the pipeline never misses a contact that an exact check finds.
//
// Oracle: for every pair of oriented boxes in a random scene, step time over the horizon
// every millisecond and test overlap with the separating-axis theorem (oracles.hpp), written
// independently of the library. Every instant at which the oracle sees overlap must lie
// inside a predicted [time_to_contact, time_to_separation]. For translation-only scenes the
// predicted time to contact must also be within 1 ms of the exact first contact, found by
// bisecting the oracle, and never later.

#include <gtest/gtest.h>

#include <map>

#include "oracles.hpp"
#include "random.hpp"
#include "scenes.hpp"
#include "workspace_proximity/proximity_world.hpp"

namespace wp = workspace_proximity;

namespace {

using TestBody = wp_test::BoxBody;

oracle::Obb obbAt(const TestBody& b, double t) { return oracle::Obb{oracle::poseAt(b.motion, t), b.half}; }

struct Prediction {
  double first;
  double last;
};

// Runs `scenes` random scenes of `n` boxes; checks every pair against the sampled oracle.
// `upright`: boxes turned and spinning about z only, as trackers report people and vehicles
// (the narrow phase's closed-form path); otherwise any orientation and spin axis (FCL).
// `threads`: WorldConfig::pair_threads, in parallel from the first pair on.
void checkScenes(int scenes, int n, bool rotate, unsigned seed, int* contacts_checked,
                 bool upright = false, int threads = 1) {
  wp_test::Rng rng(seed);
  const double horizon = 1.0;
  const double dt = 1e-3;
  const int steps = static_cast<int>(horizon / dt);

  for (int scene = 0; scene < scenes; ++scene) {
    wp::WorldConfig config;
    config.rules = wp::PairRules::allowAll();
    config.pair_threads = threads;
    config.parallel_pairs = 1;
    wp::ProximityWorld world(config);
    std::vector<TestBody> bodies(n);
    for (int i = 0; i < n; ++i) {
      TestBody& b = bodies[i];
      b = wp_test::randomBoxBody(rng, rotate, upright);
      b.handle = world.addBody(
          wp::BodyDesc{"b" + std::to_string(i), "box", wp::BodyGroup::kObject,
                       wp::Shape::box(b.half), 0.0},
          b.motion);
    }

    // A few cycles per scene, so the incremental broad phase is exercised too.
    for (int cycle = 0; cycle < 3; ++cycle) {
      std::map<std::pair<int, int>, Prediction> predicted;
      for (const wp::PairEvent& e : world.predict(horizon)) {
        if (e.state == wp::ContactState::kEnd) continue;
        const int a = e.body_a.index, b = e.body_b.index;
        predicted[{std::min(a, b), std::max(a, b)}] = {e.time_to_contact, e.time_to_separation};
      }

      for (int i = 0; i < n; ++i) {
        for (int j = i + 1; j < n; ++j) {
          const int hi = bodies[i].handle.index, hj = bodies[j].handle.index;
          const auto it = predicted.find({std::min(hi, hj), std::max(hi, hj)});
          int first_step = -1;
          for (int s = 0; s <= steps; ++s) {
            const double t = s * dt;
            if (!oracle::overlaps(obbAt(bodies[i], t), obbAt(bodies[j], t))) continue;
            if (first_step < 0) first_step = s;
            ASSERT_NE(it, predicted.end())
                << "missed contact: scene " << scene << " cycle " << cycle << " pair " << i
                << "," << j << " overlapping at t=" << t;
            ASSERT_LE(it->second.first, t + 1e-9) << "contact predicted too late";
            ASSERT_GE(it->second.last, t - 1e-9) << "separation predicted too early";
          }
          if (first_step < 0) continue;
          ++*contacts_checked;
          if (!rotate && first_step > 0) {
            // Exact first contact by bisection between the last clear and first overlapping
            // samples.
            double lo = (first_step - 1) * dt, hi_t = first_step * dt;
            for (int k = 0; k < 60; ++k) {
              const double mid = 0.5 * (lo + hi_t);
              if (oracle::overlaps(obbAt(bodies[i], mid), obbAt(bodies[j], mid))) {
                hi_t = mid;
              } else {
                lo = mid;
              }
            }
            EXPECT_LE(it->second.first, hi_t + 1e-9);
            EXPECT_GE(it->second.first, hi_t - 1e-3)
                << "scene " << scene << " pair " << i << "," << j << ": predicted "
                << it->second.first << " exact " << hi_t;
          }
        }
      }

      // Advance the scene by 0.1 s along the same motions (new poses, same velocities).
      for (TestBody& b : bodies) {
        const oracle::Obb o = obbAt(b, 0.1);
        b.motion.position = o.pose.translation();
        b.motion.orientation = Eigen::Quaterniond(o.pose.linear());
        world.setMotion(b.handle, b.motion);
      }
    }
  }
}

}  // namespace

TEST(NoFalseNegatives, TranslatingOrientedBoxesAndExactTimes) {
  int checked = 0;
  checkScenes(60, 14, false, 11, &checked);
  EXPECT_GT(checked, 100);  // the scenes are dense enough to test many contacts
}

TEST(NoFalseNegatives, RotatingAndTranslatingOrientedBoxes) {
  int checked = 0;
  checkScenes(60, 14, true, 12, &checked);
  EXPECT_GT(checked, 100);
}

TEST(NoFalseNegatives, TranslatingUprightBoxesAndExactTimes) {
  int checked = 0;
  checkScenes(60, 14, false, 13, &checked, true);
  EXPECT_GT(checked, 100);
}

TEST(NoFalseNegatives, YawingAndTranslatingUprightBoxes) {
  int checked = 0;
  checkScenes(60, 14, true, 14, &checked, true);
  EXPECT_GT(checked, 100);
}

// The per-pair stages shared among threads (chunks of 16 pairs taken in turn): the same
// oracle, denser scenes (more pairs than chunks).
TEST(NoFalseNegatives, TranslatingUprightBoxesOnThreeThreads) {
  int checked = 0;
  checkScenes(6, 24, false, 15, &checked, true, 3);
  EXPECT_GT(checked, 100);
}

TEST(NoFalseNegatives, RotatingOrientedBoxesOnTwoThreads) {
  int checked = 0;
  checkScenes(6, 24, true, 16, &checked, false, 2);
  EXPECT_GT(checked, 100);
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
