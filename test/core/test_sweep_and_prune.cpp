// Tests of the incremental SweepAndPrune. The oracle is an O(n^2) brute force of closed-interval
// AABB overlap in double precision, kept by the test for its own objects (never read back from
// the structure), plus set differences of consecutive brute-force pair sets for began/ended.
//
// Contract detail: bounds are rounded outward to float keys, so on arbitrary doubles the
// structure may also report pairs whose double gap is below float rounding. Hence two modes:
//  * exact scenes (every coordinate a multiple of 1/64 within +-1000, exact in float): the
//    reported set must EQUAL brute force;
//  * arbitrary doubles: reported ⊇ brute force, and every extra pair is separated only by a
//    gap below 1e-5 * max(1, |coordinate|) on each separating axis.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iterator>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "workspace_proximity/sweep_and_prune.hpp"

using workspace_proximity::Aabb;
using workspace_proximity::BroadPair;
using workspace_proximity::SweepAndPrune;
using workspace_proximity::SweepAndPruneConfig;

namespace {

using Rng = std::mt19937_64;
using PairCode = std::uint64_t;

// Unordered pair of the test's object ids.
PairCode pairCode(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<PairCode>(static_cast<std::uint32_t>(a)) << 32) |
         static_cast<std::uint32_t>(b);
}
int firstOf(PairCode c) { return static_cast<int>(c >> 32); }
int secondOf(PairCode c) { return static_cast<int>(c & 0xffffffffu); }

std::vector<PairCode> minus(const std::vector<PairCode>& a, const std::vector<PairCode>& b) {
  std::vector<PairCode> out;
  std::set_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
  return out;
}

Aabb makeBox(double x0, double y0, double z0, double x1, double y1, double z1) {
  Aabb b;
  b.lower = Eigen::Vector3d(x0, y0, z0);
  b.upper = Eigen::Vector3d(x1, y1, z1);
  return b;
}

// The brute-force oracle's predicate (closed intervals, double precision), written out here
// rather than calling Aabb::overlaps.
bool bruteOverlap(const Aabb& a, const Aabb& b) {
  for (int k = 0; k < 3; ++k) {
    if (a.lower[k] > b.upper[k] || b.lower[k] > a.upper[k]) return false;
  }
  return true;
}

// Drives a SweepAndPrune and checks it after every update() against the brute-force oracle.
// The test keeps its own proxy -> object maps (current and as of the previous update, since
// proxy ids can be reused).
class Harness {
 public:
  Harness(const SweepAndPruneConfig& config, bool exact) : sap_(config), exact_(exact) {}

  int create(const Aabb& box) {
    int obj = static_cast<int>(objs_.size());
    int proxy = sap_.createProxy(box);
    EXPECT_GE(proxy, 0);
    if (proxy >= static_cast<int>(proxy_to_obj_.size())) proxy_to_obj_.resize(proxy + 1, -1);
    EXPECT_EQ(proxy_to_obj_[proxy], -1) << "proxy id " << proxy << " handed out while in use";
    proxy_to_obj_[proxy] = obj;
    objs_.push_back(Obj{box, proxy, static_cast<int>(live_.size())});
    live_.push_back(obj);
    return obj;
  }

  void destroy(int obj) {
    Obj& o = objs_[obj];
    ASSERT_GE(o.live_pos, 0);
    sap_.destroyProxy(o.proxy);
    proxy_to_obj_[o.proxy] = -1;
    int last = live_.back();
    live_[o.live_pos] = last;
    objs_[last].live_pos = o.live_pos;
    live_.pop_back();
    o.live_pos = -1;
  }

  void move(int obj, const Aabb& box) {
    ASSERT_GE(objs_[obj].live_pos, 0);
    sap_.moveProxy(objs_[obj].proxy, box);
    objs_[obj].box = box;
  }

