#pragma once
/// SweepAndPrune's state (private to the core): flat arrays addressed by proxy id, shared by
/// the jobs, each in its own file pair:
///   sweep_and_prune_keys         key encoding and the full sort of an endpoint array
///   sweep_and_prune_incremental  insertion sort with pair events; relocation of a few proxies
///   sweep_and_prune_rebuild      rebuild: sort from scratch and the sweep kernel
///   sweep_and_prune_insert       batched insertion of new proxies
///   sweep_and_prune_coasting     enlarged bounds and the pairs of given bounds among them
///   sweep_and_prune_coast_policy coasting's decisions and cost model (a value class)
///   sweep_and_prune_next         a run's end spread over several updates (the next arrays)
/// sweep_and_prune.cpp holds the public class: it runs update() through these steps.

#include <cstdint>
#include <vector>

#include "sweep_and_prune_coast_policy.hpp"
#include "sweep_and_prune_keys.hpp"
#include "sweep_and_prune_next.hpp"
#include "sweep_and_prune_rebuild.hpp"
#include "workspace_proximity/pair_table.hpp"
#include "workspace_proximity/sweep_and_prune.hpp"

namespace workspace_proximity {
namespace sap {

using ProxyId = SweepAndPrune::ProxyId;

// A pair of enlarged bounds (a candidate) is a BroadPair; `touching`: its given bounds
// overlapped at the end of the last update (it is then one of pairs()). Not kept while no
// proxy is enlarged (the candidates are the pairs then): see State::flags_valid.
using Candidate = BroadPair;

enum class ProxyState : std::uint8_t { kFree, kPendingInsert, kLive };

struct ProxyInfo {
  std::int32_t next_free;
  ProxyState state;
  bool pending_remove;
  bool is_new;   // inserted in the current update
  bool escaped;  // listed in State::escapers this update
  bool fat;      // its enlarged bounds differ from its given ones
  std::uint32_t enlarged_at;  // update count at its last enlargement
};

// What enlarge() learnt of a proxy's motion: its centre's displacement per update averaged
// over its last `memory` updates (m, per axis), and a bound on the part of its displacements
// that neither rest nor that drift explained (tracker jitter, m), forgotten slowly.
struct ProxyMotion {
  float drift[3];
  float jitter;
  float memory;
};

struct State {
  explicit State(const SweepAndPruneConfig& config);
  State(const State&) = delete;  // the output pointers point into it
  State& operator=(const State&) = delete;

  /// Grows everything sized by the number of proxy slots, together, so that updates never
  /// allocate while the slot count stays put (destroyed ids are reused).
  void reserveSlots(std::size_t slots);

  // Enlarged keys (what the arrays are sorted by) per axis, indexed by endpoint code
  // o = 2 proxy + is_upper: ends[axis][o]. True when a's and b's overlap on every axis.
  bool overlaps(std::int32_t a, std::int32_t b) const {
    const std::size_t x = 2 * static_cast<std::size_t>(a), y = 2 * static_cast<std::size_t>(b);
    const std::uint64_t* e0 = ends[0].data();
    const std::uint64_t* e1 = ends[1].data();
    const std::uint64_t* e2 = ends[2].data();
    return (e0[x] < e0[y + 1]) & (e0[y] < e0[x + 1]) & (e1[x] < e1[y + 1]) & (e1[y] < e1[x + 1]) &
           (e2[x] < e2[y + 1]) & (e2[y] < e2[x + 1]);
  }
  // The same test, the two other axes first: a begin event already overlaps on `axis`, and
  // most candidates are apart on another axis.
  bool overlapsAcross(std::int32_t a, std::int32_t b, int axis) const {
    const std::size_t x = 2 * static_cast<std::size_t>(a), y = 2 * static_cast<std::size_t>(b);
    const std::uint64_t* e1 = ends[axis == 0 ? 1 : 0].data();
    const std::uint64_t* e2 = ends[axis == 2 ? 1 : 2].data();
    const std::uint64_t* e0 = ends[axis].data();
    return e1[x] < e1[y + 1] && e1[y] < e1[x + 1] && e2[x] < e2[y + 1] && e2[y] < e2[x + 1] &&
           e0[x] < e0[y + 1] && e0[y] < e0[x + 1];
  }
  // False when the pair cannot be in the table during the sort of `axis`: a pair still there
  // overlaps on every other axis, in the new keys on axes already sorted and in the previous
  // update's keys on axes not sorted yet.
  bool mayBePaired(std::int32_t a, std::int32_t b, int axis) const {
    const std::size_t x = 2 * static_cast<std::size_t>(a), y = 2 * static_cast<std::size_t>(b);
    for (int other = 0; other < 3; ++other) {
      if (other == axis) continue;
      const std::uint64_t* e = other < axis ? ends[other].data() : prev_ends[other].data();
      if (!(e[x] < e[y + 1] && e[y] < e[x + 1])) return false;
    }
    return true;
  }
  // True when the given bounds (tight) of a and b overlap.
  bool touching(std::int32_t a, std::int32_t b) const {
    const std::uint64_t* x = tight.data() + 6 * static_cast<std::size_t>(a);
    const std::uint64_t* y = tight.data() + 6 * static_cast<std::size_t>(b);
    return (x[0] < y[1]) & (y[0] < x[1]) & (x[2] < y[3]) & (y[2] < x[3]) & (x[4] < y[5]) &
           (y[4] < x[5]);
  }
  void setFat(ProxyInfo& p, bool is_fat) {
    fat_count += static_cast<int>(is_fat) - static_cast<int>(p.fat);
    p.fat = is_fat;
  }
  // A candidate begins (listed once) or ends. Out of line (sweep_and_prune.cpp): the loops
  // that call them stay small.
  void beginPair(std::int32_t a, std::int32_t b);
  void endPair(std::int32_t a, std::int32_t b);
  bool anyStale() const { return stale[0] | stale[1] | stale[2]; }

