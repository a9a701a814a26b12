#include "sweep_and_prune_next.hpp"

#include <algorithm>
#include <cstring>
#include <utility>

#include "sweep_and_prune_coasting.hpp"
#include "sweep_and_prune_incremental.hpp"
#include "sweep_and_prune_state.hpp"

namespace workspace_proximity {
namespace sap {
namespace {

using Stage = NextArrays::Stage;

// Work units of a build's parts (about a nanosecond each on the benchmark machine, as
// CoastPolicy's): one proxy enlarged; one endpoint copied with its next key (and sampled for the
// swap estimate); one position of the insertion sort, one endpoint it moves and one place that
// endpoint moves by; one endpoint swept, and one pair it finds; a proxy ranked and a pair ordered
// for the table. Each stage is priced against enlarging (the anchor, 60 a proxy): a slice's budget
// buys the same time in every stage, so that no update carries a dearer slice than the others.
// Timed per stage at +-0.5 %, +-1 % and +-5 % jitter, N = 1 000 and 10 000, on an Intel Xeon
// (bench/results/NOTES.md section 28): per unit of the anchor, a radix sort of one axis 1.7-2.4
// times the 4 units an endpoint it was given before, the table's order 1.8-2.6 times, a pair found
// by the sweep ~30 units where 3 were counted (the +-5 % rows' sweeps took twice the +-1 % rows'
// per endpoint); earlier, on an AMD EPYC, a build's sort took 55 us by insertion (1.2-1.4 swaps per
// endpoint) and 37 us by radix sort, for 6 000 endpoints (section 22). An endpoint the insertion
// sort moves costs its branch's wrong guess (~7 ns), each place it moves by ~0.5 ns (timed on the
// walkers' slices, AMD EPYC VM, section 35): priced 5 units a place before, the walkers' heights (4
// values, a few nanometres apart: one radix prefix each) took 7 slices of ~80 us for ~30 places per
// endpoint moved, the build missed its swap and the run ended at once (N = 10 000: 4-6 ms, the
// p99).
constexpr double kEnlargeUnits = 60.0;
constexpr double kCopyUnits = 2.0;
constexpr double kSortUnits = 1.0;
constexpr double kMoveUnits = 6.0;
constexpr double kSwapUnits = 0.5;
// insertionSortFrom() counts whole numbers: half units.
constexpr double kHalfUnits = 2.0;
constexpr InsertionWork kInsertionWork{static_cast<std::int64_t>(kHalfUnits * kSortUnits),
                                       static_cast<std::int64_t>(kHalfUnits * kMoveUnits),
                                       static_cast<std::int64_t>(kHalfUnits * kSwapUnits)};
constexpr double kSweepUnits = 14.0;
constexpr double kRadixUnits = 8.0;  // per endpoint: a radix sort of one axis from scratch
// Its steps (RadixSteps), per endpoint: the prefixes (the axis' range, then a conversion and a
// product each), the digits counted, one scatter per pass, the keys and owners gathered.
constexpr double kPrefixUnits = 2.5;
constexpr double kCountUnits = 1.0;
constexpr double kScatterUnits = 1.25;
constexpr double kGatherUnits = 1.5;
constexpr double kBeginSweepUnits = 20.0;  // per proxy: the widths and the slab lists
constexpr double kPlanSweepUnits = 6.0;    // of which the widths (the plan)
constexpr double kBinSweepUnits = kBeginSweepUnits - kPlanSweepUnits;  // and the slab lists
constexpr double kListUnits = 30.0;  // per pair found by the sweep: its overlap tests, listed
constexpr double kOrderUnits = 16.0;  // per pair found: counted and placed in proxy order
constexpr double kCountPlacesUnits = 10.0;  // of which counted (its bounds read: random reads)
constexpr double kPlaceUnits = kOrderUnits - kCountPlacesUnits;  // and placed
constexpr double kRankUnits = 4.0;    // per slot: its rank along the sweep axis, its count

// The arrays of the build and the current ones trade places (vectors and tables swap their
// buffers: no copy, no allocation), so that the sweep kernel runs on the next arrays as on the
// current ones.
void exchange(State& s) {
  NextArrays& n = s.next;
  for (int axis = 0; axis < 3; ++axis) {
    // The next keys are sized by the slots at the build's start. A slot created since (its
    // proxy destroyed before an update, or the build would have been abandoned) is free, and
    // createProxy writes its keys when it takes it, but the arrays must reach it: swapped in
    // short, a proxy created there wrote past their end and the next new slot's zeros
    // overwrote it (fuzz_sweep_and_prune, session 21). Within the reserved slots: no
    // allocation.
    n.ends[axis].resize(s.ends[axis].size());
    s.ends[axis].swap(n.ends[axis]);
    s.keys[axis].swap(n.keys[axis]);
    s.owners[axis].swap(n.owners[axis]);
  }
  std::swap(s.cands, n.cands);
}

// A step that cannot be cut (a step of a radix sort, the sweep's plan or its slab lists, the
// table's count or its placing) and costs
// `cost` waits for the next slice when less than that is left of this one and less than its
// share, unless the build is late (the swap two updates off or less). (Waiting whenever under
// three quarters of a slice were left gave each axis' radix sort a slice of its own: a build
// planned for 12 slices took 15, so that half the updates carried one.)
bool waitForSlice(const State& s, double budget, double full, double cost) {
  return budget < cost && budget < 0.75 * full && s.next.swap_at > s.updates + 2;
}

void start(State& s) {
  NextArrays& n = s.next;
  const std::uint32_t slices = s.coast.nextSlices(static_cast<std::uint32_t>(s.config.spread_updates));
  n.started = s.updates;
  n.swap_at = s.coast.nextSwapAt(s.updates, slices);
  n.stage = Stage::kEnlarge;
  n.flags_tracked = false;
  n.cursor = 0;
  n.axis = 0;
  n.sort_swaps = 0;
  n.jump_swaps = 0;
  n.radix = false;
  n.radix_steps = RadixSteps();
  n.sweep_step = 0;
  n.counted = false;
  for (int axis = 0; axis < 3; ++axis) n.ends[axis].resize(s.ends[axis].size());
  // Its work, spread over the updates before the one that swaps it in, 1.25 times the even
  // share per slice (a build that takes longer than estimated still has the updates up to
  // the run's expected end: CoastPolicy::kSwapMargin). With its stages priced alike, a build
  // at the even share (1.05 before) took every slice planned, and half the updates of a long
  // run carried one: the median update was then a slice's (+-1 % jitter, N = 1 000: 45 % of
  // the updates against 41 % at 1.25).
  const double live = static_cast<double>(s.live_count);
  const double work = kEnlargeUnits * live + 3.0 * (kCopyUnits + kRadixUnits) * 2.0 * live +
                      kSweepUnits * 2.0 * live + kBeginSweepUnits * live + 2.0 * kRankUnits * live +
                      (kListUnits + kOrderUnits + CoastPolicy::kFoundWork) *
                          static_cast<double>(s.cands.size());
  const double updates = std::max(1.0, static_cast<double>(n.swap_at - s.updates) - 1.0);
  n.budget = 1.25 * work / updates;
}

// Next bounds for the slots from the cursor on, within `budget`; returns what is left of it.
double enlargeSome(State& s, double budget) {
  NextArrays& n = s.next;
  // Each proxy's lead grows by the updates until the swap: after it, its bounds then hold as
  // long as bounds enlarged at the swap would; a side moving inward starts where it will be
  // then (trim), so that the room it passes through before the swap is not carried after it.
  // (At least one update: a late build, past its swap's update, takes its lead as at a swap.)
  const double until_swap = n.swap_at > s.updates ? static_cast<double>(n.swap_at - s.updates) : 1.0;
  const std::size_t slots = s.info.size();
  while (n.cursor < slots && budget > 0.0) {
    const std::size_t p = n.cursor++;
    if (s.info[p].state != ProxyState::kLive) continue;
    enlargeInto(s, static_cast<ProxyId>(p), s.coast.lead(), n.ends, until_swap);
    budget -= kEnlargeUnits;
  }
  if (n.cursor >= slots) {
    n.stage = Stage::kSort;
    n.axis = 0;
    n.cursor = 0;
  }
  return budget;
}

// Work units of a radix sort's next step, for an axis of `size` endpoints.
double radixStepUnits(const RadixSteps& r, std::size_t size) {
  using Step = RadixSteps::Step;
  const double per = r.next == Step::kPrefixes ? kPrefixUnits
                     : r.next == Step::kCounts ? kCountUnits
                     : r.next == Step::kScatter ? kScatterUnits
                     : r.next == Step::kGather ? kGatherUnits
                                               : 0.0;
  return per * static_cast<double>(size);
}

// The endpoint arrays of the next bounds, axis after axis: the current order with the next
// keys (nearly in order), then insertion sort without pair events, a slice at a time; or, when
// the swaps estimated from those keys would cost more than sorting from scratch (more than
// about 2 per endpoint, 1.4 before session 25: +-5 % jitter at N = 10 000 made 450 000 per
// axis), a radix sort, a step at a time (the prefixes, the counts, each pass, the gather: each
// about a quarter of it; whole, one axis' sort was the dearest slice of a build: 29 us at
// N = 1 000 on the Xeon, against ~20 us slices), then the insertion pass for the endpoints
// that share a prefix.
double sortSome(State& s, double budget, double full) {
  NextArrays& n = s.next;
  while (n.stage == Stage::kSort && budget > 0.0) {
    const int axis = n.axis;
    std::vector<std::uint64_t>& keys = n.keys[axis];
    std::vector<std::uint32_t>& owners = n.owners[axis];
    const std::size_t size = s.owners[axis].size();
    const std::size_t last = size - 1;  // high sentinel
    if (n.cursor == 0) {
      owners.resize(size);
      keys.resize(size);
      std::memcpy(owners.data(), s.owners[axis].data(), size * sizeof(std::uint32_t));
      const std::uint64_t* e = n.ends[axis].data();
      keys[0] = kLowSentinel;
      keys[last] = kHighSentinel;
      for (std::size_t i = 1; i < last; ++i) keys[i] = e[owners[i]];
      // The jump's swaps, estimated as for everybody enlarged at once (the run's judgement
      // compares them with the scans and searches coasting cost; they also choose the sort).
      const std::int64_t estimate = estimateSwapsOf(keys);
      n.jump_swaps += estimate;
      // (Each endpoint moved at most once: past one swap per endpoint the swaps are places.)
      const double swaps = static_cast<double>(estimate);
      n.radix = kSortUnits * static_cast<double>(size) + kMoveUnits * std::min(swaps, static_cast<double>(size)) +
                    kSwapUnits * swaps >
                kRadixUnits * static_cast<double>(size);
      if (n.radix) beginRadixSort(keys, &n.radix_steps);
      n.cursor = 1;
      budget -= kCopyUnits * static_cast<double>(size);
      continue;
    }
    if (n.radix && n.radix_steps.next != RadixSteps::Step::kDone) {
      const double cost = radixStepUnits(n.radix_steps, size);
      if (waitForSlice(s, budget, full, cost)) return 0.0;
      radixSortStep(&keys, &owners, &s.sort, &n.radix_steps);
      budget -= cost;
      continue;
    }
    // Within the slice's budget (after a radix sort: the endpoints that share a prefix).
    std::int64_t done = 0;
    n.cursor = insertionSortFrom(&keys, &owners, n.cursor, static_cast<std::int64_t>(kHalfUnits * budget) + 1,
                                 &n.sort_swaps, kInsertionWork, &done);
    budget -= static_cast<double>(done) / kHalfUnits;
    if (n.cursor >= last) {
      n.cursor = 0;
      if (++n.axis == 3) {
        n.stage = Stage::kSweep;
        n.sweep_step = 0;
      }
    }
  }
  return budget;
}

double sweepSome(State& s, double budget, double full) {
  NextArrays& n = s.next;
  // Its start, in two steps that are not cut: the plan (the widths: a pass over every proxy)
  // and, when it sweeps in slabs, the slab lists (two passes more). Together they were a
  // build's dearest slice after the sort's (33 us at N = 1 000 on the Xeon).
  const double live = static_cast<double>(s.live_count);
  if (n.sweep_step == 0) {
    if (waitForSlice(s, budget, full, kPlanSweepUnits * live)) return 0.0;
    n.found.clear();
    exchange(s);
    const bool bins = planSweep(s, s.sweep_axis, s.plain_tests, &n.sweep);
    exchange(s);
    n.sweep_step = bins ? 1 : 2;
    budget -= kPlanSweepUnits * live;
    if (budget <= 0.0) return 0.0;
  }
  if (n.sweep_step == 1) {
    if (waitForSlice(s, budget, full, kBinSweepUnits * live)) return 0.0;
    exchange(s);
    binSweep(s, &n.sweep);
    exchange(s);
    n.sweep_step = 2;
    budget -= kBinSweepUnits * live;
    if (budget <= 0.0) return 0.0;
  }
  const double per_endpoint =
      kSweepUnits + kListUnits * static_cast<double>(s.cands.size()) / std::max(1.0, 2.0 * live);
  const std::size_t endpoints = static_cast<std::size_t>(budget / per_endpoint) + 1;
  exchange(s);
  s.filling_next = true;
  const bool done = sweepOn(s, &n.sweep, endpoints);
  s.filling_next = false;
  exchange(s);
  if (done) {
    n.stage = Stage::kTable;
    n.cursor = 0;
    n.counted = false;
  }
  return 0.0;
}

// The table of the next candidates: those whose given bounds overlap now first, then the
// others, each part in the order of its pairs' first proxy along the sweep axis. The scan of
// every update (reportTouching) keeps a candidate when it touches: in the sweep's order that
// branch goes either way at random (a third touch at +-5 % jitter) and the scan took 1.9 times
// as long (97 against 51 us, N = 10 000), in this order it is predicted (bench/results/NOTES.md
// section 21). A counting sort (the places counted, then the pairs placed: each a step that is
// not cut; together 27 us at N = 1 000 on the Xeon, a build's dearest slice but the sort's),
// then the insertions, a slice at a time.
double tableSome(State& s, double budget, double full) {
  NextArrays& n = s.next;
  const std::size_t slots = s.info.size();
  std::vector<std::uint32_t>& start = n.first_of;
  // Either step's price: a pair counted or placed, and a pass over the slots.
  auto stepCost = [&n, slots](double per_pair) {
    return per_pair * static_cast<double>(n.found.size()) + kRankUnits * static_cast<double>(slots);
  };
  if (n.cursor == 0 && !n.counted) {
    const double cost = stepCost(kCountPlacesUnits);
    if (waitForSlice(s, budget, full, cost)) return 0.0;
    // Each proxy's rank along the sweep axis (its lower endpoint's place).
    std::vector<std::uint32_t>& rank = n.rank;
    rank.resize(slots);
    {
      const std::vector<std::uint32_t>& owners = n.owners[s.sweep_axis];
      std::uint32_t r = 0;
      for (std::size_t i = 1, last = owners.size() - 1; i < last; ++i) {
        if ((owners[i] & 1u) == 0u) rank[owners[i] >> 1] = r++;
      }
    }
    // Each pair's place key, kept for the placing (the given bounds may move before it).
    const std::uint32_t others = static_cast<std::uint32_t>(slots);
    n.order_of.resize(n.found.size());
    start.assign(2 * slots + 1, 0);
    for (std::size_t i = 0, found = n.found.size(); i < found; ++i) {
      const BroadPair& c = n.found[i];
      const std::uint32_t r = std::min(rank[static_cast<std::size_t>(c.proxy_a)],
                                       rank[static_cast<std::size_t>(c.proxy_b)]);
      const std::uint32_t key = s.touching(c.proxy_a, c.proxy_b) ? r : others + r;
      n.order_of[i] = key;
      ++start[key + 1];
    }
    n.counted = true;
    budget -= cost;
    if (budget <= 0.0) return 0.0;
  }
  if (n.cursor == 0) {
    const double cost = stepCost(kPlaceUnits);
    if (waitForSlice(s, budget, full, cost)) return 0.0;
    for (std::size_t p = 0; p < 2 * slots; ++p) start[p + 1] += start[p];
    n.ordered.resize(n.found.size());
    for (std::size_t i = 0, found = n.found.size(); i < found; ++i) n.ordered[start[n.order_of[i]]++] = n.found[i];
    n.cands.clear();
    if (n.cands.capacity() < n.ordered.size()) n.cands.reserve(2 * n.ordered.size());
    n.flags_tracked = true;
    n.counted = false;
    n.cursor = 1;
    budget -= cost;
  }
  const std::size_t total = n.ordered.size();
  std::size_t i = n.cursor - 1;
  for (; i < total && budget > 0.0; ++i) {
    const BroadPair& c = n.ordered[i];
    // Whether its given bounds overlap now: this update's report keeps it from here on.
    n.cands.insert(c.proxy_a, c.proxy_b, nullptr)->touching = s.touching(c.proxy_a, c.proxy_b) ? 1u : 0u;
    budget -= CoastPolicy::kFoundWork;
  }
  n.cursor = i + 1;
  if (i >= total) n.stage = Stage::kReady;
  return budget;
}

// Goes on with the build by `budget` work units, stage after stage.
void runStages(State& s, double budget) {
  NextArrays& n = s.next;
  while (budget > 0.0 && n.stage != Stage::kReady) {
    switch (n.stage) {
      case Stage::kEnlarge:
        budget = enlargeSome(s, budget);
        break;
      case Stage::kSort:
        budget = sortSome(s, budget, n.budget);
        break;
      case Stage::kSweep:
        budget = sweepSome(s, budget, n.budget);
        break;
      case Stage::kTable:
        budget = tableSome(s, budget, n.budget);
        break;
      case Stage::kIdle:
      case Stage::kReady:
        budget = 0.0;
        break;
    }
  }
}

}  // namespace

void trackNextFlags(State& s) {
  NextArrays& n = s.next;
  if (!n.flags_tracked || (n.stage != Stage::kTable && n.stage != Stage::kReady)) return;
  // (Pairs not put in the table yet get theirs when they are.)
  for (const BroadPair& c : *s.began_out) {
    if (BroadPair* pair = n.cands.find(c.proxy_a, c.proxy_b)) pair->touching = 1;
  }
  for (const BroadPair& c : *s.ended_out) {
    if (BroadPair* pair = n.cands.find(c.proxy_a, c.proxy_b)) pair->touching = 0;
  }
}

void NextArrays::reserve(std::size_t slots) {
  reserveWritten(&first_of, 2 * slots + 1);
  reserveWritten(&rank, slots);
  for (int axis = 0; axis < 3; ++axis) {
    reserveWritten(&ends[axis], 2 * slots);
    reserveWritten(&keys[axis], 2 * slots + 2);
    reserveWritten(&owners[axis], 2 * slots + 2);
  }
}

void advanceNext(State& s) {
  NextArrays& n = s.next;
  if (n.stage == Stage::kIdle) {
    if (s.config.spread_updates <= 0 || s.live_count == 0 || s.anyStale() ||
        n.abandoned_run == s.coast.lastEnlargement() ||
        !s.coast.nextDue(s.updates, s.coast.nextSlices(static_cast<std::uint32_t>(s.config.spread_updates)))) {
      return;
    }
    start(s);
  }
  s.stats.building_next = n.stage != Stage::kReady;
  runStages(s, n.budget);
}

bool finishNext(State& s) {
  NextArrays& n = s.next;
  if (n.stage == Stage::kReady) return true;
  if (n.stage == Stage::kIdle || n.stage == Stage::kEnlarge) return false;
  // (A budget no stage reaches: each then runs to its end without waiting for a slice.) Its
  // table's flags then say this update's overlaps, not the last update's.
  runStages(s, 1e15);
  n.flags_tracked = false;
  s.stats.finished_next = true;
  return n.stage == Stage::kReady;
}

void abandonNext(State& s) {
  // (A build abandoned for insertions or removals is not started again in the same run: in a
  // scene whose tracks come and go every few updates each new one would be abandoned too.)
  if (s.next.stage != Stage::kIdle) s.next.abandoned_run = s.coast.lastEnlargement();
  s.next.stage = Stage::kIdle;
}

bool nextReady(const State& s) { return s.next.stage == Stage::kReady; }

bool swapInNext(State& s, bool run_over) {
  NextArrays& n = s.next;
  // The table swapped out keeps whether each pair touched at the last update (the report
  // diffs against it).
  validateFlags(s);
  n.prev_exact = s.pairs_out == &s.exact;
  exchange(s);
  n.stage = Stage::kIdle;
  n.swapped = true;
  s.stats.swapped_next = true;
  // The arrays are in the order of these keys: remember them for the pair events of later
  // re-sorts.
  for (int axis = 1; axis < 3; ++axis) {
    s.prev_ends[axis].resize(s.ends[axis].size());
    std::memcpy(s.prev_ends[axis].data(), s.ends[axis].data(), s.ends[axis].size() * sizeof(std::uint64_t));
  }
  // Who is outside its next bounds now (its motion outran the lead since its slice)? The
  // escapers listed this update were measured against the bounds swapped out.
  for (ProxyId id : s.escapers) s.info[static_cast<std::size_t>(id)].escaped = false;
  s.escapers.clear();
  for (std::size_t p = 0, slots = s.info.size(); p < slots; ++p) {
    ProxyInfo& info = s.info[p];
    if (info.state != ProxyState::kLive) continue;
    bool equal = false;
    const bool inside = insideEnlarged(s, static_cast<ProxyId>(p), &equal);
    s.setFat(info, !equal);
    if (!inside) {
      info.escaped = true;
      s.escapers.push_back(static_cast<ProxyId>(p));
    }
  }
  s.stats.escaped = static_cast<int>(s.escapers.size());
  bool resorted = false;
  CoastPolicy::Resort r;
  r.rebuilt = true;
  // What re-sorting the given bounds would have cost without coasting: the swaps between the
  // current order and the next bounds' (the motion of the run), estimated as for a jump.
  r.estimated_swaps = n.jump_swaps;
  if (!s.escapers.empty()) {
    const std::size_t few = 1 + static_cast<std::size_t>(s.live_count) / 32;
    if (s.escapers.size() <= few) {
      const std::size_t swaps = moveEscapers(s);
      s.coast.movedFew(s.escapers.size(), swaps);
    } else {
      // Many outran their leads (the motion changed during the build): everybody at once.
      s.last_estimate = -1;
      enlargeAll(s, s.coast.lead());
      s.stats.enlarged_all = true;
      resortAll(s);
      n.flags_tracked = false;  // (a rebuild makes a table of its own)
      r.swaps = s.stats.swaps;
      r.rebuilt = s.stats.rebuilt;
      r.estimated_swaps = std::max(n.jump_swaps, s.last_estimate);
      resorted = true;
    }
  }
  r.live = s.live_count;
  r.candidates = static_cast<std::size_t>(s.cands.size());
  r.sweep_tests = s.sweep_tests;
  r.pairs = s.exact.size();
  s.coast.enlargedAll(s.updates, r, run_over ? CoastPolicy::End::kSpreadAtEnd : CoastPolicy::End::kSpreadEarly);
  return resorted;
}

void reportSwapped(State& s) {
  NextArrays& n = s.next;
  n.swapped = false;
  // The last update's pairs: its exact list, or (no enlarged bounds then) every candidate of
  // the table swapped out. Those whose given bounds no longer overlap ended. A pair whose
  // given bounds overlap is a candidate of the new table (every proxy is inside its bounds
  // now), so the new table's candidates give pairs() and, looked up in the old table, what
  // began.
  const BasicPairTable<BroadPair>& old = n.cands;
  const std::vector<BroadPair>& prev = n.prev_exact ? s.exact : old.pairs();
  s.began.clear();
  s.ended.clear();
  for (const BroadPair& c : prev) {
    if (!s.touching(c.proxy_a, c.proxy_b)) s.ended.push_back(c);
  }
  s.exact.clear();
  // Each candidate's flag says whether it touched at the last update (NextArrays::
  // flags_tracked), but for those the escapers moved alone after the swap put in: theirs from
  // the old table. Otherwise every touching candidate is looked up there (at N = 10 000 that
  // lookup was most of a swap's cost).
  const bool tracked = n.flags_tracked;
  n.flags_tracked = false;
  if (tracked) {
    for (const BroadPair& c : s.cand_began) {
      Candidate* pair = s.cands.find(c.proxy_a, c.proxy_b);
      if (pair == nullptr) continue;
      const BroadPair* was = old.find(c.proxy_a, c.proxy_b);
      pair->touching = was != nullptr && was->touching != 0 ? 1u : 0u;
    }
  }
  std::vector<Candidate>& dense = s.cands.mutablePairs();
  for (Candidate& c : dense) {
    const std::uint32_t now = s.touching(c.proxy_a, c.proxy_b) ? 1u : 0u;
    const std::uint32_t before = c.touching;
    c.touching = now;
    if (now == 0) continue;
    s.exact.push_back(c);
    if (tracked) {
      if (before == 0) s.began.push_back(c);
    } else {
      const BroadPair* was = old.find(c.proxy_a, c.proxy_b);
      if (was == nullptr || was->touching == 0) s.began.push_back(c);
    }
  }
  s.pairs_out = &s.exact;
  s.began_out = &s.began;
  s.ended_out = &s.ended;
  s.flags_valid = true;
  s.tight_last = s.fat_count == 0;
  s.stats.candidates = static_cast<int>(dense.size());
  s.coast.scanned(dense.size());
}

}  // namespace sap
}  // namespace workspace_proximity
