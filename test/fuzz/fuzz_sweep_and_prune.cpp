// libFuzzer harness over SweepAndPrune alone: create, move, destroy and update proxies with
// valid bounds, and after every update() compare the structure with brute force.
//
// Two coordinate modes, chosen by the input's first byte:
//  - exact: every coordinate is int16 / 64 (exact in float and double; signed zeros too), so
//    the pair set must equal the closed-interval overlap test of the given bounds;
//  - wide: any finite doubles, often a few ulps apart from each other, so the pair set must
//    contain every pair the given bounds overlap (conservative) and only pairs whose
//    storedBounds() (the outward-rounded bounds it tests with, which must contain the given
//    ones) overlap. Not required: equality with the storedBounds() test, because a stored
//    bound just below +0 reads back as -0.0, which compares equal to +0.
// Also checked: began/ended equal the differences with the previous pair set, pairs are
// stored with proxy_a < proxy_b, hasPair() agrees with pairs(), and proxyCount() matches.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "fuzz_input.hpp"
#include "oracles.hpp"
#include "workspace_proximity/sweep_and_prune.hpp"

namespace wp = workspace_proximity;
using wp_fuzz::fail;
using wp_fuzz::Input;
using ProxyId = wp::SweepAndPrune::ProxyId;
using Pair = std::pair<ProxyId, ProxyId>;

namespace {

constexpr int kMaxProxies = 64;
constexpr int kMaxOperations = 400;

using wp_fuzz::str;

std::string str(const wp::Aabb& b) {
  std::string s = "[";
  for (int k = 0; k < 3; ++k) s += str(b.lower[k]) + ".." + str(b.upper[k]) + (k < 2 ? ", " : "]");
  return s;
}

std::string str(const Pair& p) { return "(" + std::to_string(p.first) + "," + std::to_string(p.second) + ")"; }

// Closed intervals, in double: touching boxes overlap (the brute-force oracle).
bool overlap(const wp::Aabb& a, const wp::Aabb& b) { return oracle::aabbOverlap(a, b); }

struct ModelProxy {
  wp::Aabb bounds;
  bool inserted = false;         // has been through an update()
  bool pending_remove = false;   // destroyed, update() not yet run
  wp::Aabb rest;                 // where it was created or last moved to (tracker noise's centre)
};

class Harness {
 public:
  explicit Harness(Input& in) : in_(in), exact_((in.byte() & 1) == 0), sap_(makeConfig(in)) {
    for (double& a : anchors_) {
      a = in_.number();
      if (!std::isfinite(a)) a = 0.0;
    }
  }

  void run() {
    for (int op = 0; op < kMaxOperations && !in_.empty(); ++op) {
      switch (in_.byte() % 8) {
        case 0:
        case 1:
          create();
          break;
        case 2:
          move();
          break;
        case 3:
          destroy();
          break;
        case 4:
          jitter();
          break;
        default:
          update();
          break;
      }
    }
    update();
  }

 private:
  static wp::SweepAndPruneConfig makeConfig(Input& in) {
    const std::uint8_t b = in.byte();
    wp::SweepAndPruneConfig c;
    static const int capacities[] = {1, 2, 5, 256};
    c.initial_proxy_capacity = wp_fuzz::pickByBits(capacities, b, 0);
    c.initial_pair_capacity = wp_fuzz::pickByBits(capacities, b, 2);
    static const double factors[] = {1.0, 0.0, 0.05, 0.5, 2.0, 1e9, 1e-3, 1.0};
    c.rebuild_factor = wp_fuzz::pickByBits(factors, b, 4);
    static const double leads[] = {8.0, 0.0};  // coasting on (the default) or off
    c.coast_updates = wp_fuzz::pickByBits(leads, b, 7);
    // The last factor (1.0 again) also shortens coasting's lead to 4 updates: its runs reach
    // their longest (16 updates) within an input's updates, and their ends are then spread
    // over the updates before them (the next arrays, issue 26). An input needs ~40 updates
    // without insertions or removals for that; a seed that did it (6 boxes jittering, 1.3 KB)
    // made the CI run of this harness 222 s instead of 8 (libFuzzer's inputs grow to the
    // longest seed), so none is committed: the brute-force gtests cover the path, and a
    // campaign (scripts/fuzz) can reach it.
    if (((b >> 4) & 7) == 7 && c.coast_updates > 0.0) c.coast_updates = 4.0;
    return c;
  }

  // ---- bounds ---------------------------------------------------------------------------

  double exactCoordinate() {
    const double v = static_cast<std::int16_t>(in_.u16()) / 64.0;
    return (v == 0.0 && in_.flag()) ? -0.0 : v;
  }

  // Any finite double; often an anchor moved by a few ulps, so bounds nearly touch.
  double wideCoordinate() {
    const std::uint8_t s = in_.byte();
    if (s < 128) {
      double v = anchors_[s & 7];
      const int steps = static_cast<std::int8_t>(in_.byte()) % 4;
      for (int i = 0; i < std::abs(steps); ++i) {
        v = std::nextafter(v, steps > 0 ? std::numeric_limits<double>::infinity()
                                        : -std::numeric_limits<double>::infinity());
      }
      return std::isfinite(v) ? v : anchors_[s & 7];
    }
    const double v = in_.number();
    return std::isfinite(v) ? v : 0.0;
  }