  // update() and every check of the result.
  void updateAndCheck() {
    sap_.update();
    ++updates_;
    ASSERT_EQ(sap_.proxyCount(), static_cast<int>(live_.size()));

    // Stored bounds enclose the given ones (outward rounding), and not by much.
    for (int obj : live_) {
      const Obj& o = objs_[obj];
      Aabb s = sap_.storedBounds(o.proxy);
      for (int k = 0; k < 3; ++k) {
        ASSERT_LE(s.lower[k], o.box.lower[k]) << "object " << obj << " axis " << k;
        ASSERT_GE(s.upper[k], o.box.upper[k]) << "object " << obj << " axis " << k;
        ASSERT_LE(o.box.lower[k] - s.lower[k], 1e-6 * std::max(1.0, std::abs(o.box.lower[k])));
        ASSERT_LE(s.upper[k] - o.box.upper[k], 1e-6 * std::max(1.0, std::abs(o.box.upper[k])));
      }
    }

    // Oracle: brute-force pair set over the live objects.
    std::vector<PairCode> brute;
    for (std::size_t i = 0; i < live_.size(); ++i) {
      for (std::size_t j = i + 1; j < live_.size(); ++j) {
        if (bruteOverlap(objs_[live_[i]].box, objs_[live_[j]].box))
          brute.push_back(pairCode(live_[i], live_[j]));
      }
    }
    std::sort(brute.begin(), brute.end());

    // Reported pairs, mapped to object ids: ordered, live, no duplicates.
    std::vector<PairCode> reported = mapPairs(sap_.pairs(), proxy_to_obj_, "pairs()");
    if (::testing::Test::HasFatalFailure()) return;
    for (const BroadPair& p : sap_.pairs()) {
      ASSERT_TRUE(sap_.hasPair(p.proxy_a, p.proxy_b));
      ASSERT_TRUE(sap_.hasPair(p.proxy_b, p.proxy_a));
    }

    if (exact_) {
      // Exactly representable scene: the sets must be equal.
      std::vector<PairCode> missing = minus(brute, reported), extra = minus(reported, brute);
      ASSERT_TRUE(missing.empty()) << describe(missing, "missing");
      ASSERT_TRUE(extra.empty()) << describe(extra, "extra");
      if (updates_ % 4 == 0) {
        // hasPair must also reject every non-overlapping live pair.
        for (std::size_t i = 0; i < live_.size(); ++i) {
          for (std::size_t j = i + 1; j < live_.size(); ++j) {
            const Obj& a = objs_[live_[i]];
            const Obj& b = objs_[live_[j]];
            if (!bruteOverlap(a.box, b.box)) {
              ASSERT_FALSE(sap_.hasPair(a.proxy, b.proxy));
            }
          }
        }
      }
    } else {
      // Arbitrary doubles: superset, and extras only within float rounding of touching.
      std::vector<PairCode> missing = minus(brute, reported);
      ASSERT_TRUE(missing.empty()) << describe(missing, "missing");
      for (PairCode c : minus(reported, brute)) {
        const Aabb& a = objs_[firstOf(c)].box;
        const Aabb& b = objs_[secondOf(c)].box;
        for (int k = 0; k < 3; ++k) {
          double gap = std::max(b.lower[k] - a.upper[k], a.lower[k] - b.upper[k]);
          double mag = std::max({1.0, std::abs(a.lower[k]), std::abs(a.upper[k]),
                                 std::abs(b.lower[k]), std::abs(b.upper[k])});
          ASSERT_LT(gap, 1e-5 * mag) << describe({c}, "extra pair with a real gap")
                                     << " axis " << k << " gap " << gap;
        }
      }
    }

    // began = now - before, ended = before - now. Ended pairs may name destroyed (even
    // reused) proxy ids, so they are mapped through the previous update's table. In exact
    // mode `reported` equals the brute-force set (checked above).
    const std::vector<PairCode>& now = exact_ ? brute : reported;
    std::vector<PairCode> began = mapPairs(sap_.beganPairs(), proxy_to_obj_, "beganPairs()");
    std::vector<PairCode> ended = mapPairs(sap_.endedPairs(), prev_proxy_to_obj_, "endedPairs()");
    if (::testing::Test::HasFatalFailure()) return;
    ASSERT_EQ(began, minus(now, prev_pairs_)) << "update " << updates_;
    ASSERT_EQ(ended, minus(prev_pairs_, now)) << "update " << updates_;

    extra_pairs_ += static_cast<std::int64_t>(reported.size() - brute.size());
    began_total_ += static_cast<std::int64_t>(began.size());
    ended_total_ += static_cast<std::int64_t>(ended.size());
    prev_pairs_ = now;
    prev_proxy_to_obj_ = proxy_to_obj_;
    total_pairs_seen_ += static_cast<std::int64_t>(now.size());
  }

