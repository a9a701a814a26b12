#include "workspace_proximity/sweep_and_prune.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace workspace_proximity {
namespace {

constexpr std::uint32_t kSentinelOwner = 0xFFFFFFFFu;
constexpr std::uint64_t kLowSentinel = 0u;
constexpr std::uint64_t kHighSentinel = ~std::uint64_t{0};
constexpr std::uint64_t kSign64 = 0x8000000000000000ull;
// A plain sweep with fewer overlap tests per proxy than this is cheaper than a slab sweep.
constexpr std::int64_t kSlabTestsPerProxy = 16;

// Work units of coasting's cost model (about a nanosecond each on the benchmark machine: perf
// profiles of the uniform, walker and robot-cell scenes, bench/results/NOTES.md section 19).
constexpr double kScanWork = 4.0;     // one candidate tested on the given bounds
constexpr double kSwapWork = 10.0;    // one swap (insertion sort or a relocated endpoint)
constexpr double kPassWork = 1.5;     // one endpoint read in a pass over an axis
constexpr double kSearchWork = 100.0; // finding a proxy's six endpoints (binary searches)
constexpr double kEnlargeWork = 20.0; // enlarging one proxy
constexpr double kSortWork = 12.0;    // one endpoint radix-sorted in a rebuild, per axis
constexpr double kTestWork = 1.5;     // one overlap test of a rebuild's sweep
constexpr double kFoundWork = 25.0;   // one pair found (and stamped) by a rebuild

// Order-preserving map double -> uint64: flip all bits of negatives, set the sign of
// positives; without branches on the sign.
inline std::uint64_t sortable64(double d) {
  std::uint64_t bits;
  std::memcpy(&bits, &d, sizeof bits);
  bits = bits == kSign64 ? 0u : bits;  // -0 and +0 must map to the same key
  const std::uint64_t negative = static_cast<std::uint64_t>(static_cast<std::int64_t>(bits) >> 63);
  return bits ^ (negative | kSign64);
}

inline std::uint64_t lower64(double d) { return sortable64(d) & ~std::uint64_t{1}; }
inline std::uint64_t upper64(double d) { return sortable64(d) | 1u; }

inline double unsortable64(std::uint64_t key) {
  // Keys with the sign bit came from positives (clear it), the others from negatives (flip
  // every bit); without branches.
  const std::uint64_t flip = kSign64 | static_cast<std::uint64_t>(static_cast<std::int64_t>(~key) >> 63);
  const std::uint64_t bits = key ^ flip;
  double d;
  std::memcpy(&d, &bits, sizeof d);
  return d;
}

// LSD radix sort of 64-bit items by bits 32 .. 32 + 8 passes of each (stable), 8 bits per pass;
// a pass in which every item has the same digit is skipped. Returns the sorted items: in
// `items` or in `scratch` (no copy back).
template <int kDigit>
const std::uint64_t* radixSortHigh32(std::vector<std::uint64_t>* items,
                                     std::vector<std::uint64_t>* scratch, int passes) {
  constexpr std::uint64_t kMask = (std::uint64_t{1} << kDigit) - 1;
  const std::size_t n = items->size();
  scratch->resize(n);
  std::uint32_t count[4][kMask + 1];
  std::memset(count, 0, sizeof(count[0]) * passes);
  const std::uint64_t* in = items->data();
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint64_t x = in[i];
    for (int pass = 0; pass < passes; ++pass) ++count[pass][(x >> (32 + kDigit * pass)) & kMask];
  }
  std::uint64_t* src = items->data();
  std::uint64_t* dst = scratch->data();
  for (int pass = 0; pass < passes; ++pass) {
    const int shift = 32 + kDigit * pass;
    std::uint32_t* c = count[pass];
    if (c[(src[0] >> shift) & kMask] == n) continue;
    std::uint32_t sum = 0;
    for (std::uint64_t d = 0; d <= kMask; ++d) {
      const std::uint32_t t = c[d];
      c[d] = sum;
      sum += t;
    }
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint64_t x = src[i];
      dst[c[(x >> shift) & kMask]++] = x;
    }
    std::swap(src, dst);
  }
  return src;
}

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

// Lanes j .. j + 3 of an open set (ActiveSet) whose prefixes overlap the probe's, within
// `valid` (and, kSlabs, whose pair belongs to this slab): -1, else 0.
template <bool kSlabs, class Set>
inline Lanes4 candidates(const Set& set, std::size_t j, const ProbeLanes& probe, Lanes4 valid) {
  // A lane fails when one of the four interval tests fails: (a > b) = !(a <= b).
  const Lanes4 apart = (load4(&set.lower_b[j]) > probe.ub) | (probe.lb > load4(&set.upper_b[j])) |
                       (load4(&set.lower_c[j]) > probe.uc) | (probe.lc > load4(&set.upper_c[j]));
  if (kSlabs) valid &= probe.p_first | load4(&set.first[j]);
  return valid & ~apart;
}

}  // namespace

void SweepAndPrune::reserveSlots(std::size_t slots) {
  // Everything sized by the number of proxy slots grows here, together, so that updates never
  // allocate while the slot count stays put (destroyed ids are reused).
  reserved_slots_ = slots;
  info_.reserve(slots);
  active_pos_.reserve(slots);
  active_.reserve(slots);
  active_new_.reserve(slots);
  pending_insert_.reserve(slots);
  pending_remove_.reserve(slots);
  for (std::vector<std::uint64_t>& e : ends_) e.reserve(2 * slots);
  for (std::vector<std::uint64_t>& e : prev_ends_) e.reserve(2 * slots);
  tight_.reserve(6 * slots);
  base_.reserve(6 * slots);
  escapers_.reserve(slots);
  escaper_old_.reserve(6 * slots);
  sort_items_.reserve(2 * slots);
  sort_items2_.reserve(2 * slots);
  tmp_keys_.reserve(2 * slots + 2);
  tmp_owners_.reserve(2 * slots + 2);
  breaks_.reserve(2 * slots + 2);
  slab_lo_.reserve(slots);
  slab_hi_.reserve(slots);
  slab_owners_.reserve(8 * slots);
  slab_start_.reserve(4097);
  slab_pos_.reserve(4097);
  for (int axis = 0; axis < 3; ++axis) {
    keys_[axis].reserve(2 * slots + 2);
    owners_[axis].reserve(2 * slots + 2);
  }
}

void SweepAndPrune::ActiveSet::reserve(std::size_t n) {
  n += 3;  // testOpen reads whole groups of four
  if (id.size() >= n) return;
  id.resize(n);
  first.resize(n);
  lower_b.resize(n);
  upper_b.resize(n);
  lower_c.resize(n);
  upper_c.resize(n);
}

SweepAndPrune::SweepAndPrune(const SweepAndPruneConfig& config)
    : config_(config), cands_(config.initial_pair_capacity) {
  if (!(config.coast_updates >= 0.0 && config.coast_updates <= 1e6)) {
    throw std::invalid_argument("SweepAndPrune: coast_updates must be in [0, 1e6]");
  }
  if (!(config.max_lead_fraction >= 0.0 && config.max_lead_fraction <= 1e6)) {
    throw std::invalid_argument("SweepAndPrune: max_lead_fraction must be in [0, 1e6]");
  }
  lead_ = config.coast_updates;
  reserveSlots(static_cast<std::size_t>(std::max(config.initial_proxy_capacity, 1)));
  keepHeadroom();
  for (int axis = 0; axis < 3; ++axis) {
    // Sentinels end every inner loop without a bounds check.
    keys_[axis] = {kLowSentinel, kHighSentinel};
    owners_[axis] = {kSentinelOwner, kSentinelOwner};
  }
}

