#pragma once
/// Incremental sweep-and-prune on three axes (insertion sort of persistent endpoint arrays).
///
/// Each proxy's bounds are stored as three pairs of 32-bit sortable keys: the double bound
/// is rounded outward to float, mapped to an order-preserving unsigned integer, and the low
/// bit is forced to 0 for lower and 1 for upper endpoints. Lower keys are therefore always
/// below upper keys at equal coordinates, so touching boxes overlap, and the integer test is
/// never less conservative than the double one.
///
/// update() re-sorts every axis by insertion sort. A swap of a lower endpoint of A past an
/// upper endpoint of B starts an overlap on that axis: the pair is added when the two boxes
/// overlap on all three axes. The opposite swap ends an overlap: the pair is removed. Pairs
/// are kept in an open-addressing table; update() reports those that began and ended.
/// When insertion sort would cost more than a rebuild (too many swaps) it falls back to a
/// full sort and sweep and diffs the result against the previous pair set.

#include <cstdint>
#include <vector>

#include "workspace_proximity/aabb.hpp"
#include "workspace_proximity/pair_table.hpp"

namespace workspace_proximity {

struct SweepAndPruneConfig {
  int initial_proxy_capacity = 256;   ///< proxies preallocated
  int initial_pair_capacity = 1024;   ///< overlapping pairs preallocated
  /// Insertion sort gives up and rebuilds once the swaps of one update exceed
  /// rebuild_factor * n * log2(n) (n = endpoints per axis). A rebuild is one full sort.
  double rebuild_factor = 1.0;
};

/// Counters of the last update(), for benchmarks and diagnostics.
struct SweepAndPruneStats {
  std::int64_t swaps = 0;       ///< insertion-sort swaps over three axes
  bool rebuilt = false;         ///< fell back to a full sort-and-sweep
  int inserted = 0;             ///< proxies inserted (batched)
  int removed = 0;              ///< proxies removed (batched)
};

class SweepAndPrune {
 public:
  using ProxyId = std::int32_t;

  explicit SweepAndPrune(const SweepAndPruneConfig& config = SweepAndPruneConfig());

  /// New proxy with the given bounds; it joins the structure (and its pairs are reported)
  /// at the next update(). `user_data` is returned with its pairs. Bounds must be valid().
  ProxyId createProxy(const Aabb& bounds, std::uint32_t user_data);
  /// Remove a proxy; its pairs are reported as ended at the next update(). The id may be
  /// reused by a later createProxy().
  void destroyProxy(ProxyId proxy);
  /// New bounds for a live proxy; takes effect at the next update().
  void moveProxy(ProxyId proxy, const Aabb& bounds);

  /// Applies removals, moves and insertions; fills beganPairs() and endedPairs().
  void update();

  /// Every pair overlapping after the last update(), in no particular order.
  const std::vector<ProxyPair>& pairs() const { return pairs_.pairs(); }
  /// Pairs that started overlapping in the last update().
  const std::vector<ProxyPair>& beganPairs() const { return began_; }
  /// Pairs that stopped overlapping (or lost a proxy) in the last update().
  const std::vector<ProxyPair>& endedPairs() const { return ended_; }

  /// Live pair record for (a, b), or nullptr. Its `user` field belongs to the caller.
  ProxyPair* findPair(ProxyId a, ProxyId b) { return pairs_.find(a, b); }
  /// The current pairs, for writing their `user` fields (nothing else may be changed).
  std::vector<ProxyPair>& mutablePairs() { return pairs_.mutablePairs(); }

  std::uint32_t userData(ProxyId proxy) const { return proxies_[proxy].user; }
  /// The bounds the structure tests with (outward-rounded to float).
  Aabb storedBounds(ProxyId proxy) const;
  int proxyCount() const { return live_count_; }
  const SweepAndPruneStats& stats() const { return stats_; }

  /// Keys: order-preserving map of a float to uint32, rounded outward and tagged.
  static std::uint32_t lowerKey(double value);
  static std::uint32_t upperKey(double value);
  static double keyValue(std::uint32_t key);

 private:
  enum class ProxyState : std::uint8_t { kFree, kPendingInsert, kLive };

  struct Proxy {
    std::uint32_t lower[3];       // keys
    std::uint32_t upper[3];
    std::int32_t lower_index[3];  // position of the endpoint in axis arrays
    std::int32_t upper_index[3];
    std::uint32_t user;
    std::int32_t next_free;
    ProxyState state;
    bool pending_remove;
  };

  bool overlaps(const Proxy& a, const Proxy& b) const {
    return a.lower[0] < b.upper[0] && b.lower[0] < a.upper[0] && a.lower[1] < b.upper[1] &&
           b.lower[1] < a.upper[1] && a.lower[2] < b.upper[2] && b.lower[2] < a.upper[2];
  }
  void setIndex(std::uint32_t owner, int axis, std::int32_t index);
  void applyRemovals();
  bool sortAxes();  // false when the swap budget ran out
  void rollBack(std::size_t began_mark, std::size_t ended_mark);
  void rebuild();
  void insertPending();
  void sweepForPairs(bool only_new);
  void foundPair(std::int32_t a, std::int32_t b, bool rebuild);
  void beginPair(std::int32_t a, std::int32_t b);
  void endPair(std::int32_t a, std::int32_t b);

  SweepAndPruneConfig config_;
  std::vector<Proxy> proxies_;
  std::int32_t free_list_ = -1;
  int live_count_ = 0;

  // Endpoint arrays per axis, with a sentinel at each end: key[0] = 0, key[last] = ~0u.
  // owner = proxy << 1 | is_upper.
  std::vector<std::uint32_t> keys_[3];
  std::vector<std::uint32_t> owners_[3];

  std::vector<ProxyId> pending_insert_;
  std::vector<ProxyId> pending_remove_;
  bool any_removed_ = false;

  PairTable pairs_;
  std::vector<ProxyPair> began_;
  std::vector<ProxyPair> ended_;

  // Scratch, kept between updates so steady-state updates allocate nothing.
  std::vector<std::uint64_t> scratch_;
  std::vector<std::int32_t> active_;       // sweep: open intervals of old proxies
  std::vector<std::int32_t> active_new_;   // sweep: open intervals of inserted proxies
  std::vector<std::int32_t> active_pos_;   // per proxy: position in its active list
  std::vector<std::uint8_t> is_new_;       // per proxy: inserted in this update
  SweepAndPruneStats stats_;
  std::uint32_t epoch_ = 0;
};

}  // namespace workspace_proximity