  const std::vector<int>& live() const { return live_; }
  const Aabb& box(int obj) const { return objs_[obj].box; }
  const SweepAndPrune& sap() const { return sap_; }
  std::int64_t totalPairsSeen() const { return total_pairs_seen_; }
  std::int64_t extraPairs() const { return extra_pairs_; }
  std::int64_t beganTotal() const { return began_total_; }
  std::int64_t endedTotal() const { return ended_total_; }

 private:
  struct Obj {
    Aabb box;
    int proxy;
    int live_pos;  // index in live_, or -1 once destroyed
  };

  // Maps proxy pairs to sorted object pairs; checks proxy_a < proxy_b, known ids, no duplicates.
  std::vector<PairCode> mapPairs(const std::vector<BroadPair>& pairs, const std::vector<int>& map,
                                 const char* what) {
    std::vector<PairCode> out;
    out.reserve(pairs.size());
    for (const BroadPair& p : pairs) {
      EXPECT_LT(p.proxy_a, p.proxy_b) << what;
      bool known = p.proxy_a >= 0 && p.proxy_b >= 0 &&
                   p.proxy_a < static_cast<int>(map.size()) &&
                   p.proxy_b < static_cast<int>(map.size()) && map[p.proxy_a] >= 0 &&
                   map[p.proxy_b] >= 0;
      if (!known) {
        ADD_FAILURE() << what << " names unknown proxy pair " << p.proxy_a << "," << p.proxy_b;
        return out;
      }
      out.push_back(pairCode(map[p.proxy_a], map[p.proxy_b]));
    }
    std::sort(out.begin(), out.end());
    EXPECT_TRUE(std::adjacent_find(out.begin(), out.end()) == out.end())
        << what << " has duplicates";
    return out;
  }

  std::string describe(const std::vector<PairCode>& codes, const char* what) const {
    std::ostringstream s;
    s << what << " (" << codes.size() << ") at update " << updates_ << ":";
    for (std::size_t i = 0; i < codes.size() && i < 3; ++i) {
      const Aabb& a = objs_[firstOf(codes[i])].box;
      const Aabb& b = objs_[secondOf(codes[i])].box;
      s.precision(17);
      s << "\n  objects " << firstOf(codes[i]) << " [" << a.lower.transpose() << "]-["
        << a.upper.transpose() << "] and " << secondOf(codes[i]) << " [" << b.lower.transpose()
        << "]-[" << b.upper.transpose() << "]";
    }
    return s.str();
  }

  SweepAndPrune sap_;
  bool exact_;
  std::vector<Obj> objs_;
  std::vector<int> live_;
  std::vector<int> proxy_to_obj_;
  std::vector<int> prev_proxy_to_obj_;
  std::vector<PairCode> prev_pairs_;
  int updates_ = 0;
  std::int64_t total_pairs_seen_ = 0;
  std::int64_t extra_pairs_ = 0;
  std::int64_t began_total_ = 0;
  std::int64_t ended_total_ = 0;
};

// Random boxes for one scene. In exact mode every coordinate is a multiple of `quantum`
// (itself a multiple of 1/64) clamped to +-1000, hence exactly representable in float.
struct SceneGen {
  bool exact = true;
  double quantum = 1.0 / 64.0;
  double extent = 100.0;     // lower corners in [-extent, extent] (+ offset)
  double max_size = 10.0;
  double offset = 0.0;       // arbitrary-double scenes: shift far from the origin
  double shared = 0.0;       // a coordinate many boxes share

  double q(double x) const {
    if (!exact) return x;
    return std::clamp(quantum * std::round(x / quantum), -1000.0, 1000.0);
  }