  wp::Aabb bounds() {
    wp::Aabb b;
    for (int k = 0; k < 3; ++k) {
      if (exact_) {
        const double lo = exactCoordinate();
        const double width = in_.byte() < 24 ? 0.0 : in_.u16() / 64.0;
        b.lower[k] = lo;
        b.upper[k] = lo + width;  // at most 2^17 / 64: still exact in float
      } else {
        const double x = wideCoordinate();
        const double y = in_.byte() < 24 ? x : wideCoordinate();
        b.lower[k] = std::min(x, y);
        b.upper[k] = std::max(x, y);
      }
    }
    return b;
  }

  // ---- operations -----------------------------------------------------------------------

  // A proxy that may be moved or destroyed (not already destroyed), or -1.
  ProxyId pick() {
    std::vector<ProxyId> ids;
    for (const auto& kv : proxies_) {
      if (!kv.second.pending_remove) ids.push_back(kv.first);
    }
    const std::uint8_t b = in_.byte();
    if (ids.empty()) return -1;
    return ids[b % ids.size()];
  }

  void create() {
    if (static_cast<int>(proxies_.size()) >= kMaxProxies) return;
    const wp::Aabb b = bounds();
    in_.u32();  // was the proxy's user data: read on, so the seed corpus keeps its meaning
    const ProxyId id = sap_.createProxy(b);
    if (id < 0) fail("createProxy returned a negative id", std::to_string(id));
    if (proxies_.count(id) != 0) fail("createProxy reused an id still in use", std::to_string(id));
    proxies_[id] = ModelProxy{b, false, false, b};
  }

  void move() {
    const ProxyId id = pick();
    if (id < 0) return;
    const wp::Aabb b = bounds();
    sap_.moveProxy(id, b);
    proxies_[id].bounds = b;
    proxies_[id].rest = b;
  }

  void destroy() {
    const ProxyId id = pick();
    if (id < 0) return;
    sap_.destroyProxy(id);
    if (proxies_[id].inserted) {
      proxies_[id].pending_remove = true;
    } else {
      proxies_.erase(id);  // never entered the structure: gone at once
    }
  }

  // Small motion of every proxy: the incremental insertion-sort path. With the scale's top bit,
  // a tracker's noise instead: fresh offsets from where each proxy was created or last moved
  // to (coasting's per-proxy jitter bounds and drifts; issue 26).
  void jitter() {
    const std::uint8_t scale = in_.byte();
    const bool noise = (scale & 128) != 0;
    for (auto& kv : proxies_) {
      if (kv.second.pending_remove) continue;
      wp::Aabb b = noise ? kv.second.rest : kv.second.bounds;
      for (int k = 0; k < 3; ++k) {
        double d;
        if (exact_) {
          d = static_cast<std::int8_t>(in_.byte()) / 64.0 * (1 + (scale & 7));
        } else {
          d = static_cast<std::int8_t>(in_.byte()) * std::ldexp(1.0, (scale & 63) - 40);
        }
        const double lo = b.lower[k] + d, hi = b.upper[k] + d;
        if (std::isfinite(lo) && std::isfinite(hi) && lo <= hi) {
          b.lower[k] = lo;
          b.upper[k] = hi;
        }
      }
      sap_.moveProxy(kv.first, b);
      kv.second.bounds = b;
    }
  }

  void update() {
    sap_.update();
    for (auto it = proxies_.begin(); it != proxies_.end();) {
      if (it->second.pending_remove) {
        it = proxies_.erase(it);
      } else {
        it->second.inserted = true;
        ++it;
      }
    }
    check();
    ++updates_;
  }

  // ---- invariants after update ------------------------------------------------------------

