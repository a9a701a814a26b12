#include "sweep_and_prune_insert.hpp"

#include <algorithm>
#include <cmath>

#include "sweep_and_prune_state.hpp"

namespace workspace_proximity {
namespace sap {
namespace {

// Endpoint positions [from, to) of one axis that a new proxy must look at.
struct Window {
  std::size_t from = 0, to = 0;
};

void mergeNewEndpoints(State& s, int axis) {
  std::vector<std::uint64_t>& items = s.sort.items;
  items.clear();
  for (ProxyId id : s.pending_insert) {
    const std::uint64_t owner = static_cast<std::uint64_t>(id) << 1;
    items.push_back(owner);
    items.push_back(owner | 1u);
  }
  const std::uint64_t* e = s.ends[axis].data();
  std::sort(items.begin(), items.end(), [e](std::uint64_t x, std::uint64_t y) { return e[x] < e[y]; });

  std::vector<std::uint64_t>& keys = s.keys[axis];
  std::vector<std::uint32_t>& owners = s.owners[axis];
  const std::size_t old_size = keys.size();
  keys.resize(old_size + items.size());
  owners.resize(old_size + items.size());
  std::int64_t i = static_cast<std::int64_t>(old_size) - 2;  // last old real endpoint
  std::int64_t j = static_cast<std::int64_t>(items.size()) - 1;
  std::int64_t w = static_cast<std::int64_t>(keys.size()) - 2;
  keys.back() = kHighSentinel;
  owners.back() = kSentinelOwner;
  while (j >= 0) {
    const std::uint64_t new_key = e[items[j]];
    if (i >= 1 && keys[i] > new_key) {
      keys[w] = keys[i];
      owners[w] = owners[i];
      --i;
    } else {
      keys[w] = new_key;
      owners[w] = static_cast<std::uint32_t>(items[j]);
      --j;
    }
    --w;
  }
}

Window window(const State& s, int axis, ProxyId p) {
  // Positions in the endpoint array of `axis` from its lower bound minus the widest width
  // (with rounding slack) up to its upper bound.
  const std::uint64_t* keys = s.keys[axis].data();
  const std::uint64_t* begin = keys + 1;
  const std::uint64_t* end = keys + s.keys[axis].size() - 1;
  const std::uint64_t* kp = s.ends[axis].data() + 2 * static_cast<std::size_t>(p);
  const double low = unsortable64(kp[0]);
  const double reach = s.max_width[axis] + 1e-12 * (std::abs(low) + s.max_width[axis]) + 1e-300;
  Window w;
  w.from = static_cast<std::size_t>(std::lower_bound(begin, end, lower64(low - reach)) - keys);
  w.to = static_cast<std::size_t>(std::upper_bound(begin, end, kp[1]) - keys);
  return w;
}

int cheapestWindowAxis(const State& s, std::int64_t limit) {
  // The axis whose windows hold the fewest endpoints in all, if at most `limit`; else -1.
  int best_axis = -1;
  std::int64_t best_total = limit;
  for (int axis = 0; axis < 3; ++axis) {
    if (s.stale[axis]) continue;  // out of order: no windows to look up
    std::int64_t total = 0;
    for (ProxyId id : s.pending_insert) {
      const Window w = window(s, axis, id);
      total += static_cast<std::int64_t>(w.to - w.from);
      if (total > best_total) break;
    }
    if (total <= best_total) {
      best_total = total;
      best_axis = axis;
    }
  }
  return best_axis;
}

bool insertByWindows(State& s) {
  // A few insertions: each new proxy looks only at the lower endpoints that can belong to a
  // box overlapping it on one axis, those within its window (see window()). False when a
  // sweep is cheaper.
  const std::size_t k = s.pending_insert.size();
  const std::size_t n = s.keys[0].size() - 2;
  if (32 * k > n) return false;
  const int axis = cheapestWindowAxis(s, static_cast<std::int64_t>(n / 4));
  if (axis < 0) return false;

  const std::uint32_t* owners = s.owners[axis].data();
  for (ProxyId p : s.pending_insert) {
    const Window w = window(s, axis, p);
    for (std::size_t i = w.from; i < w.to; ++i) {
      const std::uint32_t o = owners[i];
      if (o & 1u) continue;
      const std::int32_t q = static_cast<std::int32_t>(o >> 1);
      if (q == p || (s.info[q].is_new && q > p)) continue;  // new pairs once, from the lower id
      if (s.overlaps(p, q)) s.beginPair(p, q);
    }
  }
  return true;
}

}  // namespace

void insertPending(State& s) {
  if (s.pending_insert.empty()) return;
  const std::size_t k = s.pending_insert.size();
  s.stats.inserted = static_cast<int>(k);
  // Batched: sort the new endpoints, then merge them into each axis from the back, so one
  // insertion costs O(n + k log k) instead of k passes of insertion sort.
  for (int axis = 0; axis < 3; ++axis) mergeNewEndpoints(s, axis);
  for (ProxyId id : s.pending_insert) {
    s.info[id].state = ProxyState::kLive;
    s.info[id].is_new = true;
  }
  s.live_count += static_cast<int>(k);

  if (!insertByWindows(s)) {
    std::int64_t tests = 0;
    const int axis = cheapestSweepAxis(s, &tests);
    s.sweep_tests = tests;
    // Everything new (say the first update): a slab sweep may find all pairs, each once.
    findPairs(s, axis, tests,
              k == static_cast<std::size_t>(s.live_count) ? SweepMode::kAllNew : SweepMode::kNewOnly);
  }
  for (ProxyId id : s.pending_insert) s.info[id].is_new = false;
  s.pending_insert.clear();
}

}  // namespace sap
}  // namespace workspace_proximity