  Aabb fresh(Rng& rng) const {
    std::uniform_real_distribution<double> pos(-extent, extent), size(0.0, max_size);
    Aabb b;
    for (int k = 0; k < 3; ++k) {
      b.lower[k] = q(offset + pos(rng));
      b.upper[k] = std::max(b.lower[k], q(b.lower[k] + size(rng)));
    }
    return b;
  }

  // A new box with a special relation to `other` (or a fresh one when there is no other).
  Aabb related(Rng& rng, const Aabb* other) const {
    std::uniform_int_distribution<int> kind(0, 99), coin(0, 1), axis(0, 2);
    std::uniform_real_distribution<double> size(0.0, max_size), unit(0.0, 1.0);
    int k = kind(rng);
    if (k < 6) {  // zero-size (point) box
      Aabb b = fresh(rng);
      b.upper = b.lower;
      return b;
    }
    if (k < 12) {  // many boxes whose lower or upper x is the same coordinate
      Aabb b = fresh(rng);
      double w = b.upper.x() - b.lower.x();
      if (coin(rng)) {
        b.lower.x() = shared;
        b.upper.x() = q(shared + w);
      } else {
        b.upper.x() = shared;
        b.lower.x() = q(shared - w);
      }
      return b;
    }
    if (other == nullptr || k < 45) return fresh(rng);
    if (k < 55) return *other;  // identical box
    if (k < 60) {               // point on a corner of the other box
      Aabb b;
      for (int a = 0; a < 3; ++a) b.lower[a] = coin(rng) ? other->lower[a] : other->upper[a];
      b.upper = b.lower;
      return b;
    }
    // Touching the other box on a random nonempty subset of axes (face, edge or corner
    // contact), overlapping it on the rest. Arbitrary-double scenes also get near-touching
    // boxes, separated or overlapping by a hair.
    int touch_mask = 1 + std::uniform_int_distribution<int>(0, 6)(rng);
    bool nudge = !exact && k >= 85;
    Aabb b;
    for (int a = 0; a < 3; ++a) {
      double w = q(size(rng));
      if (touch_mask & (1 << a)) {
        if (coin(rng)) {
          b.lower[a] = other->upper[a];
          if (nudge) b.lower[a] += (unit(rng) - 0.5) * 1e-7 * std::max(1.0, std::abs(b.lower[a]));
          b.upper[a] = std::max(b.lower[a], q(b.lower[a] + w));
        } else {
          b.upper[a] = other->lower[a];
          if (nudge) b.upper[a] += (unit(rng) - 0.5) * 1e-7 * std::max(1.0, std::abs(b.upper[a]));
          b.lower[a] = std::min(b.upper[a], q(b.upper[a] - w));
        }
        if (nudge && coin(rng)) {  // one double ulp apart
          b.lower[a] = std::nextafter(b.lower[a], 1e300);
          b.upper[a] = std::max(b.upper[a], b.lower[a]);
        }
      } else {
        double lo = other->lower[a], hi = other->upper[a];
        b.lower[a] = q(lo - w * unit(rng));
        b.upper[a] = std::max(b.lower[a], q(std::max(b.lower[a], lo) + (hi - lo) * unit(rng) + w));
      }
    }
    return b;
  }

  // Small motion: shift by a few quanta (exact) or a small random amount, sometimes resize.
  Aabb jitter(Rng& rng, const Aabb& b) const {
    std::uniform_int_distribution<int> steps(-2, 2), pick(0, 9);
    std::uniform_real_distribution<double> small(-0.02, 0.02);
    Aabb out = b;
    for (int a = 0; a < 3; ++a) {
      double d = exact ? quantum * steps(rng) : small(rng) * max_size;
      out.lower[a] = q(b.lower[a] + d);
      out.upper[a] = q(b.upper[a] + d);
      if (pick(rng) == 0) out.upper[a] = q(out.upper[a] + (exact ? quantum : 0.01 * max_size));
      if (out.upper[a] < out.lower[a]) out.upper[a] = out.lower[a];
    }
    return out;
  }
};

