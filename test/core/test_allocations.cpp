// Steady-state cycles of the broad phase and of event tracking allocate nothing.
// Every global operator new in this test binary is counted.

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>
#include <random>
#include <vector>

#include "workspace_proximity/event_tracker.hpp"
#include "workspace_proximity/proximity_world.hpp"
#include "workspace_proximity/sweep_and_prune.hpp"

namespace {
std::atomic<long> g_allocations{0};
}

// malloc/free behind replaced global new/delete: GCC's -Wmismatched-new-delete cannot see
// that they pair up.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void* operator new(std::size_t size) {
  ++g_allocations;
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) { return operator new(size); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
#pragma GCC diagnostic pop

namespace wp = workspace_proximity;

namespace {

struct Scene {
  std::vector<wp::Aabb> boxes;
  std::vector<Eigen::Vector3d> velocity;
  std::vector<wp::SweepAndPrune::ProxyId> ids;
};

// Bounces N boxes in a cube; `step` scales the motion per cycle.
void advance(Scene* s, double step) {
  for (std::size_t i = 0; i < s->boxes.size(); ++i) {
    Eigen::Vector3d d = s->velocity[i] * step;
    wp::Aabb& b = s->boxes[i];
    for (int k = 0; k < 3; ++k) {
      if (b.lower[k] + d[k] < 0 || b.upper[k] + d[k] > 30) {
        s->velocity[i][k] = -s->velocity[i][k];
        d[k] = -d[k];
      }
    }
    b.lower += d;
    b.upper += d;
  }
}

}  // namespace

TEST(Allocations, SweepAndPruneSteadyStateAllocatesNothing) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> pos(1, 29), half(0.25, 0.75), vel(-1, 1);
  wp::SweepAndPruneConfig config;
  config.initial_proxy_capacity = 2048;
  config.initial_pair_capacity = 8192;
  wp::SweepAndPrune sap(config);
  Scene s;
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d c(pos(rng), pos(rng), pos(rng));
    const Eigen::Vector3d h(half(rng), half(rng), half(rng));
    s.boxes.push_back({c - h, c + h});
    s.velocity.emplace_back(vel(rng), vel(rng), vel(rng));
    s.ids.push_back(sap.createProxy(s.boxes.back()));
  }
  auto cycle = [&](double step, bool churn) {
    advance(&s, step);
    for (std::size_t i = 0; i < s.boxes.size(); ++i) sap.moveProxy(s.ids[i], s.boxes[i]);
    if (churn) {
      // Tracks appear and disappear: remove and re-create a few per cycle.
      for (int k = 0; k < 5; ++k) {
        const std::size_t i = rng() % s.boxes.size();
        sap.destroyProxy(s.ids[i]);
        s.ids[i] = sap.createProxy(s.boxes[i]);
      }
    }
    sap.update();
  };
  // Warm up through every path: small motion, churn, and large jumps that force rebuilds.
  for (int i = 0; i < 50; ++i) cycle(0.05, i % 2 == 0);
  for (int i = 0; i < 5; ++i) cycle(20.0, true);
  for (int i = 0; i < 50; ++i) cycle(0.05, true);

  const long before = g_allocations.load();
  bool rebuilt = false;
  for (int i = 0; i < 200; ++i) {
    cycle(i % 50 == 0 ? 20.0 : 0.05, true);
    rebuilt |= sap.stats().rebuilt;
  }
  EXPECT_TRUE(rebuilt);
  EXPECT_EQ(g_allocations.load() - before, 0);
}

TEST(Allocations, EventTrackerSteadyStateAllocatesNothing) {
  wp::EventTracker tracker(64);
  std::mt19937 rng(9);
  auto cycle = [&] {
    tracker.beginCycle();
    const int n = static_cast<int>(rng() % 200);
    std::uint64_t seen[256];
    int count = 0;
    for (int i = 0; i < n; ++i) {
      const std::uint64_t key = rng() % 400;
      bool dup = false;
      for (int k = 0; k < count; ++k) dup |= seen[k] == key;
      if (dup) continue;
      seen[count++] = key;
      wp::PairEvent e;
      e.time_to_contact = (rng() % 100) / 100.0;
      tracker.report(key, e);
    }
    tracker.endCycle();
  };
  for (int i = 0; i < 500; ++i) cycle();
  const long before = g_allocations.load();
  for (int i = 0; i < 2000; ++i) cycle();
  EXPECT_EQ(g_allocations.load() - before, 0);
}

// The whole pipeline, FCL narrow phase included, while bodies are predicted to meet but do
// not overlap yet. (For pairs overlapping now, FCL 0.7's collide allocates inside FCL: it
// builds its GJK objects with new on every call. That path is outside this guarantee.)
TEST(Allocations, WorldPredictAllocatesNothingWhileNothingOverlapsYet) {
  wp::WorldConfig config;
  config.rules = wp::PairRules::allowAll();
  wp::ProximityWorld world(config);
  // A 6 x 6 x 3 grid of mixed shapes, 1 m between centres, each oscillating along x with
  // amplitude 0.15 m, neighbours in opposite phase: they close at up to 0.9 m/s, so contact
  // is predicted within the 1 s horizon, but the gaps (>= 0.6 - 0.3 m) never close.
  struct Oscillator {
    wp::BodyHandle handle;
    Eigen::Vector3d centre;
    double phase;
  };
  std::vector<Oscillator> bodies;
  int i = 0;
  for (int x = 0; x < 6; ++x) {
    for (int y = 0; y < 6; ++y) {
      for (int z = 0; z < 3; ++z, ++i) {
        const wp::Shape shape = (i % 3 == 0)   ? wp::Shape::sphere(0.2)
                                : (i % 3 == 1) ? wp::Shape::box({0.2, 0.15, 0.1})
                                               : wp::Shape::capsule(0.1, 0.2);
        Oscillator o{wp::BodyHandle(), Eigen::Vector3d(x, y, z), (x % 2) ? M_PI : 0.0};
        o.handle = world.addBody(
            wp::BodyDesc{"b" + std::to_string(i), "thing", wp::BodyGroup::kObject, shape, 0.02},
            wp::BodyMotion());
        bodies.push_back(o);
      }
    }
  }
  const double omega = 3.0, amplitude = 0.15;
  int predicted = 0;
  auto cycle = [&](int k) {
    const double t = k / 30.0;
    for (const Oscillator& o : bodies) {
      wp::BodyMotion m;
      m.position = o.centre + Eigen::Vector3d(amplitude * std::sin(omega * t + o.phase), 0, 0);
      m.linear_velocity = {amplitude * omega * std::cos(omega * t + o.phase), 0, 0};
      m.angular_velocity = {0, 0, 0.5};
      world.setMotion(o.handle, m);
    }
    world.predict(1.0);
    predicted += world.stats().contacts;
  };
  for (int k = 0; k < 100; ++k) cycle(k);
  const long before = g_allocations.load();
  for (int k = 100; k < 200; ++k) cycle(k);
  EXPECT_GT(predicted, 0);
  EXPECT_EQ(g_allocations.load() - before, 0);
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
