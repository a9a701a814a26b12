// The public SweepAndPrune: proxies in and out, and update() as a sequence of steps, each the
// job of a file pair (sweep_and_prune_state.hpp lists them).

#include "workspace_proximity/sweep_and_prune.hpp"

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "sweep_and_prune_coasting.hpp"
#include "sweep_and_prune_incremental.hpp"
#include "sweep_and_prune_insert.hpp"
#include "sweep_and_prune_rebuild.hpp"
#include "sweep_and_prune_state.hpp"

namespace workspace_proximity {
namespace sap {
namespace {

// What an update did to the arrays: nothing, moved a few proxies' endpoints, or re-sorted.
enum class Sorted : std::uint8_t { kNothing, kFew, kAll, kSwapped };

void keepHeadroom(State& s) {
  // A quarter of headroom in the candidate table: it then grows while the count climbs to its
  // usual level, not later when the count first touches a new maximum by chance.
  if (4 * static_cast<std::size_t>(s.cands.size()) > 3 * s.cands.capacity()) {
    s.cands.reserve(2 * s.cands.capacity());
  }
  // And room for two candidates per live proxy from the start: coasting's first long run,
  // after the short ones on probation, gives everybody its full room at once, and the count
  // then jumps to a level it never had (jitter +-1 %, N = 10 000: over three quarters of the
  // table at update 43, well past any warm-up).
  const std::size_t per_proxy = 2 * static_cast<std::size_t>(s.live_count);
  if (s.cands.capacity() < per_proxy) s.cands.reserve(per_proxy);
  // Every list holds candidates of this update or the last: with the table's capacity they
  // never grow unless the table does.
  if (s.next.cands.capacity() < s.cands.capacity()) s.next.cands.reserve(s.cands.capacity());
  if (s.cands.capacity() < s.next.cands.capacity()) s.cands.reserve(s.next.cands.capacity());
  const std::size_t cap = s.cands.capacity();
  for (std::vector<BroadPair>* v : {&s.next.found, &s.next.ordered}) {
    if (v->capacity() < cap) reserveWritten(v, cap);
  }
  if (s.next.order_of.capacity() < cap) reserveWritten(&s.next.order_of, cap);
  for (std::vector<BroadPair>* v : {&s.cand_began, &s.cand_ended, &s.exact, &s.began, &s.ended}) {
    if (v->capacity() < cap) v->reserve(cap);
  }
}

// The throws out of line: moveProxy runs once per body and cycle, and the strings they build
// made its frame and its register saves the size of its work.
[[noreturn]] __attribute__((noinline, cold)) void throwNoSuchProxy(const char* what) {
  throw std::out_of_range(std::string("SweepAndPrune::") + what + ": no such proxy");
}
[[noreturn]] __attribute__((noinline, cold)) void throwNotLive(const char* what) {
  throw std::invalid_argument(std::string("SweepAndPrune::") + what + ": proxy is not live");
}
[[noreturn]] __attribute__((noinline, cold)) void throwInvalidBounds(const char* what) {
  throw std::invalid_argument(std::string("SweepAndPrune::") + what + ": invalid bounds");
}

inline void checkLive(const State& s, ProxyId id, const char* what) {
  if (id < 0 || static_cast<std::size_t>(id) >= s.info.size()) throwNoSuchProxy(what);
  const ProxyInfo& p = s.info[static_cast<std::size_t>(id)];
  if (p.state == ProxyState::kFree || p.pending_remove) throwNotLive(what);
}

void dropRemovedEndpoints(State& s, int axis) {
  // Compacts the endpoint array in one pass.
  std::vector<std::uint64_t>& keys = s.keys[axis];
  std::vector<std::uint32_t>& owners = s.owners[axis];
  const std::size_t last = keys.size() - 1;
  std::size_t w = 1;
  for (std::size_t r = 1; r < last; ++r) {
    const std::uint32_t owner = owners[r];
    if (s.info[owner >> 1].pending_remove) continue;
    keys[w] = keys[r];
    owners[w] = owner;
    ++w;
  }
  keys[w] = kHighSentinel;
  owners[w] = kSentinelOwner;
  keys.resize(w + 1);
  owners.resize(w + 1);
}

void applyRemovals(State& s) {
  if (s.pending_remove.empty()) return;
  s.stats.removed = static_cast<int>(s.pending_remove.size());

  // Their pairs end. Walk backwards so eraseAt's swap-with-last never skips a pair.
  std::vector<Candidate>& dense = s.cands.mutablePairs();
  for (int i = static_cast<int>(dense.size()) - 1; i >= 0; --i) {
    if (s.info[dense[i].proxy_a].pending_remove || s.info[dense[i].proxy_b].pending_remove) {
      s.cand_ended.push_back(dense[i]);
      s.cands.eraseAt(i);
    }
  }
  for (int axis = 0; axis < 3; ++axis) dropRemovedEndpoints(s, axis);

  for (ProxyId id : s.pending_remove) {
    ProxyInfo& p = s.info[id];
    s.setFat(p, false);
    p.state = ProxyState::kFree;
    p.pending_remove = false;
    p.next_free = s.free_list;
    s.free_list = id;
    --s.live_count;
  }
  s.pending_remove.clear();
  if (s.live_count == 0) {
    // No endpoints left: the widest bounds are those of the proxies waiting to be inserted
    // (reset to 0, their widths were forgotten, and the next insertions' windows missed pairs
    // with them: fuzz_sweep_and_prune, session 21).
    for (int axis = 0; axis < 3; ++axis) {
      const std::uint64_t* e = s.ends[axis].data();
      double widest = 0.0;
      for (ProxyId id : s.pending_insert) {
        const std::size_t o = 2 * static_cast<std::size_t>(id);
        widest = std::max(widest, sap::unsortable64(e[o + 1]) - sap::unsortable64(e[o]));
      }
      s.max_width[axis] = widest;
    }
    for (bool& stale : s.stale) stale = false;  // no endpoints left: every axis is in order
    s.sweep_tests = 0;
    s.plain_tests = 0;
  }
}

std::int64_t rebuildCost(const State& s, bool sweep_axis_only) {
  // What a rebuild costs, counted in swaps: a fixed price per endpoint (reading, radix sorting
  // and sweeping it) and an eighth of a swap per overlap test of the sweep. Measured on the
  // uniform scenes (AMD EPYC, issue 14): a swap with its pair events costs 8-16 ns at 200 to
  // 20 000 endpoints per axis; a rebuild that sorts only the sweep axis 32-50 ns per endpoint,
  // one that sorts all three up to 1.4 times that. The break-even moves from 2 swaps per
  // endpoint at 200 endpoints to 4 at 20 000. Scaled by rebuild_factor: the swap budget of
  // insertion sort (sorting all axes), or the swaps past which a streak goes on (the sweep
  // axis only).
  const double n = 2.0 * s.live_count;
  const double per_endpoint = sweep_axis_only ? 2.0 : 3.0;
  const double estimate = per_endpoint * n + 0.125 * static_cast<double>(s.sweep_tests);
  const double budget = std::max(64.0, s.config.rebuild_factor * estimate);
  return budget > 4e18 ? std::numeric_limits<std::int64_t>::max()
                       : static_cast<std::int64_t>(budget);
}

// What a re-sort did, for the measured choice of the off path (State::insertion_ns).
enum class Resorted : std::uint8_t { kInsertion, kStreak, kOther, kFailedInsertion };

// Updates a rebuild streak lasts before insertion sort is measured against it, and how long
// (updates) such a measurement stands.
constexpr std::uint32_t kProbeAfter = 4;
constexpr std::uint32_t kMeasurementLife = 512;

// The streak under way goes on only if insertion sort was not measured cheaper lately; a long
// one whose estimate is within insertion sort's budget measures it when it has not lately.
bool leaveStreak(State& s, std::int64_t swaps) {
  if (!s.config.measure_streaks || swaps > rebuildCost(s, false)) return false;
  if (s.probe_insertion) return true;
  const bool recent = s.insertion_ns >= 0.0 && s.updates - s.insertion_at <= kMeasurementLife;
  if (!recent) {
    if (s.streak_length < kProbeAfter) return false;
    s.probe_insertion = true;  // (a full rebuild now, insertion sort at the next update)
    return true;
  }
  return s.streak_ns >= 0.0 && s.insertion_ns < 0.85 * s.streak_ns;
}

// Re-sorts every axis, incrementally or by a rebuild. `jump`: the enlarged bounds of many
// proxies changed at once (skip the insertion-sort attempt when the swaps estimated from the
// new keys exceed a rebuild); `allow_streak`: a rebuild may leave two axes unsorted (not while
// coasting: moveEscapers needs them).
Resorted resortOnce(State& s, bool jump, bool allow_streak) {
  const std::size_t began_mark = s.cand_began.size();
  const std::size_t ended_mark = s.cand_ended.size();
  if (!jump && !s.last_rebuilt && !s.anyStale()) {
    if (!sortAxes(s, true, rebuildCost(s, false))) {
      // Motion too large for insertion sort to pay: undo its partial pair changes, then sort
      // from scratch and diff the new pair set against the old one.
      rollBack(s, began_mark, ended_mark);
      rebuild(s, false, false);
      return Resorted::kFailedInsertion;
    }
    return Resorted::kInsertion;
  }
  // After a rebuild: rebuild again (the sweep axis only) while insertion sort would cost more.
  const std::int64_t swaps = estimateAllSwaps(s);
  s.last_estimate = swaps;
  if (swaps > rebuildCost(s, allow_streak)) {
    if (!(allow_streak && leaveStreak(s, swaps))) {
      rebuild(s, allow_streak, !s.anyStale());
      return allow_streak ? Resorted::kStreak : Resorted::kOther;
    }
    s.stats.left_streak = true;
  }
  if (s.anyStale()) {
    rebuild(s, false, false);  // stale axes: insertion sort would miss pair events
    return Resorted::kOther;
  }
  if (!sortAxes(s, false, rebuildCost(s, false))) {
    rollBack(s, began_mark, ended_mark);
    rebuild(s, false, true);
    return Resorted::kFailedInsertion;
  }
  return Resorted::kInsertion;
}

void resort(State& s, bool jump, bool allow_streak) {
  // Coasting off (the only caller that allows streaks): the kinds of re-sort timed, for
  // leaveStreak(). Two clock reads per update, next to re-sorts of thousands of endpoints.
  const bool timed = allow_streak && s.config.measure_streaks;
  const auto start = timed ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point();
  const Resorted kind = resortOnce(s, jump, allow_streak);
  s.streak_length = kind == Resorted::kStreak ? s.streak_length + 1 : 0;
  // Coasting off: the motion's swaps, for the next retry (a failed insertion sort's are
  // unknown; a rebuild's were estimated in this update).
  if (allow_streak && kind != Resorted::kFailedInsertion) {
    s.coast.sortedOff(static_cast<double>(kind == Resorted::kInsertion ? s.stats.swaps : s.last_estimate));
  }
  if (!timed) return;
  const double ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - start).count();
  auto average = [](double* mean, double sample) { *mean = *mean < 0.0 ? sample : 0.75 * *mean + 0.25 * sample; };
  switch (kind) {
    case Resorted::kInsertion:
      average(&s.insertion_ns, ns);
      s.insertion_at = s.updates;
      s.probe_insertion = false;
      break;
    case Resorted::kFailedInsertion:
      // It cost an insertion sort given up, its roll-back and a rebuild: what insertion sort
      // costs with this motion, as far as the choice is concerned.
      if (s.probe_insertion || s.insertion_ns >= 0.0) {
        average(&s.insertion_ns, ns);
        s.insertion_at = s.updates;
      }
      s.probe_insertion = false;
      break;
    case Resorted::kStreak:
      average(&s.streak_ns, ns);
      break;
    case Resorted::kOther:
      break;
  }
}

// Enlarges and re-sorts what left its bounds, as coasting's policy says.
Sorted handleEscapers(State& s) {
  // Removed proxies may still be listed: drop them.
  std::size_t w = 0;
  for (ProxyId id : s.escapers) {
    if (s.info[static_cast<std::size_t>(id)].state == ProxyState::kLive) s.escapers[w++] = id;
    else s.info[static_cast<std::size_t>(id)].escaped = false;
  }
  s.escapers.resize(w);
  s.stats.escaped = static_cast<int>(w);
  // A retry of coasting that would fail at once, or in the scene it last failed in, is
  // postponed without enlarging anybody.
  if (s.moved && s.coast.retryDue(s.updates)) {
    if (runsTooShort(s, s.config.coast_updates)) {
      s.coast.postponeRetry(s.updates);
    } else {
      s.coast.repeatsFailure(s.updates, s.live_count);
    }
  }
  const CoastPolicy::Step step = s.coast.step(s.updates, w, s.live_count, s.anyStale(), s.moved);
  // The next arrays, built over the last updates, take over when due, or when the run ends
  // early (a build still under way is finished first, when past its enlargements); a run that
  // ends before that ends at once, as without them.
  const bool run_over = step == CoastPolicy::Step::kEnlargeAll;
  if (s.coast.lead() > 0.0 &&
      (run_over ? finishNext(s) : (nextReady(s) && s.updates >= s.next.swap_at))) {
    return swapInNext(s, run_over) ? Sorted::kAll : Sorted::kSwapped;
  }
  if (step == CoastPolicy::Step::kEnlargeAll || step == CoastPolicy::Step::kResort) abandonNext(s);
  switch (step) {
    case CoastPolicy::Step::kNothing:
      return Sorted::kNothing;
    case CoastPolicy::Step::kResort:
      // Not coasting: moveProxy gave the arrays the new bounds.
      resort(s, false, true);
      return Sorted::kAll;
    case CoastPolicy::Step::kMoveFew: {
      // The arrays are in order: only the escapers' endpoints move.
      validateFlags(s);
      const std::size_t swaps = moveEscapers(s);
      s.coast.movedFew(w, swaps);
      return Sorted::kFew;
    }
    case CoastPolicy::Step::kEnlargeAll:
      break;
  }
  // Many: everybody gets new enlarged bounds now, so that they leave them together again.
  validateFlags(s);
  s.last_estimate = -1;
  if (s.coast.steadyLeadDue(s.updates)) {
    s.coast.takeSteadyLead(steadyLeadCapped(s, CoastPolicy::kSteadyLead * s.config.coast_updates,
                                            CoastPolicy::kMinSpreadRun));
  }
  enlargeAll(s, s.coast.lead());
  s.stats.enlarged_all = true;
  resort(s, true, false);  // every axis in order: moveEscapers needs them
  CoastPolicy::Resort r;
  r.live = s.live_count;
  r.swaps = s.stats.swaps;
  r.rebuilt = s.stats.rebuilt;
  r.candidates = static_cast<std::size_t>(s.cands.size());
  r.sweep_tests = s.sweep_tests;
  r.estimated_swaps = s.last_estimate;
  r.pairs = s.exact.size();
  s.coast.enlargedAll(s.updates, r);
  return Sorted::kAll;
}

}  // namespace

void resortAll(State& s) { resort(s, true, false); }

State::State(const SweepAndPruneConfig& c)
    : config(c), cands(c.initial_pair_capacity), coast(c.coast_updates, c.steady_lead) {
  reserveSlots(static_cast<std::size_t>(std::max(c.initial_proxy_capacity, 1)));
  keepHeadroom(*this);
  for (int axis = 0; axis < 3; ++axis) {
    // Sentinels end every inner loop without a bounds check.
    keys[axis] = {kLowSentinel, kHighSentinel};
    owners[axis] = {kSentinelOwner, kSentinelOwner};
  }
}

void State::beginPair(std::int32_t a, std::int32_t b) {
  bool inserted = false;
  Candidate* pair = cands.insert(a, b, &inserted);
  if (inserted) {
    pair->epoch = epoch;
    cand_began.push_back(*pair);
  }
}

void State::endPair(std::int32_t a, std::int32_t b) {
  Candidate removed;
  if (cands.erase(a, b, &removed)) cand_ended.push_back(removed);
}

void State::reserveSlots(std::size_t slots) {
  reserved_slots = slots;
  info.reserve(slots);
  pending_insert.reserve(slots);
  pending_remove.reserve(slots);
  for (std::vector<std::uint64_t>& e : ends) e.reserve(2 * slots);
  for (std::vector<std::uint64_t>& e : prev_ends) e.reserve(2 * slots);
  next.reserve(slots);
  tight.reserve(6 * slots);
  base.reserve(6 * slots);
  motion.reserve(slots);
  escapers.reserve(slots);
  escaper_old.reserve(6 * slots);
  sort.reserve(slots);
  breaks.reserve(2 * slots + 2);
  sweep.reserve(slots);
  for (int axis = 0; axis < 3; ++axis) {
    keys[axis].reserve(2 * slots + 2);
    owners[axis].reserve(2 * slots + 2);
  }
}

}  // namespace sap