SceneGen randomScene(Rng& rng, bool exact) {
  SceneGen g;
  g.exact = exact;
  std::uniform_int_distribution<int> pick(0, 3);
  const double quanta[] = {1.0 / 64.0, 1.0 / 8.0, 1.0, 4.0};
  const double extents[] = {4.0, 30.0, 200.0, 600.0};
  const double size_fraction[] = {0.05, 0.2, 0.5, 1.0};
  g.extent = extents[pick(rng)];
  g.max_size = g.extent * size_fraction[pick(rng)];
  if (exact) {
    g.quantum = quanta[pick(rng)];
    g.max_size = std::min(g.max_size, 350.0);
    g.shared = g.q(std::uniform_real_distribution<double>(-g.extent, g.extent)(rng));
  } else {
    const double extents_d[] = {1e-3, 1.0, 100.0, 5000.0};
    // Far from the origin (relative to the scene size) float keys get coarse; keep the
    // offset at most 1000 scene sizes so rounding stays a boundary effect.
    const double offsets[] = {0.0, 0.0, 10.0, 1000.0};
    g.extent = extents_d[pick(rng)];
    g.max_size = g.extent * size_fraction[pick(rng)];
    g.offset = offsets[pick(rng)] * g.extent;
    g.shared = g.offset + std::uniform_real_distribution<double>(-g.extent, g.extent)(rng);
  }
  return g;
}

// One scene: build, then a run of update cycles mixing jitter, large jumps, insertions and
// removals (single and batched), create+destroy before update, destroy-all and re-creation.
struct RunStats {
  int updates = 0;
  std::int64_t pairs_total = 0, extra_pairs = 0, began = 0, ended = 0;
  int rebuilds = 0;
  int large_jump_updates = 0;
  int rebuilds_on_large_jumps = 0;
};

void runScene(Rng& rng, bool exact, RunStats* stats) {
  std::uniform_int_distribution<int> pct(0, 99);
  SceneGen gen = randomScene(rng, exact);
  SweepAndPruneConfig cfg;
  const int caps[] = {1, 8, 256};
  const double factors[] = {0.0, 0.05, 1.0, 1.0, 1.0, 1e9};
  cfg.initial_proxy_capacity = caps[pct(rng) % 3];
  cfg.initial_pair_capacity = caps[pct(rng) % 3];
  cfg.rebuild_factor = factors[pct(rng) % 6];
  Harness h(cfg, exact);

  auto randomLive = [&]() {
    return h.live()[std::uniform_int_distribution<std::size_t>(0, h.live().size() - 1)(rng)];
  };
  // (The pointer is used before the next create() can reallocate the harness's storage.)
  auto randomOther = [&]() -> const Aabb* {
    return h.live().empty() ? nullptr : &h.box(randomLive());
  };

  int n0 = pct(rng) < 5 ? 0 : std::uniform_int_distribution<int>(1, 300)(rng);
  for (int i = 0; i < n0; ++i) {
    Aabb b = gen.related(rng, randomOther());
    h.create(b);
  }
  // Sometimes create and destroy before the very first update.
  if (pct(rng) < 30 && !h.live().empty()) {
    for (int i = 0, m = 1 + pct(rng) % 10; i < m && !h.live().empty(); ++i) h.destroy(randomLive());
  }
  auto account = [&]() {
    ++stats->updates;
    stats->rebuilds += h.sap().stats().rebuilt ? 1 : 0;
  };
  h.updateAndCheck();
  account();
  if (::testing::Test::HasFatalFailure()) return;

  const int cycles = 3 + pct(rng) % 8;
  for (int c = 0; c < cycles; ++c) {
    bool large = false;
    bool structural = false;
    int motion = pct(rng);
    const std::vector<int> before = h.live();
    if (motion < 45) {  // jitter a fraction of the boxes
      for (int obj : before)
        if (pct(rng) < 50) h.move(obj, gen.jitter(rng, h.box(obj)));
    } else if (motion < 75) {  // large jumps for most boxes
      large = true;
      for (int obj : before)
        if (pct(rng) < 90) h.move(obj, gen.related(rng, randomOther()));
    } else if (motion < 85) {  // a few boxes jump
      for (int obj : before)
        if (pct(rng) < 5) h.move(obj, gen.fresh(rng));
    }
    if (pct(rng) < 10 && !before.empty()) {  // several moves of one box: the last one counts
      int obj = before[pct(rng) % before.size()];
      for (int i = 0; i < 3; ++i) h.move(obj, gen.fresh(rng));
      h.move(obj, gen.related(rng, randomOther()));
    }
    if (pct(rng) < 30 && !h.live().empty()) {  // removals, single or batched
      structural = true;
      int m = pct(rng) < 50 ? 1 : 1 + pct(rng) % std::max<int>(1, h.live().size() / 3);
      for (int i = 0; i < m && !h.live().empty(); ++i) h.destroy(randomLive());
    }
    if (pct(rng) < 3) {  // destroy everything
      structural = true;
      while (!h.live().empty()) h.destroy(h.live().back());
    }
    if (pct(rng) < 35) {  // insertions, single or batched, up to 300 live
      structural = true;
      int room = 300 - static_cast<int>(h.live().size());
      int m = std::min(room, pct(rng) < 50 ? 1 : 1 + pct(rng) % 60);
      for (int i = 0; i < m; ++i) h.create(gen.related(rng, randomOther()));
    }
    if (pct(rng) < 20) {  // create and destroy before the update: never reported
      structural = true;
      std::vector<int> temp;
      for (int i = 0, m = 1 + pct(rng) % 5; i < m; ++i)
        temp.push_back(h.create(gen.related(rng, randomOther())));
      for (int obj : temp) h.destroy(obj);
    }
    h.updateAndCheck();
    account();
    if (::testing::Test::HasFatalFailure()) return;
    if (large && !structural && cfg.rebuild_factor == 1.0 && before.size() >= 100) {
      ++stats->large_jump_updates;
      if (h.sap().stats().rebuilt) ++stats->rebuilds_on_large_jumps;
    }
  }
  stats->pairs_total += h.totalPairsSeen();
  stats->extra_pairs += h.extraPairs();
  stats->began += h.beganTotal();
  stats->ended += h.endedTotal();
}