  void check() {
    if (sap_.proxyCount() != static_cast<int>(proxies_.size())) {
      fail("proxyCount() differs from the live proxies",
           std::to_string(sap_.proxyCount()) + " vs " + std::to_string(proxies_.size()));
    }
    std::map<ProxyId, wp::Aabb> stored, enlarged;
    for (const auto& kv : proxies_) {
      const wp::Aabb s = sap_.storedBounds(kv.first);
      const wp::Aabb& g = kv.second.bounds;
      for (int k = 0; k < 3; ++k) {
        if (!(s.lower[k] <= g.lower[k]) || !(s.upper[k] >= g.upper[k])) {
          fail("storedBounds() does not contain the given bounds",
               std::to_string(kv.first) + " given " + str(g) + " stored " + str(s));
        }
      }
      // The enlarged bounds the arrays sort (coasting) contain the stored ones.
      const wp::Aabb e = sap_.enlargedBounds(kv.first);
      for (int k = 0; k < 3; ++k) {
        if (!(e.lower[k] <= s.lower[k]) || !(e.upper[k] >= s.upper[k])) {
          fail("enlargedBounds() does not contain storedBounds()",
               std::to_string(kv.first) + " stored " + str(s) + " enlarged " + str(e));
        }
      }
      stored[kv.first] = s;
      enlarged[kv.first] = e;
    }

    // The structure's pairs, each once, ordered, naming live proxies, known to hasPair().
    std::set<Pair> actual;
    for (const wp::BroadPair& p : sap_.pairs()) {
      const Pair key{p.proxy_a, p.proxy_b};
      if (!(p.proxy_a < p.proxy_b)) fail("pair not stored with proxy_a < proxy_b", str(key));
      if (proxies_.count(p.proxy_a) == 0 || proxies_.count(p.proxy_b) == 0) {
        fail("pair names a proxy that is not live", str(key));
      }
      if (!actual.insert(key).second) fail("pair listed twice", str(key));
      if (!sap_.hasPair(p.proxy_b, p.proxy_a) || !sap_.hasPair(p.proxy_a, p.proxy_b)) {
        fail("hasPair() does not know a listed pair", str(key));
      }
    }

    // The candidates: exactly the pairs whose enlarged bounds overlap (closed intervals on the
    // values the keys stand for), each once.
    std::set<Pair> candidates;
    for (const wp::BroadPair& p : sap_.candidatePairs()) {
      const Pair key{std::min(p.proxy_a, p.proxy_b), std::max(p.proxy_a, p.proxy_b)};
      if (!candidates.insert(key).second) fail("candidate listed twice", str(key));
    }
    for (auto i = proxies_.begin(); i != proxies_.end(); ++i) {
      for (auto j = std::next(i); j != proxies_.end(); ++j) {
        const Pair key{i->first, j->first};
        const bool fat = oracle::readBackOverlap(enlarged[i->first], enlarged[j->first]);
        if (fat != (candidates.count(key) != 0)) {
          fail(fat ? "candidate missing" : "stale candidate",
               str(key) + " enlarged " + str(enlarged[i->first]) + " " + str(enlarged[j->first]));
        }
      }
    }

    // Brute force.
    std::set<Pair> expected;
    for (auto i = proxies_.begin(); i != proxies_.end(); ++i) {
      for (auto j = std::next(i); j != proxies_.end(); ++j) {
        const Pair key{i->first, j->first};
        const bool given = overlap(i->second.bounds, j->second.bounds);
        const bool by_stored = overlap(stored[i->first], stored[j->first]);
        const bool listed = actual.count(key) != 0;
        // Formatted only on a failure: formatting it for every pair made long inputs (hundreds
        // of updates of 64 proxies) take seconds each.
        auto detail = [&]() {
          return str(key) + " " + str(i->second.bounds) + " " + str(j->second.bounds) +
                 " stored " + str(stored[i->first]) + " " + str(stored[j->first]);
        };
        // given overlap => listed => overlap of the stored (outward-rounded) bounds; in exact
        // mode the rounding changes nothing, so listed <=> given.
        if (given && !listed) fail("overlapping pair missing", detail());
        if (exact_ && listed && !given) fail("pair listed but the boxes do not overlap", detail());
        if (listed && !by_stored) fail("pair listed but its storedBounds() do not overlap", detail());
        if (listed) expected.insert(key);
        if (!listed && sap_.hasPair(key.first, key.second)) {
          fail("hasPair() knows an unlisted pair", detail());
        }
      }
    }

    // began = now - before, ended = before - now.
    std::set<Pair> began, ended;
    for (const wp::BroadPair& p : sap_.beganPairs()) {
      const Pair key{std::min(p.proxy_a, p.proxy_b), std::max(p.proxy_a, p.proxy_b)};
      if (!began.insert(key).second) fail("pair began twice", str(key));
    }
    for (const wp::BroadPair& p : sap_.endedPairs()) {
      const Pair key{std::min(p.proxy_a, p.proxy_b), std::max(p.proxy_a, p.proxy_b)};
      if (!ended.insert(key).second) fail("pair ended twice", str(key));
    }
    for (const Pair& key : expected) {
      const bool before = previous_.count(key) != 0;
      if (!before && began.count(key) == 0) fail("new pair not in beganPairs()", str(key));
      if (before && began.count(key) != 0) fail("lasting pair in beganPairs()", str(key));
      if (before && ended.count(key) != 0) fail("lasting pair in endedPairs()", str(key));
    }
    for (const Pair& key : began) {
      if (expected.count(key) == 0) fail("beganPairs() lists a pair not in pairs()", str(key));
    }
    for (const Pair& key : previous_) {
      const bool now = expected.count(key) != 0;
      if (!now && ended.count(key) == 0) fail("vanished pair not in endedPairs()", str(key));
    }
    for (const Pair& key : ended) {
      if (previous_.count(key) == 0 || expected.count(key) != 0) {
        fail("endedPairs() lists a pair that did not end", str(key));
      }
    }
    previous_ = expected;
  }

  Input& in_;
  const bool exact_;
  wp::SweepAndPrune sap_;
  double anchors_[8] = {};
  std::map<ProxyId, ModelProxy> proxies_;  // created and not yet removed by an update()
  std::set<Pair> previous_;  // pairs after the last update
  int updates_ = 0;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return wp_fuzz::runHarness<Harness>(data, size);
}