using sap::ProxyInfo;
using sap::ProxyState;

SweepAndPrune::SweepAndPrune(const SweepAndPruneConfig& config) {
  if (!(config.coast_updates >= 0.0 && config.coast_updates <= 1e6)) {
    throw std::invalid_argument("SweepAndPrune: coast_updates must be in [0, 1e6]");
  }
  if (!(config.max_lead_fraction >= 0.0 && config.max_lead_fraction <= 1e6)) {
    throw std::invalid_argument("SweepAndPrune: max_lead_fraction must be in [0, 1e6]");
  }
  if (!(config.spread_updates >= 0 && config.spread_updates <= 1024)) {
    throw std::invalid_argument("SweepAndPrune: spread_updates must be in [0, 1024]");
  }
  s_ = std::make_unique<sap::State>(config);
}

SweepAndPrune::~SweepAndPrune() = default;
SweepAndPrune::SweepAndPrune(SweepAndPrune&&) noexcept = default;
SweepAndPrune& SweepAndPrune::operator=(SweepAndPrune&&) noexcept = default;

SweepAndPrune::ProxyId SweepAndPrune::createProxy(const Aabb& bounds) {
  if (!bounds.valid()) sap::throwInvalidBounds("createProxy");
  sap::State& s = *s_;
  ProxyId id;
  if (s.free_list >= 0) {
    id = s.free_list;
    s.free_list = s.info[id].next_free;
  } else {
    id = static_cast<ProxyId>(s.info.size());
    if (s.info.size() >= s.reserved_slots) s.reserveSlots(2 * s.reserved_slots);
    s.info.emplace_back();
    for (std::vector<std::uint64_t>& e : s.ends) e.resize(e.size() + 2);
    s.tight.resize(s.tight.size() + 6);
    s.base.resize(s.base.size() + 6);
    s.motion.emplace_back();
    s.sweep.active_pos.push_back(-1);
  }
  sap::writeTight(s, id, bounds);
  ProxyInfo& p = s.info[id];
  p.next_free = -1;
  p.state = ProxyState::kPendingInsert;
  p.pending_remove = false;
  p.is_new = false;
  p.escaped = false;
  p.fat = false;
  s.motion[static_cast<std::size_t>(id)] = sap::ProxyMotion{{0.0f, 0.0f, 0.0f}, 0.0f, 0.0f};
  sap::enlarge(s, id, 0.0);  // no motion seen yet: its given bounds
  p.enlarged_at = s.updates + 1;  // as of the update that inserts it
  s.pending_insert.push_back(id);
  return id;
}

