#pragma once
/// SweepAndPrune's next arrays (private to the core): a coasting run's end spread over several
/// updates. Enlarging everybody and re-sorting at once made the dear cycles of the broad phase
/// (issue 26: ~165 us against an 11 us median at +-1 % jitter, N = 1 000). Instead, the
/// updates before the run's expected end build the next arrays beside the current ones, a
/// slice each: every proxy's next enlarged bounds (with the lead grown by the updates left
/// until the swap, so that they hold as long after it as bounds enlarged at the swap would),
/// the three endpoint arrays sorted, and one sweep for their candidates into a table of their
/// own. Until the swap the current arrays answer every update as before (escapers move alone
/// in them). The swap exchanges arrays and tables (no copy); the proxies outside their next
/// bounds by then move alone in the new arrays, and pairs(), beganPairs() and endedPairs()
/// come from the given bounds against the last update's pairs. Any insertion, removal or
/// re-sort of everybody in between abandons the build (the run then ends at once, as before).
/// Between slices the build keeps a radix sort's partial order in State::sort and a sweep's
/// slab lists in State::sweep: their other users (insertions, re-sorts of everybody) run only
/// after the build was abandoned, finished or swapped in.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "sweep_and_prune_keys.hpp"
#include "sweep_and_prune_rebuild.hpp"
#include "workspace_proximity/pair_table.hpp"
#include "workspace_proximity/sweep_and_prune.hpp"

namespace workspace_proximity {
namespace sap {

struct State;

/// Reserves `n` elements and writes them once, keeping the contents: the first build runs long
/// after its arrays were reserved, and each page it wrote first was a fault then (uniform 1 %,
/// N = 10 000: its first slices took 250 us more than the later builds' on the AMD EPYC VM,
/// 2 of the 150 timed updates' dearest). For the arrays only a build uses.
template <typename T>
void reserveWritten(std::vector<T>* v, std::size_t n) {
  v->reserve(n);
  const std::size_t size = v->size();
  if (size >= n) return;
  v->resize(n);
  v->resize(size);
}

struct NextArrays {
  enum class Stage : std::uint8_t {
    kIdle,     ///< nothing built
    kEnlarge,  ///< next enlarged bounds, slot after slot
    kSort,     ///< endpoint arrays, axis after axis (insertion sort from the current order)
    kSweep,    ///< the candidates of the next bounds, listed
    kTable,    ///< ordered (touching first) and put in their table
    kReady,    ///< waiting for the swap
  };
  Stage stage = Stage::kIdle;
  // Next enlarged keys by endpoint code, sorted endpoint arrays and candidates: the same
  // shapes as State::ends, keys, owners and cands, exchanged with them at the swap.
  std::vector<std::uint64_t> ends[3];
  std::vector<std::uint64_t> keys[3];
  std::vector<std::uint32_t> owners[3];
  BasicPairTable<BroadPair> cands;
  std::vector<BroadPair> found;         ///< kSweep: the candidates, in the sweep's order
  std::vector<BroadPair> ordered;       ///< kTable: the same, touching first, by first proxy
  std::vector<std::uint32_t> first_of;  ///< kTable: counting sort's starts
  std::vector<std::uint32_t> order_of;  ///< kTable: each found pair's place key, as counted
  std::vector<std::uint32_t> rank;      ///< kTable: each proxy's place along the sweep axis
  std::uint32_t started = 0;   ///< update that started the build
  std::uint32_t swap_at = 0;   ///< update that swaps it in (next bounds hold the lead past it)
  std::size_t cursor = 0;      ///< kEnlarge: next slot; kSort: next position; kTable: 1 + next pair
  int axis = 0;                ///< kSort: axis being sorted
  std::int64_t sort_swaps = 0; ///< kSort: swaps on every axis
  std::int64_t jump_swaps = 0; ///< kSort: those estimated from the keys, as for a jump
  bool radix = false;          ///< kSort: this axis is radix sorted (too many swaps estimated)
  RadixSteps radix_steps;      ///< kSort: where that radix sort is
  SweepCursor sweep;           ///< kSweep
  /// kSweep: 0 before its plan (planSweep), 1 before its slab lists (binSweep), 2 sweeping.
  int sweep_step = 0;
  bool counted = false;        ///< kTable: the found pairs' places counted, not yet placed
  double budget = 0.0;         ///< work per update (units of CoastPolicy, ~ns)
  bool swapped = false;        ///< swapped in by this update: its report diffs the pairs
  /// The run (CoastPolicy::lastEnlargement) in which a build was last abandoned; none is
  /// started again in that run.
  std::uint32_t abandoned_run = ~std::uint32_t{0};
  bool prev_exact = false;     ///< at the swap: the last update's pairs() were State::exact
  /// Each candidate's `touching` in the table of the build says whether its given bounds
  /// overlapped at the last update: set when it is put in the table, kept by every later
  /// update's report (trackNextFlags), so that the swap's report needs no lookup in the old
  /// table. False when the table was filled in the update of the swap (finishNext) or the
  /// swap re-sorted everybody.
  bool flags_tracked = false;

  void reserve(std::size_t slots);
};

/// Starts a build when coasting's policy says it is due, or goes on with the one under way, by
/// about a slice of its work. Called once per update, after the current arrays are settled.
void advanceNext(State& s);
/// The run under way ended (its proxies left their bounds, or its longest) before the build was
/// swapped in: finishes it now when it is past its enlargements (the rest costs less than
/// everybody enlarged at once, and the next bounds lead past the planned swap, so that the
/// proxies are inside them); returns true when it is ready to be swapped in.
bool finishNext(State& s);
/// Abandons the build (insertions, removals, everybody enlarged at once, coasting off).
void abandonNext(State& s);
/// True when the next arrays are built and may be swapped in now.
bool nextReady(const State& s);
/// Swaps them in and moves the proxies outside their next bounds alone (or, when more than a
/// few are, enlarges everybody at once and re-sorts); returns true when everybody was
/// re-sorted (the new arrays' order is then to be remembered as after any re-sort).
/// `run_over`: the run under way ended in this update (many left their bounds, or its longest).
bool swapInNext(State& s, bool run_over);
/// pairs(), beganPairs() and endedPairs() of an update that swapped the next arrays in.
void reportSwapped(State& s);
/// After an update's report: the pairs that began or ended touching in it get their flag in the
/// build's table too (NextArrays::flags_tracked).
void trackNextFlags(State& s);
/// Everybody enlarged at once: re-sorts every axis as a jump (sweep_and_prune.cpp).
void resortAll(State& s);

}  // namespace sap
}  // namespace workspace_proximity