// `n` half-unit cubes at random integer corners in [-900, 900]^3: sparse, exact in float.
std::vector<Aabb> spreadBoxes(Rng& rng, int n) {
  std::vector<Aabb> out;
  std::uniform_real_distribution<double> pos(-900.0, 900.0);
  for (int i = 0; i < n; ++i) {
    double x = std::round(pos(rng)), y = std::round(pos(rng)), z = std::round(pos(rng));
    out.push_back(makeBox(x, y, z, x + 0.5, y + 0.5, z + 0.5));
  }
  return out;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Deterministic configurations with known answers.

TEST(SweepAndPrune, EmptyStructureUpdates) {
  SweepAndPrune sap;
  sap.update();
  EXPECT_TRUE(sap.pairs().empty());
  EXPECT_TRUE(sap.beganPairs().empty());
  EXPECT_TRUE(sap.endedPairs().empty());
  EXPECT_EQ(sap.proxyCount(), 0);
}

TEST(SweepAndPrune, TouchingGridReportsFaceEdgeAndCornerNeighbours) {
  // A 4x4x4 grid of unit cubes sharing faces: each cube touches every cube at Chebyshev
  // distance 1 (face, edge or corner). Analytic count: ((3n-2)^3 - n^3) / 2 = 468 for n = 4.
  Harness h(SweepAndPruneConfig(), true);
  const int n = 4;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) h.create(makeBox(i, j, k, i + 1, j + 1, k + 1));
  h.updateAndCheck();
  const int m = 3 * n - 2;
  EXPECT_EQ(static_cast<int>(h.sap().pairs().size()), (m * m * m - n * n * n) / 2);
}