void SweepAndPrune::destroyProxy(ProxyId id) {
  sap::State& s = *s_;
  sap::checkLive(s, id, "destroyProxy");
  ProxyInfo& p = s.info[id];
  if (p.state == ProxyState::kPendingInsert) {
    // Never entered the arrays: forget it now.
    auto it = std::find(s.pending_insert.begin(), s.pending_insert.end(), id);
    *it = s.pending_insert.back();
    s.pending_insert.pop_back();
    p.state = ProxyState::kFree;
    p.next_free = s.free_list;
    s.free_list = id;
    return;
  }
  // Live: it keeps its slot (so the id is not reused) until update() takes it out.
  p.pending_remove = true;
  s.pending_remove.push_back(id);
}

// (tightKeysInside reads a box's six bounds as they lie: lower x, y, z, then upper x, y, z.)
static_assert(std::is_standard_layout<Aabb>::value && sizeof(Aabb) == 6 * sizeof(double) &&
                  offsetof(Aabb, upper) == 3 * sizeof(double),
              "Aabb is six doubles in a row");

namespace sap {
namespace {

// moveProxy's general path: the checks one by one, escapers, proxies not in the arrays yet,
// coasting off. Out of line, so that the path nearly every call takes while coasting keeps no
// registers of its own to save.
__attribute__((noinline)) void moveProxyChecked(State& s, ProxyId id, const Aabb& bounds) {
  if (!bounds.valid()) throwInvalidBounds("moveProxy");
  checkLive(s, id, "moveProxy");
  // Only the proxy's keys change here; update() re-sorts what left its enlarged bounds.
  ProxyInfo& p = s.info[static_cast<std::size_t>(id)];
  if (s.coast.lead() <= 0.0 || p.state == ProxyState::kPendingInsert) {
    // Not coasting (or not in the arrays yet): the arrays take the given bounds, as they come.
    // The previous ones stay in base, should coasting start again.
    std::uint64_t* t = s.tight.data() + 6 * static_cast<std::size_t>(id);
    std::uint64_t* b = s.base.data() + 6 * static_cast<std::size_t>(id);
    const std::size_t o = 2 * static_cast<std::size_t>(id);
    for (int axis = 0; axis < 3; ++axis) {
      b[2 * axis] = t[2 * axis];
      b[2 * axis + 1] = t[2 * axis + 1];
      std::uint64_t* e = s.ends[axis].data() + o;
      e[0] = t[2 * axis] = lower64(bounds.lower[axis]);
      e[1] = t[2 * axis + 1] = upper64(bounds.upper[axis]);
      s.max_width[axis] = std::max(s.max_width[axis], bounds.upper[axis] - bounds.lower[axis]);
    }
    // As of the next update (a pending proxy's: the one that inserts it).
    p.enlarged_at = p.state == ProxyState::kLive ? s.updates : s.updates + 1;
    s.setFat(p, false);
    s.moved |= p.state == ProxyState::kLive;
    return;
  }
  bool equal = false;
  const bool inside = writeTightInside(s, id, bounds, &equal);
  if (p.escaped) return;  // enlarged anew in the update, from its latest bounds
  if (!inside) {
    p.escaped = true;
    s.escapers.push_back(id);
  } else {
    s.setFat(p, !equal);  // a box that shrank inside its bounds is enlarged now
  }
}

}  // namespace
}  // namespace sap