// Kept inline: moveProxy runs once per body and cycle.
inline void SweepAndPrune::writeTight(ProxyId id, const Aabb& bounds) {
  std::uint64_t* t = tight_.data() + 6 * static_cast<std::size_t>(id);
  for (int axis = 0; axis < 3; ++axis) {
    t[2 * axis] = lower64(bounds.lower[axis]);
    t[2 * axis + 1] = upper64(bounds.upper[axis]);
  }
}

inline bool SweepAndPrune::insideEnlarged(ProxyId id, bool* equal) const {
  const std::size_t o = 2 * static_cast<std::size_t>(id);
  const std::uint64_t* t = tight_.data() + 6 * static_cast<std::size_t>(id);
  bool inside = true, same = true;
  for (int axis = 0; axis < 3; ++axis) {
    const std::uint64_t* e = ends_[axis].data() + o;
    inside &= (e[0] <= t[2 * axis]) & (t[2 * axis + 1] <= e[1]);
    same &= (e[0] == t[2 * axis]) & (t[2 * axis + 1] == e[1]);
  }
  *equal = same;
  return inside;
}

void SweepAndPrune::enlarge(ProxyId id, double lead) {
  // Lead ahead of each side that moved outward since the last enlargement: `lead` updates of
  // its displacement per update; behind it (and on a side that moved inward) one update's, so
  // that a body that turns or stops does not leave at once. A side that did not move gets no
  // room: a resting body never leaves its bounds.
  const std::size_t o = 2 * static_cast<std::size_t>(id);
  std::uint64_t* t = tight_.data() + 6 * static_cast<std::size_t>(id);
  std::uint64_t* b = base_.data() + 6 * static_cast<std::size_t>(id);
  ProxyInfo& info = info_[static_cast<std::size_t>(id)];
  const std::uint32_t elapsed = updates_ - info.enlarged_at;
  info.enlarged_at = updates_;
  if (!(lead > 0.0)) {
    for (int axis = 0; axis < 3; ++axis) {
      std::uint64_t* e = ends_[axis].data() + o;
      e[0] = b[2 * axis] = t[2 * axis];
      e[1] = b[2 * axis + 1] = t[2 * axis + 1];
      max_width_[axis] = std::max(max_width_[axis], unsortable64(e[1]) - unsortable64(e[0]));
    }
    setFat(info, false);
    return;
  }
  double lo[3], hi[3], extent = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    lo[axis] = unsortable64(t[2 * axis]);
    hi[axis] = unsortable64(t[2 * axis + 1]);
    extent = std::max(extent, hi[axis] - lo[axis]);
  }
  // (Enlarging everybody divides by the same count again and again.)
  if (elapsed != recip_of_) {
    recip_of_ = elapsed;
    recip_ = 1.0 / static_cast<double>(std::max<std::uint32_t>(1, elapsed));
  }
  const double per_update = recip_;
  const double cap = config_.max_lead_fraction * extent;
  bool fat = false;
  for (int axis = 0; axis < 3; ++axis) {
    // Displacements per update of the lower and the upper side (positive: upward). Without
    // branches (the directions are random): max(-lead d, d) is lead |d| for a side moving
    // outward and |d| for one moving inward.
    const double d_lo = (lo[axis] - unsortable64(b[2 * axis])) * per_update;
    const double d_hi = (hi[axis] - unsortable64(b[2 * axis + 1])) * per_update;
    const double below = std::min(cap, std::max(-lead * d_lo, d_lo));
    const double above = std::min(cap, std::max(lead * d_hi, -d_hi));
    // Not a number: no room on that side. Finite: keys of infinities read back as NaN.
    constexpr double kMax = std::numeric_limits<double>::max();
    const double lo_e = std::max(-kMax, lo[axis] - (below > 0.0 ? below : 0.0));
    const double hi_e = std::min(kMax, hi[axis] + (above > 0.0 ? above : 0.0));
    std::uint64_t* e = ends_[axis].data() + o;
    // Outward of the given keys whatever the rounding of the subtraction above.
    e[0] = std::min(t[2 * axis], lower64(lo_e));
    e[1] = std::max(t[2 * axis + 1], upper64(hi_e));
    fat |= (e[0] != t[2 * axis]) | (e[1] != t[2 * axis + 1]);
    // (Widths only bound the windows of insertions, which allow for rounding.)
    max_width_[axis] = std::max(max_width_[axis], hi_e - lo_e);
    b[2 * axis] = t[2 * axis];
    b[2 * axis + 1] = t[2 * axis + 1];
  }
  setFat(info, fat);
}

inline void SweepAndPrune::checkLive(ProxyId id, const char* what) const {
  if (id < 0 || static_cast<std::size_t>(id) >= info_.size()) {
    throw std::out_of_range(std::string("SweepAndPrune::") + what + ": no such proxy");
  }
  const ProxyInfo& p = info_[static_cast<std::size_t>(id)];
  if (p.state == ProxyState::kFree || p.pending_remove) {
    throw std::invalid_argument(std::string("SweepAndPrune::") + what + ": proxy is not live");
  }
}

SweepAndPrune::ProxyId SweepAndPrune::createProxy(const Aabb& bounds) {
  if (!bounds.valid()) throw std::invalid_argument("SweepAndPrune::createProxy: invalid bounds");
  ProxyId id;
  if (free_list_ >= 0) {
    id = free_list_;
    free_list_ = info_[id].next_free;
  } else {
    id = static_cast<ProxyId>(info_.size());
    if (info_.size() >= reserved_slots_) reserveSlots(2 * reserved_slots_);
    info_.emplace_back();
    for (std::vector<std::uint64_t>& e : ends_) e.resize(e.size() + 2);
    tight_.resize(tight_.size() + 6);
    base_.resize(base_.size() + 6);
    active_pos_.push_back(-1);
  }
  writeTight(id, bounds);
  ProxyInfo& p = info_[id];
  p.next_free = -1;
  p.state = ProxyState::kPendingInsert;
  p.pending_remove = false;
  p.is_new = false;
  p.escaped = false;
  p.fat = false;
  enlarge(id, 0.0);  // no motion seen yet: its given bounds
  p.enlarged_at = updates_ + 1;  // as of the update that inserts it
  pending_insert_.push_back(id);
  return id;
}

void SweepAndPrune::destroyProxy(ProxyId id) {
  checkLive(id, "destroyProxy");
  ProxyInfo& p = info_[id];
  if (p.state == ProxyState::kPendingInsert) {
    // Never entered the arrays: forget it now.
    auto it = std::find(pending_insert_.begin(), pending_insert_.end(), id);
    *it = pending_insert_.back();
    pending_insert_.pop_back();
    p.state = ProxyState::kFree;
    p.next_free = free_list_;
    free_list_ = id;
    return;
  }
  // Live: it keeps its slot (so the id is not reused) until update() takes it out.
  p.pending_remove = true;
  pending_remove_.push_back(id);
}