TEST(SweepAndPrune, TouchingPairsAtEveryContactKind) {
  Harness h(SweepAndPruneConfig(), true);
  Aabb base = makeBox(0, 0, 0, 1, 1, 1);
  h.create(base);
  h.create(makeBox(1, 0.25, 0.25, 2, 0.75, 0.75));   // face
  h.create(makeBox(-1, 1, 0.25, 0, 2, 0.75));       // edge
  h.create(makeBox(1, 1, 1, 2, 2, 2));              // corner
  h.create(makeBox(-2, -2, -2, 0, 0, 0));           // corner at the origin
  h.create(makeBox(0.5, 0.5, 0.5, 0.5, 0.5, 0.5));  // point inside
  h.create(makeBox(1, 1, 1, 1, 1, 1));              // point on the corner
  h.create(makeBox(1, 1, 1, 1, 1, 1));              // the same point again
  h.create(makeBox(3, 3, 3, 4, 4, 4));              // apart from everything
  h.updateAndCheck();
  int with_base = 0;
  for (const BroadPair& p : h.sap().pairs()) with_base += (p.proxy_a == 0 || p.proxy_b == 0);
  EXPECT_EQ(with_base, 7);
}

TEST(SweepAndPrune, SignedZeroTouchingBoxesOverlap) {
  // Upper x = -0.0 against lower x = +0.0: they touch in double, so they must be reported.
  Harness h(SweepAndPruneConfig(), true);
  h.create(makeBox(-1, 0, 0, -0.0, 1, 1));
  h.create(makeBox(0.0, 0, 0, 1, 1, 1));
  h.create(makeBox(-0.0, 5, 5, 1, 6, 6));
  h.create(makeBox(-1, 5, 5, 0.0, 6, 6));
  h.updateAndCheck();
}

TEST(SweepAndPrune, IdenticalAndCoincidentBoxes) {
  // 40 identical boxes, 30 identical points, 30 boxes sharing one x coordinate:
  // every pair among the first 70 overlaps with its own group.
  Harness h(SweepAndPruneConfig(), true);
  for (int i = 0; i < 40; ++i) h.create(makeBox(1, 2, 3, 4, 5, 6));
  for (int i = 0; i < 30; ++i) h.create(makeBox(-7, -7, -7, -7, -7, -7));
  for (int i = 0; i < 30; ++i) h.create(makeBox(10, 3 * i, 0, 12, 3 * i + 3, 1));
  h.updateAndCheck();
  // 780 + 435 + 29 face neighbours along y.
  EXPECT_EQ(h.sap().pairs().size(), 780u + 435u + 29u);
  // Moving all of them by the same amount keeps the set and reports nothing.
  for (int obj : std::vector<int>(h.live())) {
    Aabb b = h.box(obj);
    b.lower.array() += 0.5;
    b.upper.array() += 0.5;
    h.move(obj, b);
  }
  h.updateAndCheck();
  EXPECT_TRUE(h.sap().beganPairs().empty());
  EXPECT_TRUE(h.sap().endedPairs().empty());
}

TEST(SweepAndPrune, CreateAndDestroyBeforeUpdateIsNeverReported) {
  Harness h(SweepAndPruneConfig(), true);
  h.create(makeBox(0, 0, 0, 1, 1, 1));
  int b = h.create(makeBox(0.5, 0.5, 0.5, 2, 2, 2));
  h.destroy(b);
  h.updateAndCheck();
  EXPECT_TRUE(h.sap().pairs().empty());
  EXPECT_TRUE(h.sap().beganPairs().empty());
  // Destroy a live proxy and create a new overlapping one in the same update: the id may be
  // reused, and the old pair must end while the new one begins.
  int c = h.create(makeBox(0.5, 0.5, 0.5, 2, 2, 2));
  h.updateAndCheck();
  h.destroy(c);
  h.create(makeBox(0.75, 0.75, 0.75, 2, 2, 2));
  h.updateAndCheck();
  EXPECT_EQ(h.sap().beganPairs().size(), 1u);
  EXPECT_EQ(h.sap().endedPairs().size(), 1u);
  // Destroy everything.
  while (!h.live().empty()) h.destroy(h.live().back());
  h.updateAndCheck();
  EXPECT_TRUE(h.sap().pairs().empty());
  EXPECT_EQ(h.sap().endedPairs().size(), 1u);
}

