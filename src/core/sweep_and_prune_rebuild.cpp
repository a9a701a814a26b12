#include "sweep_and_prune_rebuild.hpp"

#include <algorithm>
#include <cstring>
#include <limits>

#include "sweep_and_prune_incremental.hpp"
#include "sweep_and_prune_state.hpp"

namespace workspace_proximity {
namespace sap {
namespace {

// A plain sweep with fewer overlap tests per proxy than this is cheaper than a slab sweep.
constexpr std::int64_t kSlabTestsPerProxy = 16;

// Four 32-bit lanes (GCC and Clang vector extension: SSE2 on x86-64, NEON on ARM, plain code
// elsewhere). Comparisons give -1 (true) or 0 per lane.
using Lanes4 = std::int32_t __attribute__((vector_size(16)));

inline Lanes4 splat4(std::int32_t x) { return Lanes4{x, x, x, x}; }
inline Lanes4 load4(const std::int32_t* p) {
  Lanes4 v;
  std::memcpy(&v, p, sizeof v);  // unaligned
  return v;
}
inline bool anyLane(Lanes4 v) {
  std::uint64_t half[2];
  std::memcpy(half, &v, sizeof half);
  return (half[0] | half[1]) != 0u;
}

// One lower endpoint's prefixes on the two tested axes, in every lane.
struct ProbeLanes {
  Lanes4 lb, ub, lc, uc;
  Lanes4 p_first;  // -1: the slab is the probing proxy's first
};

// Lanes j .. j + 3 of an open set whose prefixes overlap the probe's, within `valid` (and,
// kSlabs, whose pair belongs to this slab): -1, else 0.
template <bool kSlabs>
inline Lanes4 candidates(const ActiveSet& set, std::size_t j, const ProbeLanes& probe, Lanes4 valid) {
  // A lane fails when one of the four interval tests fails: (a > b) = !(a <= b).
  const Lanes4 apart = (load4(&set.lower_b[j]) > probe.ub) | (probe.lb > load4(&set.upper_b[j])) |
                       (load4(&set.lower_c[j]) > probe.uc) | (probe.lc > load4(&set.upper_c[j]));
  if (kSlabs) valid &= probe.p_first | load4(&set.first[j]);
  return valid & ~apart;
}

void sortAxisFully(State& s, int axis) { sortEndpoints(&s.keys[axis], &s.owners[axis], &s.sort); }

std::int64_t sweepTests(const State& s, int axis) {
  // A sweep along `axis` tests every proxy against the intervals open at its lower endpoint.
  const std::uint32_t* owner = s.owners[axis].data();
  const std::size_t last = s.owners[axis].size() - 1;
  std::int64_t tests = 0, open = 0;
  for (std::size_t i = 1; i < last; ++i) {
    const std::int64_t upper = owner[i] & 1u;
    tests += open & (upper - 1);  // upper - 1 is all ones for a lower endpoint, 0 otherwise
    open += 1 - 2 * upper;
  }
  return tests;
}

void measureWidths(State& s, double* mean_width) {
  // Widest width of the live proxies and of those waiting to be inserted, and mean width of the
  // live ones, per axis; the widest is exact again (between rebuilds it only grows). (The
  // waiting ones too: a rebuild runs before the update's insertions, whose windows, and every
  // later insertion's, reach back by the widest; measured without them, a wide box inserted
  // in a rebuild's update was missed by the boxes created inside it later: session 21.)
  for (int axis = 0; axis < 3; ++axis) {
    const std::uint64_t* e = s.ends[axis].data();
    double widest = 0.0, sum = 0.0;
    for (std::size_t p = 0, slots = s.info.size(); p < slots; ++p) {  // in slot order: streams
      const ProxyState state = s.info[p].state;
      if (state == ProxyState::kFree) continue;
      const double w = unsortable64(e[2 * p + 1]) - unsortable64(e[2 * p]);
      widest = std::max(widest, w);
      if (state == ProxyState::kLive) sum += w;
    }
    s.max_width[axis] = widest;
    mean_width[axis] = s.live_count > 0 ? sum / s.live_count : 0.0;
  }
}

// ---------------------------------------------------------------------------------------------
// Sweeps: every lower endpoint, in order along the sweep axis, is tested against the intervals
// open at it. One kernel (testOpen) serves the plain and the slab sweep.

// Out of line: the sweep's kernel (testOpen) stays small enough to inline into the sweeps.
__attribute__((noinline)) void foundPair(State& s, std::int32_t a, std::int32_t b, bool rebuild) {
  if (s.filling_next) {
    // The next arrays' sweep (sweep_and_prune_next): their candidates are listed, then put
    // in their own table; nothing begins or ends until they are swapped in.
    s.next.found.push_back(a < b ? BroadPair{a, b, 0, 0} : BroadPair{b, a, 0, 0});
    return;
  }
  if (!rebuild) {
    s.beginPair(a, b);
    return;
  }
  bool inserted = false;
  Candidate* pair = s.cands.insert(a, b, &inserted);
  pair->epoch = s.epoch;
  if (inserted) s.cand_began.push_back(*pair);
}

// The exact test of p against the proxy at position j of `set`; reports the pair.
inline void testExactly(State& s, const ActiveSet& set, std::size_t j, std::int32_t p,
                        const EndKeys& k, bool rebuild) {
  const std::int32_t q = set.id[j];
  const std::uint64_t* eb = set.keys_b + 2 * static_cast<std::size_t>(q);
  const std::uint64_t* ec = set.keys_c + 2 * static_cast<std::size_t>(q);
  if ((eb[0] < k.ub) & (k.lb < eb[1]) & (ec[0] < k.uc) & (k.lc < ec[1])) foundPair(s, p, q, rebuild);
}

template <bool kSlabs>
__attribute__((always_inline)) inline std::size_t testOpen(State& s, const ActiveSet& set,
                                                           std::int32_t p, const EndKeys& k,
                                                           bool p_first, bool rebuild) {
  // Four open intervals at a time on 32-bit prefixes (a filter that never drops an overlap),
  // then the exact test on full keys for the few lanes it passes. In a slab sweep a pair is
  // reported only in the slab holding the larger of the two lower bounds: p's first slab, or
  // the first slab of the other proxy. Only the last group masks lanes past the set's end.
  const ProbeLanes probe{splat4(prefix32(k.lb)), splat4(prefix32(k.ub)), splat4(prefix32(k.lc)),
                         splat4(prefix32(k.uc)), splat4(p_first ? -1 : 0)};
  auto testLanes = [&](std::size_t j, Lanes4 h) {
    for (int t = 0; t < 4; ++t) {
      if (h[t] != 0) testExactly(s, set, j + static_cast<std::size_t>(t), p, k, rebuild);
    }
  };
  const std::size_t n = set.size, whole = n & ~std::size_t{3};
  std::size_t j = 0;
  for (; j < whole; j += 4) {
    const Lanes4 h = candidates<kSlabs>(set, j, probe, splat4(-1));
    if (anyLane(h)) testLanes(j, h);
  }
  if (j < n) {
    const Lanes4 lane = {0, 1, 2, 3};
    const Lanes4 in_set = lane < splat4(static_cast<std::int32_t>(n - j));
    const Lanes4 h = candidates<kSlabs>(set, j, probe, in_set);
    if (anyLane(h)) testLanes(j, h);
  }
  return n;
}

inline void open(State& s, ActiveSet& set, std::int32_t p, const EndKeys& k, bool first_slab) {
  s.sweep.active_pos[p] = static_cast<std::int32_t>(set.push(p, k, first_slab));
}

inline void close(State& s, ActiveSet& set, std::int32_t p) {
  std::int32_t* active_pos = s.sweep.active_pos.data();
  const std::size_t pos = static_cast<std::size_t>(active_pos[p]);
  const std::int32_t moved = set.removeAt(pos);
  if (moved >= 0) active_pos[moved] = static_cast<std::int32_t>(pos);
}

void sweepPositions(State& s, int axis, bool only_new, std::size_t from, std::size_t to) {
  // One sweep along `axis` with sets of open intervals, over the endpoint positions [from, to)
  // (the sets persist between calls; the first call starts at 1). With only_new, old proxies
  // are tested only against new ones, so an insertion costs O(n + k * overlaps); otherwise
  // every pair is found and stamped (rebuild).
  const int axis_b = (axis + 1) % 3, axis_c = (axis + 2) % 3;
  const std::uint32_t* owner = s.owners[axis].data();
  const std::uint64_t* eb = s.ends[axis_b].data();
  const std::uint64_t* ec = s.ends[axis_c].data();
  ActiveSet& active = s.sweep.active;
  ActiveSet& active_new = s.sweep.active_new;
  if (from <= 1) {
    active.reserve(s.reserved_slots);
    active_new.reserve(s.reserved_slots);
    active.clear();
    active_new.clear();
  }
  active.keys_b = active_new.keys_b = eb;
  active.keys_c = active_new.keys_c = ec;
  for (std::size_t i = std::max<std::size_t>(from, 1); i < to; ++i) {
    const std::uint32_t o = owner[i];
    const std::int32_t p = static_cast<std::int32_t>(o >> 1);
    const bool p_new = only_new && s.info[p].is_new;
    ActiveSet& set = p_new ? active_new : active;
    if ((o & 1u) != 0u) {
      close(s, set, p);
      continue;
    }
    const EndKeys k{eb[o], eb[o + 1], ec[o], ec[o + 1]};
    if (!only_new || p_new) testOpen<false>(s, active, p, k, true, !only_new);
    testOpen<false>(s, active_new, p, k, true, !only_new);
    open(s, set, p, k, false);
  }
}

void sweepForPairs(State& s, int axis, bool only_new) {
  sweepPositions(s, axis, only_new, 1, s.owners[axis].size() - 1);
}

SlabGrid slabGrid(const State& s, int axis, const double* mean_width) {
  // The other axis that fits the most slabs of two mean widths; none (count 0) when fewer than
  // four fit or there are too few proxies to share them.
  constexpr std::size_t kMaxSlabs = 4096;
  const std::size_t max_slabs = std::min<std::size_t>(kMaxSlabs, static_cast<std::size_t>(s.live_count) / 8);
  SlabGrid grid;
  double slabs = 0.0, hi = 0.0;
  for (int k = 1; k < 3; ++k) {
    const int b = (axis + k) % 3;
    const std::vector<std::uint64_t>& kb = s.keys[b];
    const double b_lo = unsortable64(kb[1]), b_hi = unsortable64(kb[kb.size() - 2]);
    const double fit = (b_hi - b_lo) / (2.0 * mean_width[b]);
    if (fit > slabs) {
      slabs = fit;
      grid.axis = b;
      grid.lo = b_lo;
      hi = b_hi;
    }
  }
  if (grid.axis < 0 || !(slabs >= 4.0) || max_slabs < 4) return SlabGrid();
  grid.count = static_cast<std::size_t>(std::min(slabs, static_cast<double>(max_slabs)));
  grid.scale = static_cast<double>(grid.count) / (hi - grid.lo);
  return grid;
}

bool binIntoSlabs(State& s, int axis, const SlabGrid& grid) {
  // Slab range of every proxy, then a stable counting sort of the sweep axis' endpoints into
  // the slabs (each slab's list stays sorted along the sweep axis). False when the boxes span
  // so many slabs that the lists would outgrow their space: one plain sweep then.
  SweepScratch& w = s.sweep;
  const std::uint64_t* eb = s.ends[grid.axis].data();
  w.slab_lo.resize(s.info.size());
  w.slab_hi.resize(s.info.size());
  w.slab_start.assign(grid.count + 1, 0);
  std::size_t total = 0;
  for (std::size_t p = 0, slots = s.info.size(); p < slots; ++p) {  // in slot order: streams
    if (s.info[p].state != ProxyState::kLive) continue;
    const std::uint32_t s0 = grid.slabOf(eb[2 * p]), s1 = grid.slabOf(eb[2 * p + 1]);
    w.slab_lo[p] = s0;
    w.slab_hi[p] = s1;
    total += 2 * (s1 - s0 + 1);
    w.slab_start[s0] += 2;  // difference array: +2 on [s0, s1]
    if (s1 + 1 < grid.count) w.slab_start[s1 + 1] -= 2;
  }
  if (total > w.slab_owners.capacity()) return false;
  // Running sum of the difference array = endpoints per slab; then exclusive prefix = starts.
  std::size_t run = 0, start = 0;
  for (std::size_t slab = 0; slab < grid.count; ++slab) {
    run += w.slab_start[slab];
    w.slab_start[slab] = start;
    start += run;
  }
  w.slab_start[grid.count] = start;
  w.slab_pos.assign(w.slab_start.begin(), w.slab_start.end());
  w.slab_owners.resize(total);
  const std::uint32_t* owner = s.owners[axis].data();
  for (std::size_t i = 1, last = s.owners[axis].size() - 1; i < last; ++i) {
    const std::uint32_t o = owner[i];
    const std::uint32_t p = o >> 1;
    for (std::uint32_t slab = w.slab_lo[p], s1 = w.slab_hi[p]; slab <= s1; ++slab) {
      w.slab_owners[w.slab_pos[slab]++] = o;
    }
  }
  return true;
}

std::int64_t sweepSlabRange(State& s, int axis, const SlabGrid& grid, bool rebuild,
                            std::size_t from, std::size_t to) {
  // Slabs [from, to); returns the overlap tests done.
  const int b = grid.axis, c = 3 - axis - grid.axis;
  const std::uint64_t* eb = s.ends[b].data();
  const std::uint64_t* ec = s.ends[c].data();
  const std::uint32_t* slab_owners = s.sweep.slab_owners.data();
  const std::uint32_t* slab_lo = s.sweep.slab_lo.data();
  const std::size_t* slab_start = s.sweep.slab_start.data();
  const std::size_t total = s.sweep.slab_owners.size();
  std::int64_t tests = 0;
  ActiveSet& set = s.sweep.active;
  set.keys_b = eb;
  set.keys_c = ec;
  for (std::size_t slab_index = from; slab_index < to; ++slab_index) {
    set.clear();
    const std::uint32_t slab = static_cast<std::uint32_t>(slab_index);
    for (std::size_t i = slab_start[slab_index], end = slab_start[slab_index + 1]; i < end; ++i) {
      const std::uint32_t o = slab_owners[i];
      const std::int32_t p = static_cast<std::int32_t>(o >> 1);
      // The keys of the endpoint a few places on: a random access, started early.
      const std::uint32_t ahead = slab_owners[std::min(i + 8, total - 1)] & ~1u;
      __builtin_prefetch(eb + ahead);
      __builtin_prefetch(ec + ahead);
      if ((o & 1u) != 0u) {
        close(s, set, p);
        continue;
      }
      const EndKeys k{eb[o], eb[o + 1], ec[o], ec[o + 1]};
      const bool p_first = slab_lo[p] == slab;
      tests += static_cast<std::int64_t>(testOpen<true>(s, set, p, k, p_first, rebuild));
      open(s, set, p, k, p_first);
    }
  }
  return tests;
}

bool sweepSlabs(State& s, int axis, const double* mean_width, bool rebuild) {
  // Many bodies: cut a second axis into slabs about two mean widths wide and sweep each slab on
  // its own, so a lower endpoint is tested only against the open intervals of its slab. A box
  // goes into every slab it overlaps; a pair is reported in one slab only.
  const SlabGrid grid = slabGrid(s, axis, mean_width);
  if (grid.count == 0 || !binIntoSlabs(s, axis, grid)) return false;
  s.sweep_tests = sweepSlabRange(s, axis, grid, rebuild, 0, grid.count);
  return true;
}

}  // namespace

void ActiveSet::reserve(std::size_t n) {
  n += 3;  // testOpen reads whole groups of four
  if (id.size() >= n) return;
  id.resize(n);
  first.resize(n);
  lower_b.resize(n);
  upper_b.resize(n);
  lower_c.resize(n);
  upper_c.resize(n);
}

void SweepScratch::reserve(std::size_t slots) {
  active_pos.reserve(slots);
  active.reserve(slots);
  active_new.reserve(slots);
  slab_lo.reserve(slots);
  slab_hi.reserve(slots);
  slab_owners.reserve(8 * slots);
  slab_start.reserve(4097);
  slab_pos.reserve(4097);
}

void rebuild(State& s, bool streak, bool keys_read) {
  // The axis with the fewest open intervals, re-chosen every 8th rebuild (counting them costs a
  // pass over each axis, and needs each axis sorted).
  const bool choose = s.rebuilds_since_choice++ % 8 == 0;
  // In a streak the sweep needs only its own axis in order (its keys are read); the others go
  // stale.
  const bool sweep_axis_only = streak && !choose;
  if (!sweep_axis_only && !keys_read) refreshKeys(s);
  for (int axis = 0; axis < 3; ++axis) {
    s.stale[axis] = sweep_axis_only && axis != s.sweep_axis;
    if (!s.stale[axis]) sortAxisFully(s, axis);
  }
  if (choose) {
    s.widths_due = true;
    s.sweep_axis = cheapestSweepAxis(s, &s.plain_tests);
  }
  // The plain sweep's tests only choose between a plain and a slab sweep (a slab sweep counts
  // its own): the count of the last choice will do, like the widths.
  s.sweep_tests = s.plain_tests;
  // Stamp every pair the sweep finds; unstamped survivors ended.
  ++s.epoch;
  findPairs(s, s.sweep_axis, s.sweep_tests, SweepMode::kRebuild);
  std::vector<Candidate>& dense = s.cands.mutablePairs();
  for (int i = static_cast<int>(dense.size()) - 1; i >= 0; --i) {
    if (dense[i].epoch != s.epoch) {
      s.cand_ended.push_back(dense[i]);
      s.cands.eraseAt(i);
    }
  }
  s.stats.rebuilt = true;
}

int cheapestSweepAxis(const State& s, std::int64_t* tests) {
  // A stale axis is out of order: a sweep along it would miss pairs. The sweep axis never is.
  int best = s.sweep_axis;
  std::int64_t best_tests = std::numeric_limits<std::int64_t>::max();
  for (int axis = 0; axis < 3; ++axis) {
    if (s.stale[axis]) continue;
    const std::int64_t t = sweepTests(s, axis);
    if (t < best_tests) {
      best = axis;
      best_tests = t;
    }
  }
  *tests = best_tests;
  return best;
}

void findPairs(State& s, int axis, std::int64_t tests, SweepMode mode) {
  // Slabs pay only when a plain sweep would test each proxy against many open intervals, and
  // only when every pair is wanted.
  if (mode != SweepMode::kNewOnly && tests >= kSlabTestsPerProxy * s.live_count) {
    // Rebuilds re-measure with the sweep axis' choice: widths only size the slabs, and the
    // widest ones only grow in between (writeBounds), so older ones cost speed, never pairs.
    if (mode != SweepMode::kRebuild || s.widths_due) measureWidths(s, s.mean_width);
    s.widths_due = false;
    if (sweepSlabs(s, axis, s.mean_width, mode == SweepMode::kRebuild)) return;
  }
  sweepForPairs(s, axis, mode != SweepMode::kRebuild);
}

bool planSweep(State& s, int axis, std::int64_t tests, SweepCursor* c) {
  // As findPairs() chooses for a rebuild: slabs when a plain sweep would test each proxy
  // against many open intervals (and the boxes fit the slab lists).
  c->axis = axis;
  c->pos = 0;
  c->grid = SlabGrid();
  if (tests >= kSlabTestsPerProxy * s.live_count) {
    // (measureWidths makes max_width exact for the bounds it reads, the next ones: the live
    // bounds stay in the arrays until the swap, and insertions read their widest.)
    const double widest[3] = {s.max_width[0], s.max_width[1], s.max_width[2]};
    measureWidths(s, s.mean_width);
    for (int axis_k = 0; axis_k < 3; ++axis_k) s.max_width[axis_k] = std::max(s.max_width[axis_k], widest[axis_k]);
    c->grid = slabGrid(s, axis, s.mean_width);
    if (c->grid.count > 0) return true;
  }
  c->end = s.owners[axis].size() - 1;
  c->pos = 1;
  return false;
}

void binSweep(State& s, SweepCursor* c) {
  if (!binIntoSlabs(s, c->axis, c->grid)) c->grid = SlabGrid();
  c->pos = c->grid.count > 0 ? 0 : 1;
  c->end = c->grid.count > 0 ? c->grid.count : s.owners[c->axis].size() - 1;
}

bool sweepOn(State& s, SweepCursor* c, std::size_t endpoints) {
  if (c->grid.count > 0) {
    // Whole slabs, until about `endpoints` endpoints were swept.
    const std::size_t* start = s.sweep.slab_start.data();
    std::size_t to = c->pos;
    while (to < c->end && (to == c->pos || start[to] - start[c->pos] < endpoints)) ++to;
    sweepSlabRange(s, c->axis, c->grid, true, c->pos, to);
    c->pos = to;
  } else {
    const std::size_t to = std::min(c->end, c->pos + std::max<std::size_t>(endpoints, 1));
    sweepPositions(s, c->axis, false, c->pos, to);
    c->pos = to;
  }
  return c->pos >= c->end;
}

}  // namespace sap
}  // namespace workspace_proximity