void SweepAndPrune::moveProxy(ProxyId id, const Aabb& bounds) {
  if (!bounds.valid()) throw std::invalid_argument("SweepAndPrune::moveProxy: invalid bounds");
  checkLive(id, "moveProxy");
  // Only the proxy's keys change here; update() re-sorts what left its enlarged bounds.
  ProxyInfo& p = info_[static_cast<std::size_t>(id)];
  if (lead_ <= 0.0 || p.state == ProxyState::kPendingInsert) {
    // Not coasting (or not in the arrays yet): the arrays take the given bounds, as they come.
    // The previous ones stay in base_, should coasting start again.
    std::uint64_t* t = tight_.data() + 6 * static_cast<std::size_t>(id);
    std::uint64_t* b = base_.data() + 6 * static_cast<std::size_t>(id);
    const std::size_t o = 2 * static_cast<std::size_t>(id);
    for (int axis = 0; axis < 3; ++axis) {
      b[2 * axis] = t[2 * axis];
      b[2 * axis + 1] = t[2 * axis + 1];
      std::uint64_t* e = ends_[axis].data() + o;
      e[0] = t[2 * axis] = lower64(bounds.lower[axis]);
      e[1] = t[2 * axis + 1] = upper64(bounds.upper[axis]);
      max_width_[axis] = std::max(max_width_[axis], bounds.upper[axis] - bounds.lower[axis]);
    }
    // As of the next update (a pending proxy's: the one that inserts it).
    p.enlarged_at = p.state == ProxyState::kLive ? updates_ : updates_ + 1;
    setFat(p, false);
    moved_ |= p.state == ProxyState::kLive;
    return;
  }
  writeTight(id, bounds);
  if (p.escaped) return;  // enlarged anew in the update, from its latest bounds
  bool equal = false;
  if (!insideEnlarged(id, &equal)) {
    p.escaped = true;
    escapers_.push_back(id);
  } else {
    setFat(p, !equal);  // a box that shrank inside its bounds is enlarged now
  }
}

Aabb SweepAndPrune::storedBounds(ProxyId id) const {
  if (id < 0 || static_cast<std::size_t>(id) >= info_.size()) {
    throw std::out_of_range("SweepAndPrune::storedBounds: no such proxy");
  }
  Aabb box;
  const std::uint64_t* t = tight_.data() + 6 * static_cast<std::size_t>(id);
  for (int axis = 0; axis < 3; ++axis) {
    box.lower[axis] = unsortable64(t[2 * axis]);
    box.upper[axis] = unsortable64(t[2 * axis + 1]);
  }
  return box;
}

Aabb SweepAndPrune::enlargedBounds(ProxyId id) const {
  if (id < 0 || static_cast<std::size_t>(id) >= info_.size()) {
    throw std::out_of_range("SweepAndPrune::enlargedBounds: no such proxy");
  }
  Aabb box;
  for (int axis = 0; axis < 3; ++axis) {
    box.lower[axis] = unsortable64(ends_[axis][2 * static_cast<std::size_t>(id)]);
    box.upper[axis] = unsortable64(ends_[axis][2 * static_cast<std::size_t>(id) + 1]);
  }
  return box;
}

void SweepAndPrune::beginPair(std::int32_t a, std::int32_t b) {
  bool inserted = false;
  Candidate* pair = cands_.insert(a, b, &inserted);
  if (inserted) {
    pair->epoch = epoch_;
    cand_began_.push_back(*pair);
  }
}

void SweepAndPrune::endPair(std::int32_t a, std::int32_t b) {
  Candidate removed;
  if (cands_.erase(a, b, &removed)) cand_ended_.push_back(removed);
}

void SweepAndPrune::update() {
  stats_ = SweepAndPruneStats();
  cand_began_.clear();
  cand_ended_.clear();
  ++updates_;
  applyRemovals();
  // (A run's end enlarges everybody even when nobody left: ask what it did.)
  const Sorted done = live_count_ > 0 ? handleEscapers() : Sorted::kNothing;
  const bool inserted = !pending_insert_.empty();
  const bool sorted = done != Sorted::kNothing || inserted;
  moved_ = false;
  for (ProxyId id : escapers_) info_[static_cast<std::size_t>(id)].escaped = false;
  escapers_.clear();
  stats_.coasted = !sorted;
  insertPending();
  if (sorted) last_rebuilt_ = stats_.rebuilt;
  reportTouching();
  keepHeadroom();
  // The arrays are now sorted by the current keys: remember them for the next update's events
  // (none come from a stale axis: the next update rebuilds). Nothing changed when coasting;
  // moveEscapers() wrote the keys it changed.
  if ((done != Sorted::kAll && !inserted) || anyStale()) return;
  for (int axis = 1; axis < 3; ++axis) {
    prev_ends_[axis].resize(ends_[axis].size());
    std::memcpy(prev_ends_[axis].data(), ends_[axis].data(), ends_[axis].size() * sizeof(std::uint64_t));
  }
}

SweepAndPrune::Sorted SweepAndPrune::handleEscapers() {
  // Removed proxies may still be listed: drop them.
  std::size_t w = 0;
  for (ProxyId id : escapers_) {
    if (info_[static_cast<std::size_t>(id)].state == ProxyState::kLive) escapers_[w++] = id;
    else info_[static_cast<std::size_t>(id)].escaped = false;
  }
  escapers_.resize(w);
  stats_.escaped = static_cast<int>(w);
  if (lead_ <= 0.0) {
    // Not coasting: moveProxy gave the arrays the new bounds. Try coasting again when due.
    if (!moved_) return Sorted::kNothing;
    if (config_.coast_updates > 0.0 && updates_ >= retry_at_) {
      lead_ = config_.coast_updates;
      judge_next_ = false;  // the run starts here
    } else {
      resort(false, true);
      return Sorted::kAll;
    }
  } else {
    // A run lasts at most 4 coast_updates updates: then everybody is enlarged again, with
    // leads measured anew (stale ones only cost tests), and the run is judged.
    const bool run_over = updates_ - last_global_ >= 4.0 * config_.coast_updates;
    if (w == 0 && !run_over) return Sorted::kNothing;
    // A few: move their endpoints alone (a pass over the arrays costs more). The arrays must
    // be in order for that.
    const std::size_t few = 1 + static_cast<std::size_t>(live_count_) / 32;
    if (w > 0 && w <= few && !anyStale() && !run_over) {
      validateFlags();
      moveEscapers();
      return Sorted::kFew;
    }
  }
  // Many: everybody gets new enlarged bounds now, so that they leave them together again.
  validateFlags();
  last_estimate_ = -1;
  enlargeAll(lead_);
  stats_.enlarged_all = true;
  resort(true, false);  // every axis in order: moveEscapers needs them
  const double endpoints = 2.0 * live_count_;
  double work = kEnlargeWork * live_count_ + kSwapWork * static_cast<double>(stats_.swaps);
  work += stats_.rebuilt ? rebuildWork(3.0, static_cast<double>(cands_.size()))
                         : kPassWork * 3.0 * endpoints;
  if (judge_next_) judgeRun(endpoints);
  judge_next_ = true;
  run_work_ = work;
  last_global_ = updates_;
  return Sorted::kAll;
}

double SweepAndPrune::rebuildWork(double axes_sorted, double pairs) const {
  return kSortWork * axes_sorted * 2.0 * live_count_ + kTestWork * static_cast<double>(sweep_tests_) +
         kFoundWork * pairs;
}

void SweepAndPrune::judgeRun(double endpoints) {
  // The run that ends here, from the last enlargement of everybody to this one, against what
  // the same updates would have cost without coasting: one pass over every axis and the
  // swaps of its motion (this jump's estimated swaps, spread over the run), or a rebuild of
  // the given bounds (one axis sorted) if cheaper; both with the scan of the pairs. Coasting
  // that costs more switches off for a while (longer after each failure in a row).
  const double run = static_cast<double>(updates_ - last_global_);
  const double swaps = static_cast<double>(last_estimate_ >= 0 ? last_estimate_ : stats_.swaps);
  const double pairs = static_cast<double>(exact_.size());
  const double without = kScanWork * pairs +
                         std::min(kPassWork * 3.0 * endpoints + kSwapWork * swaps / run,
                                  rebuildWork(1.0, pairs));
  if (run_work_ / run > without) {
    lead_ = 0.0;
    retry_at_ = updates_ + backoff_;
    backoff_ = std::min<std::uint32_t>(2 * backoff_, 4096);
  } else {
    backoff_ = 64;
  }
}

void SweepAndPrune::validateFlags() {
  // Somebody is enlarged in this update: from here on candidates and pairs may differ, and each
  // candidate's `touching` must say what it was. Not kept so far, the candidates were the pairs
  // (those that ended in this update so far too).
  if (flags_valid_) return;
  for (Candidate& c : cands_.mutablePairs()) c.touching = 1;
  for (Candidate& c : cand_ended_) c.touching = 1;
  flags_valid_ = true;
}