TEST(SweepAndPrune, MoveOfProxyCreatedSinceLastUpdate) {
  // A proxy moved before its first update joins with its latest bounds.
  Harness h(SweepAndPruneConfig(), true);
  h.create(makeBox(0, 0, 0, 1, 1, 1));
  int b = h.create(makeBox(10, 10, 10, 11, 11, 11));
  h.move(b, makeBox(1, 1, 1, 2, 2, 2));
  h.updateAndCheck();
  EXPECT_EQ(h.sap().pairs().size(), 1u);
}

TEST(SweepAndPrune, SmallMotionSortsIncrementallyLargeJumpsRebuild) {
  // Default config; 250 well-separated boxes. Sub-spacing jitter must stay on the
  // insertion-sort path; re-scattering every box costs O(n^2) swaps and must rebuild.
  Rng rng(5);
  Harness h(SweepAndPruneConfig(), true);
  for (const Aabb& b : spreadBoxes(rng, 250)) h.create(b);
  h.updateAndCheck();
  std::uniform_int_distribution<int> step(-1, 1);
  for (int round = 0; round < 3; ++round) {
    for (int obj : std::vector<int>(h.live())) {
      Aabb b = h.box(obj);
      Eigen::Vector3d d(step(rng) / 64.0, step(rng) / 64.0, step(rng) / 64.0);
      b.lower += d;
      b.upper += d;
      h.move(obj, b);
    }
    h.updateAndCheck();
    EXPECT_FALSE(h.sap().stats().rebuilt) << "round " << round;
  }
  std::vector<Aabb> scattered = spreadBoxes(rng, 250);
  for (std::size_t i = 0; i < h.live().size(); ++i) h.move(h.live()[i], scattered[i]);
  h.updateAndCheck();
  EXPECT_TRUE(h.sap().stats().rebuilt);
  // And back to incremental afterwards.
  for (int obj : std::vector<int>(h.live())) {
    Aabb b = h.box(obj);
    b.lower.x() += 1.0 / 64.0;
    b.upper.x() += 1.0 / 64.0;
    h.move(obj, b);
  }
  h.updateAndCheck();
  EXPECT_FALSE(h.sap().stats().rebuilt);
}

// ---------------------------------------------------------------------------------------------
// Random scenes against brute force.

TEST(SweepAndPrune, RandomExactScenesEqualBruteForce) {
  Rng rng(20240601);
  RunStats stats;
  for (int scene = 0; scene < 500; ++scene) {
    SCOPED_TRACE(testing::Message() << "scene " << scene);
    runScene(rng, true, &stats);
    if (::testing::Test::HasFatalFailure()) return;
  }
  std::printf("exact scenes: %d updates, %d rebuilds, %lld pairs, %lld began, %lld ended\n",
              stats.updates, stats.rebuilds, static_cast<long long>(stats.pairs_total),
              static_cast<long long>(stats.began), static_cast<long long>(stats.ended));
  EXPECT_GT(stats.updates, 3000);
  EXPECT_GT(stats.began, 10000);
  EXPECT_GT(stats.ended, 10000);
  // Large jumps with the default rebuild factor must sometimes take the rebuild path.
  EXPECT_GT(stats.large_jump_updates, 0);
  EXPECT_GT(stats.rebuilds_on_large_jumps, 0);
}

TEST(SweepAndPrune, RandomDoubleScenesContainBruteForce) {
  Rng rng(777001);
  RunStats stats;
  for (int scene = 0; scene < 300; ++scene) {
    SCOPED_TRACE(testing::Message() << "scene " << scene);
    runScene(rng, false, &stats);
    if (::testing::Test::HasFatalFailure()) return;
  }
  std::printf("double scenes: %d updates, %d rebuilds, %lld pairs (%lld within float "
              "rounding of touching), %lld began, %lld ended\n",
              stats.updates, stats.rebuilds, static_cast<long long>(stats.pairs_total),
              static_cast<long long>(stats.extra_pairs), static_cast<long long>(stats.began),
              static_cast<long long>(stats.ended));
  EXPECT_GT(stats.updates, 1800);
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