void SweepAndPrune::moveProxy(ProxyId id, const Aabb& bounds) {
  sap::State& s = *s_;
  // Nearly every call while coasting: a live proxy whose new bounds lie within its enlarged
  // ones. Its keys, the general path's checks and the test against its enlarged keys in one
  // pass, two bounds at a time (tightKeysInside); the general path takes the rest and decides
  // as before, bit for bit.
  if (static_cast<std::size_t>(id) < s.info.size() && s.coast.lead() > 0.0) {
    ProxyInfo& p = s.info[static_cast<std::size_t>(id)];
    const std::size_t o = 2 * static_cast<std::size_t>(id);
    const std::uint64_t* const enlarged[3] = {s.ends[0].data() + o, s.ends[1].data() + o, s.ends[2].data() + o};
    bool equal = false;
    if (p.state == ProxyState::kLive && !p.pending_remove &&
        sap::tightKeysInside(bounds.lower.data(), enlarged, s.tight.data() + 6 * static_cast<std::size_t>(id),
                             &equal)) {
      if (!p.escaped) s.setFat(p, !equal);  // (escaped: enlarged anew in the update)
      return;
    }
  }
  sap::moveProxyChecked(s, id, bounds);
}

void SweepAndPrune::update() {
  sap::State& s = *s_;
  s.stats = SweepAndPruneStats();
  s.cand_began.clear();
  s.cand_ended.clear();
  ++s.updates;
  // The next arrays hold the proxies of the update that started them.
  if (!s.pending_insert.empty() || !s.pending_remove.empty()) sap::abandonNext(s);
  sap::applyRemovals(s);
  // (A run's end enlarges everybody even when nobody left: ask what it did.)
  const sap::Sorted done = s.live_count > 0 ? sap::handleEscapers(s) : sap::Sorted::kNothing;
  const bool inserted = !s.pending_insert.empty();
  const bool sorted = done != sap::Sorted::kNothing || inserted;
  s.moved = false;
  for (ProxyId id : s.escapers) s.info[static_cast<std::size_t>(id)].escaped = false;
  s.escapers.clear();
  s.stats.coasted = !sorted;
  sap::insertPending(s);
  if (sorted) s.last_rebuilt = s.stats.rebuilt;
  sap::advanceNext(s);
  s.stats.next_ready = sap::nextReady(s);
  s.stats.lead = s.coast.lead();
  if (s.next.swapped) {
    sap::reportSwapped(s);
  } else {
    sap::reportTouching(s);
    sap::trackNextFlags(s);
  }
  sap::keepHeadroom(s);
  // The arrays are now sorted by the current keys: remember them for the next update's events
  // (none come from a stale axis: the next update rebuilds). Nothing changed when coasting;
  // moveEscapers() wrote the keys it changed.
  if ((done != sap::Sorted::kAll && !inserted) || s.anyStale()) return;
  for (int axis = 1; axis < 3; ++axis) {
    s.prev_ends[axis].resize(s.ends[axis].size());
    std::memcpy(s.prev_ends[axis].data(), s.ends[axis].data(), s.ends[axis].size() * sizeof(std::uint64_t));
  }
}