void SweepAndPrune::enlargeAll(double lead) {
  for (std::size_t p = 0, slots = info_.size(); p < slots; ++p) {
    if (info_[p].state == ProxyState::kLive) enlarge(static_cast<ProxyId>(p), lead);
  }
}

void SweepAndPrune::moveEscapers() {
  // New enlarged keys for all of them first: the pair tests below use the final keys of both
  // proxies, so that a pair between two escapers is decided once, whatever the order.
  escaper_old_.resize(6 * escapers_.size());
  for (std::size_t n = 0; n < escapers_.size(); ++n) {
    const std::size_t o = 2 * static_cast<std::size_t>(escapers_[n]);
    for (int axis = 0; axis < 3; ++axis) {
      escaper_old_[6 * n + 2 * axis] = ends_[axis][o];
      escaper_old_[6 * n + 2 * axis + 1] = ends_[axis][o + 1];
    }
    enlarge(escapers_[n], lead_);
  }
  std::size_t swaps = 0;
  for (int axis = 0; axis < 3; ++axis) {
    for (std::size_t n = 0; n < escapers_.size(); ++n) {
      const std::uint32_t lower = static_cast<std::uint32_t>(escapers_[n]) << 1;
      const std::uint64_t old_lo = escaper_old_[6 * n + 2 * axis];
      const std::uint64_t old_hi = escaper_old_[6 * n + 2 * axis + 1];
      const std::uint64_t new_lo = ends_[axis][lower];
      const std::uint64_t new_hi = ends_[axis][lower + 1];
      // Move them so that the lower endpoint never passes its own upper one.
      if (new_lo > old_hi) {
        swaps += relocateEndpoint(axis, findEndpoint(axis, old_hi, lower | 1u), new_hi);
        swaps += relocateEndpoint(axis, findEndpoint(axis, old_lo, lower), new_lo);
      } else {
        swaps += relocateEndpoint(axis, findEndpoint(axis, old_lo, lower), new_lo);
        swaps += relocateEndpoint(axis, findEndpoint(axis, old_hi, lower | 1u), new_hi);
      }
      if (axis > 0) {
        prev_ends_[axis][lower] = new_lo;
        prev_ends_[axis][lower + 1] = new_hi;
      }
    }
  }
  run_work_ += kSearchWork * static_cast<double>(escapers_.size()) + kSwapWork * static_cast<double>(swaps);
}

std::size_t SweepAndPrune::findEndpoint(int axis, std::uint64_t key, std::uint32_t owner) const {
  const std::uint64_t* keys = keys_[axis].data();
  const std::uint32_t* owners = owners_[axis].data();
  std::size_t i = static_cast<std::size_t>(
      std::lower_bound(keys + 1, keys + keys_[axis].size() - 1, key) - keys);
  while (owners[i] != owner) ++i;  // equal keys: it is among them
  return i;
}