  SweepAndPruneConfig config;
  std::vector<std::uint64_t> ends[3];  // 2 keys per proxy slot and axis
  // Keys as of the last update (the order of the endpoint arrays) on axes 1 and 2.
  std::vector<std::uint64_t> prev_ends[3];
  std::vector<ProxyInfo> info;
  std::int32_t free_list = -1;
  std::size_t reserved_slots = 0;
  int live_count = 0;
  double max_width[3] = {0.0, 0.0, 0.0};  // widest bound per axis since the last rebuild, m

  // Endpoint arrays per axis, sorted by key, with a sentinel at each end: key[0] = 0,
  // key[last] = ~0. owner = proxy << 1 | is_upper.
  std::vector<std::uint64_t> keys[3];
  std::vector<std::uint32_t> owners[3];

  std::vector<ProxyId> pending_insert;
  std::vector<ProxyId> pending_remove;

  // Candidates (pairs of enlarged bounds) and their changes in this update (began, ended).
  BasicPairTable<Candidate> cands;
  std::vector<Candidate> cand_began;
  std::vector<Candidate> cand_ended;
  // What callers see: the touching candidates, and their changes; or, while no proxy is
  // enlarged, the candidates and theirs.
  std::vector<BroadPair> exact;
  std::vector<BroadPair> began;
  std::vector<BroadPair> ended;
  const std::vector<BroadPair>* pairs_out = &exact;
  const std::vector<BroadPair>* began_out = &began;
  const std::vector<BroadPair>* ended_out = &ended;
  int fat_count = 0;         // live proxies whose enlarged bounds differ from the given ones
  bool flags_valid = true;   // every candidate's `touching` is up to date
  bool tight_last = true;    // no proxy was enlarged at the end of the last update

  // Coasting. Given bounds as keys, six per slot (lower, upper per axis): tight; the same at
  // the proxy's last enlargement: base (its displacement since then sizes the next lead).
  std::vector<std::uint64_t> tight;
  std::vector<std::uint64_t> base;
  std::vector<ProxyMotion> motion;          // by slot
  std::vector<ProxyId> escapers;            // proxies that left their enlarged bounds
  std::vector<std::uint64_t> escaper_old;   // their previous enlarged keys, six each
  std::uint32_t updates = 0;                // update() calls so far
  CoastPolicy coast;
  bool moved = false;                       // not coasting: a live proxy moved
  std::int64_t last_estimate = -1;          // swaps estimated by the last re-sort after a jump
  std::uint32_t recip_of = 1;               // enlarge(): 1 / recip_of = recip
  double recip = 1.0;

  // Rebuild heuristics.
  bool last_rebuilt = false;
  double swap_scale = 3.0;      // all axes' estimated swaps / the sweep axis' (last estimate)
  // Axes a streak rebuild left out of order: no pair events may come from them until a full
  // rebuild sorts them (insertion sort from a stale order misses pairs that separated and
  // re-joined, or the reverse, since it was sorted); nothing looks up keys in them either.
  bool stale[3] = {false, false, false};
  std::int64_t sweep_tests = 0;       // overlap tests of the last full sweep
  std::int64_t plain_tests = 0;       // of a plain sweep along the axis when last chosen
  int sweep_axis = 0;                 // axis of the rebuild sweeps
  unsigned rebuilds_since_choice = 0;
  double mean_width[3] = {0.0, 0.0, 0.0};  // mean bound width per axis when last measured, m
  bool widths_due = true;                  // the next rebuild's slab sweep re-measures them
  // Coasting off, the choice between a rebuild streak and insertion sort checked by their
  // measured costs (SweepAndPruneConfig::measure_streaks; resort() in sweep_and_prune.cpp).
  double insertion_ns = -1.0;        // an update whose insertion sort sufficed (average; -1: none)
  double streak_ns = -1.0;           // a rebuild that followed a rebuild (average; -1: none)
  std::uint32_t insertion_at = 0;    // update of the last insertion measurement
  std::uint32_t streak_length = 0;   // rebuilds in a row, the streak under way
  bool probe_insertion = false;      // leave the streak to measure insertion sort

  // A run's end spread over several updates: the next arrays, built beside these.
  NextArrays next;
  bool filling_next = false;  // the sweep runs on the next arrays: found pairs only go in

  // Scratch, kept between updates so steady-state updates allocate nothing.
  SortScratch sort;
  std::vector<std::uint32_t> breaks;  // insertion sort: positions where the order breaks
  SweepScratch sweep;
  SweepAndPruneStats stats;
  std::uint32_t epoch = 0;
};

}  // namespace sap
}  // namespace workspace_proximity
