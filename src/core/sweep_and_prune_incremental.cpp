#include "sweep_and_prune_incremental.hpp"

#include <algorithm>

#include "sweep_and_prune_coasting.hpp"
#include "sweep_and_prune_state.hpp"

namespace workspace_proximity {
namespace sap {
namespace {

}  // namespace

std::int64_t estimateSwapsOf(const std::vector<std::uint64_t>& keys) {
  // Insertion sort's swaps are the inversions of the keys just read against the array's order:
  // the sum over d >= 1 of the endpoints whose key is below the one d places before. Counted at
  // d = 1, 2, 4, ..., 64 for every 4th endpoint (about 1 000 endpoints on large axes); the
  // count at d = 2^j stands for the 2^(j-1) distances in (2^(j-1), 2^j]. Measured on the
  // uniform scenes this gives 75-93 % of the swaps at up to 10 swaps per endpoint, hence the
  // 5/4 (larger motion: an underestimate of a large number).
  const std::uint64_t* key = keys.data();
  const std::size_t last = keys.size() - 1;
  const std::size_t stride = std::max<std::size_t>(4, last / 1024);
  std::int64_t below[7] = {0, 0, 0, 0, 0, 0, 0};
  for (std::size_t i = 2; i < last; i += stride) {
    const std::uint64_t k = key[i];
    for (int j = 0; j < 7; ++j) {
      const std::size_t d = std::size_t{1} << j;
      if (d < i) below[j] += key[i - d] > k;
    }
  }
  std::int64_t sampled = below[0];
  for (int j = 1; j < 7; ++j) sampled += below[j] << (j - 1);
  return 5 * static_cast<std::int64_t>(stride) * sampled / 4;
}

namespace {

// The swaps an insertion sort of `axis` would make, estimated from its keys (just read).
std::int64_t estimateSwaps(const State& s, int axis) { return estimateSwapsOf(s.keys[axis]); }

std::size_t findBreaks(State& s, int axis, bool refresh) {
  // Without branches: read the current keys (if asked) and list the positions where the order
  // breaks. Between two breaks the endpoints are already in order.
  std::uint64_t* key = s.keys[axis].data();
  const std::uint32_t* owner = s.owners[axis].data();
  const std::uint64_t* e = s.ends[axis].data();
  const std::size_t last = s.keys[axis].size() - 1;  // high sentinel
  s.breaks.resize(last + 1);
  std::uint32_t* brk = s.breaks.data();
  std::size_t count = 0;
  std::uint64_t prev = kLowSentinel;
  if (refresh) {
    for (std::size_t i = 1; i < last; ++i) {
      const std::uint64_t k = e[owner[i]];
      key[i] = k;
      brk[count] = static_cast<std::uint32_t>(i);
      count += k < prev;
      prev = k;
    }
  } else {
    for (std::size_t i = 1; i < last; ++i) {
      const std::uint64_t k = key[i];
      brk[count] = static_cast<std::uint32_t>(i);
      count += k < prev;
      prev = k;
    }
  }
  brk[count] = static_cast<std::uint32_t>(last);
  return count;
}

inline std::size_t sinkEndpoint(State& s, int axis, std::size_t i) {
  // Moves the endpoint at i down to its place. Passing an endpoint of the other kind starts or
  // ends an overlap on this axis. Returns its new position.
  std::uint64_t* key = s.keys[axis].data();
  std::uint32_t* owner = s.owners[axis].data();
  const std::uint64_t k = key[i];
  const std::uint32_t o = owner[i];
  const std::uint32_t o_upper = o & 1u;
  const std::int32_t p = static_cast<std::int32_t>(o >> 1);
  std::size_t j = i;
  do {
    const std::uint32_t o2 = owner[j - 1];
    if ((o2 & 1u) != o_upper) {
      const std::int32_t q = static_cast<std::int32_t>(o2 >> 1);
      if (o_upper == 0u) {
        // p's lower passes below q's upper: they may now overlap on every axis.
        if (s.overlapsAcross(p, q, axis)) s.beginPair(p, q);
      } else {
        // p's upper passes below q's lower: separated on this axis.
        if (s.mayBePaired(p, q, axis)) s.endPair(p, q);
      }
    }
    key[j] = key[j - 1];
    owner[j] = o2;
    --j;
  } while (key[j - 1] > k);  // the low sentinel (key 0) stops this
  key[j] = k;
  owner[j] = o;
  return j;
}

bool sortRuns(State& s, int axis, std::size_t breaks, std::int64_t budget, std::int64_t* swaps) {
  // Insertion sort that starts at each break and stops once an endpoint is not below
  // everything before it (the rest of that run then is in place too).
  const std::uint64_t* key = s.keys[axis].data();
  const std::uint32_t* brk = s.breaks.data();
  std::int64_t total = *swaps;
  for (std::size_t t = 0; t < breaks; ++t) {
    const std::size_t next = brk[t + 1];
    for (std::size_t i = brk[t]; i < next; ++i) {
      if (key[i - 1] <= key[i]) break;
      total += static_cast<std::int64_t>(i - sinkEndpoint(s, axis, i));
      if (total > budget) {
        *swaps = total;
        return false;
      }
    }
  }
  *swaps = total;
  return true;
}

std::size_t findEndpoint(const State& s, int axis, std::uint64_t key, std::uint32_t owner) {
  const std::uint64_t* keys = s.keys[axis].data();
  const std::uint32_t* owners = s.owners[axis].data();
  std::size_t i = static_cast<std::size_t>(
      std::lower_bound(keys + 1, keys + s.keys[axis].size() - 1, key) - keys);
  while (owners[i] != owner) ++i;  // equal keys: it is among them
  return i;
}

std::size_t relocateEndpoint(State& s, int axis, std::size_t i, std::uint64_t k) {
  // Moves one endpoint to its new key, down or up; returns the swaps. Passing an endpoint of
  // the other kind changes whether the two overlap on this axis: they start to when p's lower
  // moves below or p's upper moves above the other's, and stop in the other two cases. A pair
  // is added or removed by the final keys on every axis (so no pair both ends and begins).
  std::uint64_t* key = s.keys[axis].data();
  std::uint32_t* owner = s.owners[axis].data();
  const std::uint32_t o = owner[i];
  const std::uint32_t o_upper = o & 1u;
  const std::int32_t p = static_cast<std::int32_t>(o >> 1);
  auto pass = [&](std::uint32_t o2, bool starts) {
    if ((o2 & 1u) == o_upper) return;
    const std::int32_t q = static_cast<std::int32_t>(o2 >> 1);
    if (starts) {
      if (s.overlapsAcross(p, q, axis)) s.beginPair(p, q);
    } else if (!s.overlapsAcross(p, q, axis)) {
      s.endPair(p, q);
    }
  };
  std::size_t j = i;
  while (key[j - 1] > k) {  // the low sentinel (key 0) stops this
    pass(owner[j - 1], o_upper == 0u);
    key[j] = key[j - 1];
    owner[j] = owner[j - 1];
    --j;
  }
  while (key[j + 1] < k) {  // the high sentinel (all ones) stops this
    pass(owner[j + 1], o_upper != 0u);
    key[j] = key[j + 1];
    owner[j] = owner[j + 1];
    ++j;
  }
  key[j] = k;
  owner[j] = o;
  return j > i ? j - i : i - j;
}

}  // namespace

bool sortAxes(State& s, bool refresh, std::int64_t budget) {
  std::int64_t swaps = 0;
  bool within_budget = true;
  for (int axis = 0; axis < 3 && within_budget; ++axis) {
    const std::size_t breaks = findBreaks(s, axis, refresh);
    within_budget = sortRuns(s, axis, breaks, budget, &swaps);
  }
  s.stats.swaps = swaps;
  return within_budget;
}

void rollBack(State& s, std::size_t began_mark, std::size_t ended_mark) {
  for (std::size_t i = began_mark; i < s.cand_began.size(); ++i) {
    s.cands.erase(s.cand_began[i].proxy_a, s.cand_began[i].proxy_b);
  }
  for (std::size_t i = ended_mark; i < s.cand_ended.size(); ++i) {
    Candidate* pair = s.cands.insert(s.cand_ended[i].proxy_a, s.cand_ended[i].proxy_b, nullptr);
    *pair = s.cand_ended[i];
  }
  s.cand_began.resize(began_mark);
  s.cand_ended.resize(ended_mark);
}

void refreshKeys(State& s) {
  for (int axis = 0; axis < 3; ++axis) refreshAxis(s, axis);
}

void refreshAxis(State& s, int axis) {
  std::uint64_t* key = s.keys[axis].data();
  const std::uint32_t* owner = s.owners[axis].data();
  const std::uint64_t* e = s.ends[axis].data();
  const std::size_t last = s.keys[axis].size() - 1;
  for (std::size_t i = 1; i < last; ++i) key[i] = e[owner[i]];
}

std::int64_t estimateAllSwaps(State& s) {
  // Reads the keys of every axis in order (all three, or only the sweep axis after a streak
  // rebuild: then scaled by the three axes' share of the last full estimate).
  if (s.anyStale()) {
    refreshAxis(s, s.sweep_axis);
    return static_cast<std::int64_t>(s.swap_scale * static_cast<double>(estimateSwaps(s, s.sweep_axis)));
  }
  refreshKeys(s);
  std::int64_t per_axis[3], total = 0;
  for (int axis = 0; axis < 3; ++axis) total += per_axis[axis] = estimateSwaps(s, axis);
  const double share = static_cast<double>(std::max<std::int64_t>(per_axis[s.sweep_axis], 1));
  s.swap_scale = std::clamp(static_cast<double>(total) / share, 1.0, 3.0);
  return total;
}

std::size_t moveEscapers(State& s) {
  // New enlarged keys for all of them first: the pair tests below use the final keys of both
  // proxies, so that a pair between two escapers is decided once, whatever the order.
  const std::vector<ProxyId>& escapers = s.escapers;
  std::vector<std::uint64_t>& old = s.escaper_old;
  old.resize(6 * escapers.size());
  for (std::size_t n = 0; n < escapers.size(); ++n) {
    const std::size_t o = 2 * static_cast<std::size_t>(escapers[n]);
    for (int axis = 0; axis < 3; ++axis) {
      old[6 * n + 2 * axis] = s.ends[axis][o];
      old[6 * n + 2 * axis + 1] = s.ends[axis][o + 1];
    }
    enlarge(s, escapers[n], s.coast.lead());
  }
  std::size_t swaps = 0;
  for (int axis = 0; axis < 3; ++axis) {
    for (std::size_t n = 0; n < escapers.size(); ++n) {
      const std::uint32_t lower = static_cast<std::uint32_t>(escapers[n]) << 1;
      const std::uint64_t old_lo = old[6 * n + 2 * axis];
      const std::uint64_t old_hi = old[6 * n + 2 * axis + 1];
      const std::uint64_t new_lo = s.ends[axis][lower];
      const std::uint64_t new_hi = s.ends[axis][lower + 1];
      // Move them so that the lower endpoint never passes its own upper one.
      if (new_lo > old_hi) {
        swaps += relocateEndpoint(s, axis, findEndpoint(s, axis, old_hi, lower | 1u), new_hi);
        swaps += relocateEndpoint(s, axis, findEndpoint(s, axis, old_lo, lower), new_lo);
      } else {
        swaps += relocateEndpoint(s, axis, findEndpoint(s, axis, old_lo, lower), new_lo);
        swaps += relocateEndpoint(s, axis, findEndpoint(s, axis, old_hi, lower | 1u), new_hi);
      }
      if (axis > 0) {
        s.prev_ends[axis][lower] = new_lo;
        s.prev_ends[axis][lower + 1] = new_hi;
      }
    }
  }
  return swaps;
}

}  // namespace sap
}  // namespace workspace_proximity