const std::vector<BroadPair>& SweepAndPrune::pairs() const { return *s_->pairs_out; }
const std::vector<BroadPair>& SweepAndPrune::beganPairs() const { return *s_->began_out; }
const std::vector<BroadPair>& SweepAndPrune::endedPairs() const { return *s_->ended_out; }

bool SweepAndPrune::hasPair(ProxyId a, ProxyId b) const {
  const BroadPair* c = s_->cands.find(a, b);
  return c != nullptr && (s_->fat_count == 0 || c->touching != 0);
}

Aabb SweepAndPrune::storedBounds(ProxyId id) const {
  const sap::State& s = *s_;
  if (id < 0 || static_cast<std::size_t>(id) >= s.info.size()) {
    throw std::out_of_range("SweepAndPrune::storedBounds: no such proxy");
  }
  Aabb box;
  const std::uint64_t* t = s.tight.data() + 6 * static_cast<std::size_t>(id);
  for (int axis = 0; axis < 3; ++axis) {
    box.lower[axis] = sap::unsortable64(t[2 * axis]);
    box.upper[axis] = sap::unsortable64(t[2 * axis + 1]);
  }
  return box;
}

Aabb SweepAndPrune::enlargedBounds(ProxyId id) const {
  const sap::State& s = *s_;
  if (id < 0 || static_cast<std::size_t>(id) >= s.info.size()) {
    throw std::out_of_range("SweepAndPrune::enlargedBounds: no such proxy");
  }
  Aabb box;
  for (int axis = 0; axis < 3; ++axis) {
    box.lower[axis] = sap::unsortable64(s.ends[axis][2 * static_cast<std::size_t>(id)]);
    box.upper[axis] = sap::unsortable64(s.ends[axis][2 * static_cast<std::size_t>(id) + 1]);
  }
  return box;
}

const std::vector<BroadPair>& SweepAndPrune::candidatePairs() const { return s_->cands.pairs(); }
int SweepAndPrune::proxyCount() const { return s_->live_count; }
const SweepAndPruneStats& SweepAndPrune::stats() const { return s_->stats; }

}  // namespace workspace_proximity