std::size_t SweepAndPrune::relocateEndpoint(int axis, std::size_t i, std::uint64_t k) {
  // Moves one endpoint to its new key, down or up. Passing an endpoint of the other kind
  // changes whether the two overlap on this axis: they start to when p's lower moves below or
  // p's upper moves above the other's, and stop in the other two cases. A pair is added or
  // removed by the final keys on every axis (so no pair both ends and begins).
  std::uint64_t* key = keys_[axis].data();
  std::uint32_t* owner = owners_[axis].data();
  const std::uint32_t o = owner[i];
  const std::uint32_t o_upper = o & 1u;
  const std::int32_t p = static_cast<std::int32_t>(o >> 1);
  auto pass = [&](std::uint32_t o2, bool starts) {
    if ((o2 & 1u) == o_upper) return;
    const std::int32_t q = static_cast<std::int32_t>(o2 >> 1);
    if (starts) {
      if (overlapsAcross(p, q, axis)) beginPair(p, q);
    } else if (!overlapsAcross(p, q, axis)) {
      endPair(p, q);
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

void SweepAndPrune::reportTouching() {
  std::vector<Candidate>& dense = cands_.mutablePairs();
  stats_.candidates = static_cast<int>(dense.size());
  // No enlarged bounds, now and at the last update: the candidates are the pairs, and their
  // changes the changes. (The first update without them still scans: a candidate of enlarged
  // bounds that did not touch may have begun to, without being a new candidate.)
  const bool was_tight = tight_last_;
  tight_last_ = fat_count_ == 0;
  if (fat_count_ == 0 && was_tight) {
    pairs_out_ = &dense;
    began_out_ = &cand_began_;
    ended_out_ = &cand_ended_;
    // Coasting on (a box that shrinks inside its bounds is enlarged, without an update that
    // enlarges): keep `touching` up to date, for the new candidates only. Off: not needed until
    // coasting starts again (validateFlags).
    if (lead_ > 0.0 && flags_valid_) {
      for (const Candidate& c : cand_began_) {
        Candidate* pair = cands_.find(c.proxy_a, c.proxy_b);
        if (pair != nullptr) pair->touching = 1;
      }
    } else {
      flags_valid_ = false;
    }
    return;
  }
  // pairs() = the candidates whose given bounds overlap; began and ended = the changes of that.
  pairs_out_ = &exact_;
  began_out_ = &began_;
  ended_out_ = &ended_;
  began_.clear();
  ended_.clear();
  exact_.clear();
  for (const Candidate& c : cand_ended_) {
    if (c.touching != 0) ended_.push_back(c);
  }
  for (Candidate& c : dense) {
    const std::uint32_t now = touching(c.proxy_a, c.proxy_b) ? 1u : 0u;
    if (now != c.touching) {
      c.touching = now;
      (now != 0 ? began_ : ended_).push_back(c);
    }
    if (now != 0) exact_.push_back(c);
  }
  if (lead_ > 0.0) run_work_ += kScanWork * static_cast<double>(dense.size());
}

void SweepAndPrune::resort(bool jump, bool allow_streak) {
  const std::size_t began_mark = cand_began_.size();
  const std::size_t ended_mark = cand_ended_.size();
  if (!jump && !last_rebuilt_ && !anyStale()) {
    if (!sortAxes(true, rebuildCost(false))) {
      // Motion too large for insertion sort to pay: undo its partial pair changes, then sort
      // from scratch and diff the new pair set against the old one.
      rollBack(began_mark, ended_mark);
      rebuild(false, false);
    }
    return;
  }
  // After a rebuild: rebuild again (the sweep axis only) while insertion sort would cost more.
  const std::int64_t swaps = estimateAllSwaps();
  last_estimate_ = swaps;
  if (swaps > rebuildCost(allow_streak)) {
    rebuild(allow_streak, !anyStale());
  } else if (anyStale()) {
    rebuild(false, false);  // stale axes: insertion sort would miss pair events
  } else if (!sortAxes(false, rebuildCost(false))) {
    rollBack(began_mark, ended_mark);
    rebuild(false, true);
  }
}

std::int64_t SweepAndPrune::estimateAllSwaps() {
  // Reads the keys of every axis in order (all three, or only the sweep axis after a streak
  // rebuild: then scaled by the three axes' share of the last full estimate).
  if (anyStale()) {
    refreshAxis(sweep_axis_);
    return static_cast<std::int64_t>(swap_scale_ * static_cast<double>(estimateSwaps(sweep_axis_)));
  }
  refreshKeys();
  std::int64_t per_axis[3], total = 0;
  for (int axis = 0; axis < 3; ++axis) total += per_axis[axis] = estimateSwaps(axis);
  const double share = static_cast<double>(std::max<std::int64_t>(per_axis[sweep_axis_], 1));
  swap_scale_ = std::clamp(static_cast<double>(total) / share, 1.0, 3.0);
  return total;
}

void SweepAndPrune::keepHeadroom() {
  // A quarter of headroom in the candidate table: it then grows while the count climbs to its
  // usual level, not later when the count first touches a new maximum by chance.
  if (4 * static_cast<std::size_t>(cands_.size()) > 3 * cands_.capacity()) {
    cands_.reserve(2 * cands_.capacity());
  }
  // Every list holds candidates of this update or the last: with the table's capacity they
  // never grow unless the table does.
  const std::size_t cap = cands_.capacity();
  for (std::vector<BroadPair>* v : {&cand_began_, &cand_ended_, &exact_, &began_, &ended_}) {
    if (v->capacity() < cap) v->reserve(cap);
  }
}

void SweepAndPrune::applyRemovals() {
  if (pending_remove_.empty()) return;
  stats_.removed = static_cast<int>(pending_remove_.size());

  // Their pairs end. Walk backwards so eraseAt's swap-with-last never skips a pair.
  std::vector<Candidate>& dense = cands_.mutablePairs();
  for (int i = static_cast<int>(dense.size()) - 1; i >= 0; --i) {
    if (info_[dense[i].proxy_a].pending_remove || info_[dense[i].proxy_b].pending_remove) {
      cand_ended_.push_back(dense[i]);
      cands_.eraseAt(i);
    }
  }
  for (int axis = 0; axis < 3; ++axis) dropRemovedEndpoints(axis);

  for (ProxyId id : pending_remove_) {
    ProxyInfo& p = info_[id];
    setFat(p, false);
    p.state = ProxyState::kFree;
    p.pending_remove = false;
    p.next_free = free_list_;
    free_list_ = id;
    --live_count_;
  }
  pending_remove_.clear();
  if (live_count_ == 0) {
    for (double& w : max_width_) w = 0.0;
    for (bool& s : stale_) s = false;  // no endpoints left: every axis is in order
    sweep_tests_ = 0;
    plain_tests_ = 0;
  }
}

void SweepAndPrune::dropRemovedEndpoints(int axis) {
  // Compacts the endpoint array in one pass.
  std::vector<std::uint64_t>& keys = keys_[axis];
  std::vector<std::uint32_t>& owners = owners_[axis];
  const std::size_t last = keys.size() - 1;
  std::size_t w = 1;
  for (std::size_t r = 1; r < last; ++r) {
    const std::uint32_t owner = owners[r];
    if (info_[owner >> 1].pending_remove) continue;
    keys[w] = keys[r];
    owners[w] = owner;
    ++w;
  }
  keys[w] = kHighSentinel;
  owners[w] = kSentinelOwner;
  keys.resize(w + 1);
  owners.resize(w + 1);
}

std::int64_t SweepAndPrune::rebuildCost(bool sweep_axis_only) const {
  // What a rebuild costs, counted in swaps: a fixed price per endpoint (reading, radix sorting
  // and sweeping it) and an eighth of a swap per overlap test of the sweep. Measured on the
  // uniform scenes (AMD EPYC, issue 14): a swap with its pair events costs 8-16 ns at 200 to
  // 20 000 endpoints per axis; a rebuild that sorts only the sweep axis 32-50 ns per endpoint,
  // one that sorts all three up to 1.4 times that. The break-even moves from 2 swaps per
  // endpoint at 200 endpoints to 4 at 20 000.
  const double n = 2.0 * live_count_;
  const double per_endpoint = sweep_axis_only ? 2.0 : 3.0;
  const double estimate = per_endpoint * n + 0.125 * static_cast<double>(sweep_tests_);
  const double budget = std::max(64.0, config_.rebuild_factor * estimate);
  return budget > 4e18 ? std::numeric_limits<std::int64_t>::max()
                       : static_cast<std::int64_t>(budget);
}

void SweepAndPrune::refreshKeys() {
  for (int axis = 0; axis < 3; ++axis) refreshAxis(axis);
}

void SweepAndPrune::refreshAxis(int axis) {
  std::uint64_t* key = keys_[axis].data();
  const std::uint32_t* owner = owners_[axis].data();
  const std::uint64_t* e = ends_[axis].data();
  const std::size_t last = keys_[axis].size() - 1;
  for (std::size_t i = 1; i < last; ++i) key[i] = e[owner[i]];
}

std::int64_t SweepAndPrune::estimateSwaps(int axis) const {
  // Insertion sort's swaps are the inversions of the keys just read against the array's order:
  // the sum over d >= 1 of the endpoints whose key is below the one d places before. Counted at
  // d = 1, 2, 4, ..., 64 for every 4th endpoint (about 1 000 endpoints on large axes); the
  // count at d = 2^j stands for the 2^(j-1) distances in (2^(j-1), 2^j]. Measured on the
  // uniform scenes this gives 75-93 % of the swaps at up to 10 swaps per endpoint, hence the
  // 5/4 (larger motion: an underestimate of a large number).
  const std::uint64_t* key = keys_[axis].data();
  const std::size_t last = keys_[axis].size() - 1;
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

// ---------------------------------------------------------------------------------------------
// Incremental path: insertion sort of every axis, reporting pair events as endpoints pass.

bool SweepAndPrune::sortAxes(bool refresh, std::int64_t budget) {
  std::int64_t swaps = 0;
  bool within_budget = true;
  for (int axis = 0; axis < 3 && within_budget; ++axis) {
    const std::size_t breaks = findBreaks(axis, refresh);
    within_budget = sortRuns(axis, breaks, budget, &swaps);
  }
  stats_.swaps = swaps;
  return within_budget;
}

std::size_t SweepAndPrune::findBreaks(int axis, bool refresh) {
  // Without branches: read the current keys (if asked) and list the positions where the order
  // breaks. Between two breaks the endpoints are already in order.
  std::uint64_t* key = keys_[axis].data();
  const std::uint32_t* owner = owners_[axis].data();
  const std::uint64_t* e = ends_[axis].data();
  const std::size_t last = keys_[axis].size() - 1;  // high sentinel
  breaks_.resize(last + 1);
  std::uint32_t* brk = breaks_.data();
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

bool SweepAndPrune::sortRuns(int axis, std::size_t breaks, std::int64_t budget,
                             std::int64_t* swaps) {
  // Insertion sort that starts at each break and stops once an endpoint is not below
  // everything before it (the rest of that run then is in place too).
  const std::uint64_t* key = keys_[axis].data();
  const std::uint32_t* brk = breaks_.data();
  std::int64_t total = *swaps;
  for (std::size_t t = 0; t < breaks; ++t) {
    const std::size_t next = brk[t + 1];
    for (std::size_t i = brk[t]; i < next; ++i) {
      if (key[i - 1] <= key[i]) break;
      total += static_cast<std::int64_t>(i - sinkEndpoint(axis, i));
      if (total > budget) {
        *swaps = total;
        return false;
      }
    }
  }
  *swaps = total;
  return true;
}

inline std::size_t SweepAndPrune::sinkEndpoint(int axis, std::size_t i) {
  // Moves the endpoint at i down to its place. Passing an endpoint of the other kind starts or
  // ends an overlap on this axis.
  std::uint64_t* key = keys_[axis].data();
  std::uint32_t* owner = owners_[axis].data();
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
        if (overlapsAcross(p, q, axis)) beginPair(p, q);
      } else {
        // p's upper passes below q's lower: separated on this axis.
        if (mayBePaired(p, q, axis)) endPair(p, q);
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

void SweepAndPrune::rollBack(std::size_t began_mark, std::size_t ended_mark) {
  for (std::size_t i = began_mark; i < cand_began_.size(); ++i) {
    cands_.erase(cand_began_[i].proxy_a, cand_began_[i].proxy_b);
  }
  for (std::size_t i = ended_mark; i < cand_ended_.size(); ++i) {
    Candidate* pair = cands_.insert(cand_ended_[i].proxy_a, cand_ended_[i].proxy_b, nullptr);
    *pair = cand_ended_[i];
  }
  cand_began_.resize(began_mark);
  cand_ended_.resize(ended_mark);
}


// ---------------------------------------------------------------------------------------------
// Rebuild: sort every axis from scratch, one sweep for the pairs, diff with the old set.

void SweepAndPrune::rebuild(bool streak, bool keys_read) {
  // The axis with the fewest open intervals, re-chosen every 8th rebuild (counting them costs a
  // pass over each axis, and needs each axis sorted).
  const bool choose = rebuilds_since_choice_++ % 8 == 0;
  // In a streak the sweep needs only its own axis in order (its keys are read); the others go
  // stale.
  const bool sweep_axis_only = streak && !choose;
  if (!sweep_axis_only && !keys_read) refreshKeys();
  for (int axis = 0; axis < 3; ++axis) {
    stale_[axis] = sweep_axis_only && axis != sweep_axis_;
    if (!stale_[axis]) sortAxisFully(axis);
  }
  if (choose) {
    widths_due_ = true;
    sweep_axis_ = cheapestSweepAxis(&plain_tests_);
  }
  // The plain sweep's tests only choose between a plain and a slab sweep (a slab sweep counts
  // its own): the count of the last choice will do, like the widths.
  sweep_tests_ = plain_tests_;
  // Stamp every pair the sweep finds; unstamped survivors ended.
  ++epoch_;
  findPairs(sweep_axis_, sweep_tests_, SweepMode::kRebuild);
  std::vector<Candidate>& dense = cands_.mutablePairs();
  for (int i = static_cast<int>(dense.size()) - 1; i >= 0; --i) {
    if (dense[i].epoch != epoch_) {
      cand_ended_.push_back(dense[i]);
      cands_.eraseAt(i);
    }
  }
  stats_.rebuilt = true;
}

void SweepAndPrune::sortAxisFully(int axis) {
  radixSortAxis(axis);
  insertionSortAxis(axis);
}

void SweepAndPrune::radixSortAxis(int axis) {
  // Sorts by the 32 most significant bits that vary over the axis (radix sort); endpoints that
  // share those bits are left for an insertion pass. Small axes go to insertion sort directly.
  std::vector<std::uint64_t>& keys = keys_[axis];
  std::vector<std::uint32_t>& owners = owners_[axis];
  const std::size_t n = keys.size() - 2;
  if (n <= 48) return;
  std::uint64_t lo = keys[1], hi = keys[1];
  for (std::size_t i = 2; i <= n; ++i) {
    lo = std::min(lo, keys[i]);
    hi = std::max(hi, keys[i]);
  }
  // Prefix bits: about 6-8 more than log2(n), so that few endpoints share a prefix. 8-bit
  // digits below 4 096 endpoints (16 or 24 bits), 11-bit digits from there (22 or 32 bits: one
  // pass fewer; the counts still fit in L1).
  const bool wide = n >= 4096;
  const int passes = n < 256 ? 2 : n < 4096 ? 3 : n < 65536 ? 2 : 3;
  const int prefix_bits = std::min(32, (wide ? 11 : 8) * passes);
  sort_items_.resize(n);
  // Prefix: the coordinate's place in [lo, hi] in 2^prefix_bits steps (monotone in the key).
  // Keys themselves are spaced logarithmically: on an axis that crosses zero, or spans many
  // octaves, their high bits would leave most coordinates in a few prefixes, and the
  // insertion pass after the radix sort would do the sorting.
  const double x_lo = unsortable64(lo), span = unsortable64(hi) - x_lo;
  if (std::isfinite(span) && span > 0.0) {
    const double top = std::ldexp(1.0, prefix_bits) - 1.0;
    const double scale = top / span;
    for (std::size_t i = 0; i < n; ++i) {
      const double v = (unsortable64(keys[i + 1]) - x_lo) * scale;
      const std::uint64_t prefix = static_cast<std::uint64_t>(v < top ? (v > 0.0 ? v : 0.0) : top);
      sort_items_[i] = (prefix << 32) | i;
    }
  } else {
    // Infinite bounds: the keys' own high bits.
    const std::uint64_t range = hi - lo;
    const int width = range == 0 ? 0 : 64 - __builtin_clzll(range);
    const int shift = std::max(0, width - prefix_bits);
    for (std::size_t i = 0; i < n; ++i) sort_items_[i] = (((keys[i + 1] - lo) >> shift) << 32) | i;
  }
  const std::uint64_t* sorted = wide ? radixSortHigh32<11>(&sort_items_, &sort_items2_, passes)
                                     : radixSortHigh32<8>(&sort_items_, &sort_items2_, passes);
  tmp_keys_.resize(n + 2);
  tmp_owners_.resize(n + 2);
  tmp_keys_[0] = kLowSentinel;
  tmp_owners_[0] = kSentinelOwner;
  tmp_keys_[n + 1] = kHighSentinel;
  tmp_owners_[n + 1] = kSentinelOwner;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t from = static_cast<std::uint32_t>(sorted[i]) + 1;
    tmp_keys_[i + 1] = keys[from];
    tmp_owners_[i + 1] = owners[from];
  }
  keys.swap(tmp_keys_);
  owners.swap(tmp_owners_);
}

void SweepAndPrune::insertionSortAxis(int axis) {
  // Plain insertion sort, no pair events (the rebuild's sweep finds the pairs).
  std::uint64_t* key = keys_[axis].data();
  std::uint32_t* owner = owners_[axis].data();
  const std::size_t n = keys_[axis].size() - 2;
  for (std::size_t i = 2; i <= n; ++i) {
    const std::uint64_t k = key[i];
    if (key[i - 1] <= k) continue;
    const std::uint32_t o = owner[i];
    std::size_t j = i;
    do {
      key[j] = key[j - 1];
      owner[j] = owner[j - 1];
      --j;
    } while (key[j - 1] > k);
    key[j] = k;
    owner[j] = o;
  }
}

std::int64_t SweepAndPrune::sweepTests(int axis) const {
  // A sweep along `axis` tests every proxy against the intervals open at its lower endpoint.
  const std::uint32_t* owner = owners_[axis].data();
  const std::size_t last = owners_[axis].size() - 1;
  std::int64_t tests = 0, open = 0;
  for (std::size_t i = 1; i < last; ++i) {
    const std::int64_t upper = owner[i] & 1u;
    tests += open & (upper - 1);  // upper - 1 is all ones for a lower endpoint, 0 otherwise
    open += 1 - 2 * upper;
  }
  return tests;
}

int SweepAndPrune::cheapestSweepAxis(std::int64_t* tests) const {
  // A stale axis is out of order: a sweep along it would miss pairs. The sweep axis never is.
  int best = sweep_axis_;
  std::int64_t best_tests = std::numeric_limits<std::int64_t>::max();
  for (int axis = 0; axis < 3; ++axis) {
    if (stale_[axis]) continue;
    const std::int64_t t = sweepTests(axis);
    if (t < best_tests) {
      best = axis;
      best_tests = t;
    }
  }
  *tests = best_tests;
  return best;
}

void SweepAndPrune::measureWidths(double* mean_width) {
  // Widest and mean width of the live proxies per axis; the widest is exact again (between
  // rebuilds it only grows).
  for (int axis = 0; axis < 3; ++axis) {
    const std::uint64_t* e = ends_[axis].data();
    double widest = 0.0, sum = 0.0;
    for (std::size_t p = 0, slots = info_.size(); p < slots; ++p) {  // in slot order: streams
      if (info_[p].state != ProxyState::kLive) continue;
      const double w = unsortable64(e[2 * p + 1]) - unsortable64(e[2 * p]);
      widest = std::max(widest, w);
      sum += w;
    }
    max_width_[axis] = widest;
    mean_width[axis] = live_count_ > 0 ? sum / live_count_ : 0.0;
  }
}


// ---------------------------------------------------------------------------------------------
// Sweeps: every lower endpoint, in order along the sweep axis, is tested against the intervals
// open at it. One kernel (testOpen) serves the plain and the slab sweep.

void SweepAndPrune::findPairs(int axis, std::int64_t tests, SweepMode mode) {
  // Slabs pay only when a plain sweep would test each proxy against many open intervals, and
  // only when every pair is wanted.
  if (mode != SweepMode::kNewOnly && tests >= kSlabTestsPerProxy * live_count_) {
    // Rebuilds re-measure with the sweep axis' choice: widths only size the slabs, and the
    // widest ones only grow in between (writeBounds), so older ones cost speed, never pairs.
    if (mode != SweepMode::kRebuild || widths_due_) measureWidths(mean_width_);
    widths_due_ = false;
    if (sweepSlabs(axis, mean_width_, mode == SweepMode::kRebuild)) return;
  }
  sweepForPairs(axis, mode != SweepMode::kRebuild);
}

void SweepAndPrune::foundPair(std::int32_t a, std::int32_t b, bool rebuild) {
  if (!rebuild) {
    beginPair(a, b);
    return;
  }
  bool inserted = false;
  Candidate* pair = cands_.insert(a, b, &inserted);
  pair->epoch = epoch_;
  if (inserted) cand_began_.push_back(*pair);
}

template <bool kSlabs>
inline std::size_t SweepAndPrune::testOpen(const ActiveSet& set, std::int32_t p, const EndKeys& k,
                                           bool p_first, bool rebuild) {
  // Four open intervals at a time on 32-bit prefixes (a filter that never drops an overlap),
  // then the exact test on full keys for the few lanes it passes. In a slab sweep a pair is
  // reported only in the slab holding the larger of the two lower bounds: p's first slab, or
  // the first slab of the other proxy. Only the last group masks lanes past the set's end.
  const ProbeLanes probe{splat4(prefix32(k.lb)), splat4(prefix32(k.ub)), splat4(prefix32(k.lc)),
                         splat4(prefix32(k.uc)), splat4(p_first ? -1 : 0)};
  auto testLanes = [&](std::size_t j, Lanes4 h) {
    for (int t = 0; t < 4; ++t) {
      if (h[t] != 0) testExactly(set, j + static_cast<std::size_t>(t), p, k, rebuild);
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

inline void SweepAndPrune::testExactly(const ActiveSet& set, std::size_t j, std::int32_t p,
                                       const EndKeys& k, bool rebuild) {
  const std::int32_t q = set.id[j];
  const std::uint64_t* eb = set.keys_b + 2 * static_cast<std::size_t>(q);
  const std::uint64_t* ec = set.keys_c + 2 * static_cast<std::size_t>(q);
  if ((eb[0] < k.ub) & (k.lb < eb[1]) & (ec[0] < k.uc) & (k.lc < ec[1])) foundPair(p, q, rebuild);
}

inline void SweepAndPrune::open(ActiveSet& set, std::int32_t p, const EndKeys& k,
                                bool first_slab) {
  active_pos_[p] = static_cast<std::int32_t>(set.push(p, k, first_slab));
}

inline void SweepAndPrune::close(ActiveSet& set, std::int32_t p) {
  const std::size_t pos = static_cast<std::size_t>(active_pos_[p]);
  const std::int32_t moved = set.removeAt(pos);
  if (moved >= 0) active_pos_[moved] = static_cast<std::int32_t>(pos);
}

void SweepAndPrune::sweepForPairs(int axis, bool only_new) {
  // One sweep along `axis` with sets of open intervals. With only_new, old proxies are tested
  // only against new ones, so an insertion costs O(n + k * overlaps); otherwise every pair is
  // found and stamped (rebuild).
  const int axis_b = (axis + 1) % 3, axis_c = (axis + 2) % 3;
  const std::uint32_t* owner = owners_[axis].data();
  const std::size_t last = owners_[axis].size() - 1;
  const std::uint64_t* eb = ends_[axis_b].data();
  const std::uint64_t* ec = ends_[axis_c].data();
  active_.reserve(reserved_slots_);
  active_new_.reserve(reserved_slots_);
  active_.clear();
  active_new_.clear();
  active_.keys_b = active_new_.keys_b = eb;
  active_.keys_c = active_new_.keys_c = ec;
  for (std::size_t i = 1; i < last; ++i) {
    const std::uint32_t o = owner[i];
    const std::int32_t p = static_cast<std::int32_t>(o >> 1);
    const bool p_new = only_new && info_[p].is_new;
    ActiveSet& set = p_new ? active_new_ : active_;
    if ((o & 1u) != 0u) {
      close(set, p);
      continue;
    }
    const EndKeys k{eb[o], eb[o + 1], ec[o], ec[o + 1]};
    if (!only_new || p_new) testOpen<false>(active_, p, k, true, !only_new);
    testOpen<false>(active_new_, p, k, true, !only_new);
    open(set, p, k, false);
  }
}

bool SweepAndPrune::sweepSlabs(int axis, const double* mean_width, bool rebuild) {
  // Many bodies: cut a second axis into slabs about two mean widths wide and sweep each slab on
  // its own, so a lower endpoint is tested only against the open intervals of its slab. A box
  // goes into every slab it overlaps; a pair is reported in one slab only.
  const SlabGrid grid = slabGrid(axis, mean_width);
  if (grid.count == 0 || !binIntoSlabs(axis, grid)) return false;
  sweep_tests_ = sweepEachSlab(axis, grid, rebuild);
  return true;
}

SweepAndPrune::SlabGrid SweepAndPrune::slabGrid(int axis, const double* mean_width) const {
  // The other axis that fits the most slabs of two mean widths; none (count 0) when fewer than
  // four fit or there are too few proxies to share them.
  constexpr std::size_t kMaxSlabs = 4096;
  const std::size_t max_slabs = std::min<std::size_t>(kMaxSlabs, static_cast<std::size_t>(live_count_) / 8);
  SlabGrid grid;
  double slabs = 0.0, hi = 0.0;
  for (int k = 1; k < 3; ++k) {
    const int b = (axis + k) % 3;
    const std::vector<std::uint64_t>& kb = keys_[b];
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

inline std::uint32_t SweepAndPrune::SlabGrid::slabOf(std::uint64_t key) const {
  const double x = (unsortable64(key) - lo) * scale;
  return static_cast<std::uint32_t>(std::clamp(x, 0.0, static_cast<double>(count - 1)));
}

bool SweepAndPrune::binIntoSlabs(int axis, const SlabGrid& grid) {
  // Slab range of every proxy, then a stable counting sort of the sweep axis' endpoints into
  // the slabs (each slab's list stays sorted along the sweep axis). False when the boxes span
  // so many slabs that the lists would outgrow their space: one plain sweep then.
  const std::uint64_t* eb = ends_[grid.axis].data();
  slab_lo_.resize(info_.size());
  slab_hi_.resize(info_.size());
  slab_start_.assign(grid.count + 1, 0);
  std::size_t total = 0;
  for (std::size_t p = 0, slots = info_.size(); p < slots; ++p) {  // in slot order: streams
    if (info_[p].state != ProxyState::kLive) continue;
    const std::uint32_t s0 = grid.slabOf(eb[2 * p]), s1 = grid.slabOf(eb[2 * p + 1]);
    slab_lo_[p] = s0;
    slab_hi_[p] = s1;
    total += 2 * (s1 - s0 + 1);
    slab_start_[s0] += 2;  // difference array: +2 on [s0, s1]
    if (s1 + 1 < grid.count) slab_start_[s1 + 1] -= 2;
  }
  if (total > slab_owners_.capacity()) return false;
  // Running sum of the difference array = endpoints per slab; then exclusive prefix = starts.
  std::size_t run = 0, start = 0;
  for (std::size_t s = 0; s < grid.count; ++s) {
    run += slab_start_[s];
    slab_start_[s] = start;
    start += run;
  }
  slab_start_[grid.count] = start;
  slab_pos_.assign(slab_start_.begin(), slab_start_.end());
  slab_owners_.resize(total);
  const std::uint32_t* owner = owners_[axis].data();
  for (std::size_t i = 1, last = owners_[axis].size() - 1; i < last; ++i) {
    const std::uint32_t o = owner[i];
    const std::uint32_t p = o >> 1;
    for (std::uint32_t s = slab_lo_[p], s1 = slab_hi_[p]; s <= s1; ++s) slab_owners_[slab_pos_[s]++] = o;
  }
  return true;
}

std::int64_t SweepAndPrune::sweepEachSlab(int axis, const SlabGrid& grid, bool rebuild) {
  // Returns the overlap tests done.
  const int b = grid.axis, c = 3 - axis - grid.axis;
  const std::uint64_t* eb = ends_[b].data();
  const std::uint64_t* ec = ends_[c].data();
  const std::size_t total = slab_owners_.size();
  std::int64_t tests = 0;
  ActiveSet& set = active_;
  set.keys_b = eb;
  set.keys_c = ec;
  for (std::size_t s = 0; s < grid.count; ++s) {
    set.clear();
    const std::uint32_t slab = static_cast<std::uint32_t>(s);
    for (std::size_t i = slab_start_[s], end = slab_start_[s + 1]; i < end; ++i) {
      const std::uint32_t o = slab_owners_[i];
      const std::int32_t p = static_cast<std::int32_t>(o >> 1);
      // The keys of the endpoint a few places on: a random access, started early.
      const std::uint32_t ahead = slab_owners_[std::min(i + 8, total - 1)] & ~1u;
      __builtin_prefetch(eb + ahead);
      __builtin_prefetch(ec + ahead);
      if ((o & 1u) != 0u) {
        close(set, p);
        continue;
      }
      const EndKeys k{eb[o], eb[o + 1], ec[o], ec[o + 1]};
      const bool p_first = slab_lo_[p] == slab;
      tests += static_cast<std::int64_t>(testOpen<true>(set, p, k, p_first, rebuild));
      open(set, p, k, p_first);
    }
  }
  return tests;
}

// ---------------------------------------------------------------------------------------------
// Insertion of new proxies: merged into the sorted arrays in one batch, then their pairs.

void SweepAndPrune::insertPending() {
  if (pending_insert_.empty()) return;
  const std::size_t k = pending_insert_.size();
  stats_.inserted = static_cast<int>(k);
  // Batched: sort the new endpoints, then merge them into each axis from the back, so one
  // insertion costs O(n + k log k) instead of k passes of insertion sort.
  for (int axis = 0; axis < 3; ++axis) mergeNewEndpoints(axis);
  for (ProxyId id : pending_insert_) {
    info_[id].state = ProxyState::kLive;
    info_[id].is_new = true;
  }
  live_count_ += static_cast<int>(k);

  if (!insertByWindows()) {
    std::int64_t tests = 0;
    const int axis = cheapestSweepAxis(&tests);
    sweep_tests_ = tests;
    // Everything new (say the first update): a slab sweep may find all pairs, each once.
    findPairs(axis, tests, k == static_cast<std::size_t>(live_count_) ? SweepMode::kAllNew : SweepMode::kNewOnly);
  }
  for (ProxyId id : pending_insert_) info_[id].is_new = false;
  pending_insert_.clear();
}

void SweepAndPrune::mergeNewEndpoints(int axis) {
  sort_items_.clear();
  for (ProxyId id : pending_insert_) {
    const std::uint64_t owner = static_cast<std::uint64_t>(id) << 1;
    sort_items_.push_back(owner);
    sort_items_.push_back(owner | 1u);
  }
  const std::uint64_t* e = ends_[axis].data();
  std::sort(sort_items_.begin(), sort_items_.end(),
            [e](std::uint64_t x, std::uint64_t y) { return e[x] < e[y]; });

  std::vector<std::uint64_t>& keys = keys_[axis];
  std::vector<std::uint32_t>& owners = owners_[axis];
  const std::size_t old_size = keys.size();
  keys.resize(old_size + sort_items_.size());
  owners.resize(old_size + sort_items_.size());
  std::int64_t i = static_cast<std::int64_t>(old_size) - 2;  // last old real endpoint
  std::int64_t j = static_cast<std::int64_t>(sort_items_.size()) - 1;
  std::int64_t w = static_cast<std::int64_t>(keys.size()) - 2;
  keys.back() = kHighSentinel;
  owners.back() = kSentinelOwner;
  while (j >= 0) {
    const std::uint64_t new_key = e[sort_items_[j]];
    if (i >= 1 && keys[i] > new_key) {
      keys[w] = keys[i];
      owners[w] = owners[i];
      --i;
    } else {
      keys[w] = new_key;
      owners[w] = static_cast<std::uint32_t>(sort_items_[j]);
      --j;
    }
    --w;
  }
}

bool SweepAndPrune::insertByWindows() {
  // A few insertions: each new proxy looks only at the lower endpoints that can belong to a
  // box overlapping it on one axis, those within its window (see window()). False when a
  // sweep is cheaper.
  const std::size_t k = pending_insert_.size();
  const std::size_t n = keys_[0].size() - 2;
  if (32 * k > n) return false;
  const int axis = cheapestWindowAxis(static_cast<std::int64_t>(n / 4));
  if (axis < 0) return false;

  const std::uint32_t* owners = owners_[axis].data();
  for (ProxyId p : pending_insert_) {
    const Window w = window(axis, p);
    for (std::size_t i = w.from; i < w.to; ++i) {
      const std::uint32_t o = owners[i];
      if (o & 1u) continue;
      const std::int32_t q = static_cast<std::int32_t>(o >> 1);
      if (q == p || (info_[q].is_new && q > p)) continue;  // new pairs once, from the lower id
      if (overlaps(p, q)) beginPair(p, q);
    }
  }
  return true;
}

int SweepAndPrune::cheapestWindowAxis(std::int64_t limit) const {
  // The axis whose windows hold the fewest endpoints in all, if at most `limit`; else -1.
  int best_axis = -1;
  std::int64_t best_total = limit;
  for (int axis = 0; axis < 3; ++axis) {
    if (stale_[axis]) continue;  // out of order: no windows to look up
    std::int64_t total = 0;
    for (ProxyId id : pending_insert_) {
      const Window w = window(axis, id);
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

SweepAndPrune::Window SweepAndPrune::window(int axis, ProxyId p) const {
  // Positions in the endpoint array of `axis` from its lower bound minus the widest width
  // (with rounding slack) up to its upper bound.
  const std::uint64_t* keys = keys_[axis].data();
  const std::uint64_t* begin = keys + 1;
  const std::uint64_t* end = keys + keys_[axis].size() - 1;
  const std::uint64_t* kp = ends_[axis].data() + 2 * static_cast<std::size_t>(p);
  const double low = unsortable64(kp[0]);
  const double reach = max_width_[axis] + 1e-12 * (std::abs(low) + max_width_[axis]) + 1e-300;
  Window w;
  w.from = static_cast<std::size_t>(std::lower_bound(begin, end, lower64(low - reach)) - keys);
  w.to = static_cast<std::size_t>(std::upper_bound(begin, end, kp[1]) - keys);
  return w;
}

}  // namespace workspace_proximity
