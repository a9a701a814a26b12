#pragma once
/// Incremental sweep-and-prune on three axes (insertion sort of persistent endpoint arrays).
///
/// Each proxy's bounds are stored as three pairs of 64-bit sortable keys: the double bound is
/// mapped to an order-preserving unsigned integer, and the low bit is forced to 0 for lower and
/// 1 for upper endpoints. Lower keys are therefore always below upper keys at equal
/// coordinates, so touching boxes overlap; the tag moves a bound outward by at most one double
/// ulp, so the integer test is never less conservative than the double one and differs from it
/// only for boxes less than one ulp apart.
///
/// update() re-sorts every axis by insertion sort, reading each endpoint's current key from the
/// proxy as it goes. A swap of a lower endpoint of A past an upper endpoint of B starts an
/// overlap on that axis: the pair is added when the two boxes overlap on all three axes. The
/// opposite swap ends an overlap: the pair is removed. Pairs are kept in an open-addressing
/// table; update() reports those that began and ended. When insertion sort would cost more than
/// a rebuild (too many swaps, or, right after a rebuild, as many as an estimate from the new
/// keys predicts), it rebuilds instead: radix sort of every axis, a sweep along the axis with
/// the fewest overlapping intervals (in slabs of a second axis when there are many bodies), and
/// a diff against the previous pair set. A rebuild that follows a rebuild sorts only the sweep
/// axis and leaves the other two stale (out of order); the first update that would re-sort
/// incrementally with a stale axis rebuilds in full instead. Steady-state updates allocate
/// nothing: scratch space grows with the number of proxy slots, and the pair table keeps a
/// quarter of headroom.
///
/// Coasting (enlarged bounds, a neighbour list in molecular dynamics' terms): the arrays hold
/// each proxy's bounds enlarged ahead of its motion, so the pairs they give are candidates, and
/// pairs() are the candidates whose given bounds overlap, tested every update (one scan of the
/// candidates; none while no proxy is enlarged). An update in which no proxy left its enlarged
/// bounds sorts nothing. When up to 1 + n / 32 proxies left them, only their endpoints move in
/// the arrays; when more did, or after a run of 4 coast_updates updates, every proxy is
/// enlarged again at once and the arrays are re-sorted or rebuilt as above, so a steady motion
/// costs one re-sort every few updates instead of one per update. The lead ahead of a side
/// that moved outward is SweepAndPruneConfig::coast_updates updates of that side's own
/// displacement per update since its last enlargement, capped at max_lead_fraction of the
/// box's largest extent; a side that moved inward gets one update's, a resting side none. Each
/// time everybody is enlarged again, the run of updates since the last time is judged with a
/// cost model (work units counted from the candidates scanned, swaps, searches and rebuilds)
/// against what the same updates would have cost without coasting (estimated from the swaps of
/// the jump); when coasting cost more (large motion, dense scenes), it switches itself off for
/// 64 updates, twice as long after each failure in a row (up to 4 096), then tries again
/// (unless the proxies' last displacements show that more than a quarter of them would leave
/// their enlarged bounds within 4 updates: the retry is then put off by 64 updates, without
/// enlarging anybody); the first three runs after it starts are not judged (and last coast_updates updates each, not 4
/// coast_updates, so that the leads are measured again soon). Tracker jitter: each proxy also keeps a
/// bound on the displacement that neither rest nor its drift (averaged over about 16 updates)
/// explains (learnt only when more than one axis shows it: a one-axis residual is a bounce or a
/// change of speed, not noise), forgotten slowly; every side gets three times that bound on top
/// of its lead, and
/// the lead is sized from the displacement beyond it (or from the averaged drift), so a box
/// reported a little off around where it was stays inside its bounds and costs no sort work.
/// The long lead: while judged runs last their longest (nobody leaves: jitter around rest, a
/// slow drift), a lead of at most 8 doubles and runs last up to 6 coast_updates, their ends
/// spread over up to twice spread_updates; the first judged run shorter than 4 coast_updates
/// brings the configured lead back (SweepAndPruneStats::lead says which is in use). Each run's
/// end costs about a re-sort of everybody: under jitter they came every 28-29 updates, at
/// their longest. The steady lead (SweepAndPruneConfig::steady_lead): when a judged run ends
/// before 16 updates because its proxies left their bounds together (steady motion: a lead of
/// 8 ends runs every 7-9 updates), the enlargement that ends it takes three times the lead
/// (when that is at most 24), so that runs last long enough for their ends to be spread. It is
/// refused (and blocked) when more than a quarter of the proxies would pass bounds that long,
/// capped at max_lead_fraction, within 16 updates; a run at it shorter than 16 updates, costing
/// more per update than the last run at the configured lead, or costing more than not coasting
/// brings the configured lead back and blocks the steady one for 8 judged runs (twice as many
/// after each such run in a row); a run at it that lasts 4 coast_updates brings it back
/// unblocked.
///
/// Long runs (at least 16 updates: tracker jitter around rest or a slow drift, where runs last
/// their longest) end without a dear update: the next arrays are built over
/// the updates before the run's expected end, a slice per update (each proxy's next enlarged
/// bounds, with its lead grown by the updates left until the swap and a side moving inward
/// starting where it will be then; the three endpoint arrays, sorted from the current order by
/// insertion sort or radix sort; one sweep for their candidates, put in a table of their own
/// with the pairs touching then first), beside the current arrays, which answer every update
/// meanwhile. Then the two trade places; the proxies outside their next bounds by then move
/// alone (or, when more than a few are, everybody is enlarged at once), and that update's
/// began and ended pairs come from the given bounds against the last update's pairs. An
/// insertion, a removal, or everybody enlarged at once abandons the build (the run then ends
/// at once). Shorter runs (steady motion at a lead of 8: everybody leaves together every 7-9
/// updates, until the steady lead lengthens them) end at once: a build squeezed into them
/// costs more than it spreads. SweepAndPruneConfig::
/// spread_updates bounds the slices (0: every run ends at once).
///
/// The state is private: flat arrays by proxy id behind one pointer, and one file pair per job
/// in src/core/ (sweep_and_prune_state.hpp lists them).

#include <cstdint>
#include <memory>
#include <vector>

#include "workspace_proximity/aabb.hpp"

namespace workspace_proximity {

namespace sap {
struct State;  // src/core/sweep_and_prune_state.hpp
}  // namespace sap

struct SweepAndPruneConfig {
  int initial_proxy_capacity = 256;   ///< proxies preallocated
  int initial_pair_capacity = 1024;   ///< overlapping pairs preallocated
  /// Insertion sort gives up and rebuilds once the swaps of one update (all axes) exceed
  /// rebuild_factor * (3 n + t / 8), n = endpoints per axis, t = overlap tests of the last
  /// full sweep: an estimate of what a rebuild costs, in swaps. After a rebuild, the next
  /// update rebuilds again (sorting only the sweep axis) while the swaps estimated from the new
  /// keys exceed rebuild_factor * (2 n + t / 8). 0 rebuilds on almost any motion; a huge value
  /// never rebuilds.
  double rebuild_factor = 1.0;
  /// Coasting: the lead ahead of a moving side, in updates of its own displacement per update
  /// (see the class comment). 0 turns coasting off: the arrays then hold the given bounds.
  double coast_updates = 8.0;
  /// Cap of that lead, as a fraction of the proxy's largest extent.
  double max_lead_fraction = 0.5;
  /// A coasting run's end spread over up to this many updates (the next arrays: each proxy's
  /// next enlarged bounds, the sorted endpoint arrays and their candidates, built a slice per
  /// update beside the current ones before the run is expected to end, then swapped in; fewer
  /// updates when runs are short: under half of a run's; at the long lead twice as many, under
  /// two thirds of its run's); 0 enlarges everybody and re-sorts in one update, as the run ends.
  int spread_updates = 16;
  /// The steady lead: when coasting's runs end before 16 updates because the proxies leave
  /// their bounds together (steady motion), the lead triples (when that makes at most 24
  /// updates), so that runs last long enough for their ends to be spread (spread_updates).
  /// Refused when the motion would pass the lead's cap (max_lead_fraction) within 16 updates;
  /// back to coast_updates when a run at it is shorter than 16 updates, costs more per update
  /// than a run at coast_updates did or more than not coasting, or lasts 4 coast_updates. The
  /// monitor's lead of 16 never takes it (its steady runs are long enough). Uniform 1 %,
  /// N = 1 000, one run beside it off: p99 / median 20x -> 4x, mean 27 % lower, median 47 %
  /// higher (bench/results/NOTES.md section 33). false: the lead is coast_updates (or the long
  /// lead under jitter) whatever the runs.
  bool steady_lead = true;
  /// Coasting off, a rebuild streak whose estimate says it beats insertion sort by less than
  /// the rebuild of all three axes it would take to leave it is checked against the measured
  /// costs of both (steady_clock around the re-sort: insertion sort is tried once in a while
  /// after 16 rebuilds in a row, and then preferred while it costs under 0.85 of a streak
  /// rebuild). The estimate prices neither pairs nor a rebuild's diff: with swept boxes of
  /// dense crowds a streak rebuild took 1.8-2.4 ms where insertion sort took 1.1 ms. The pairs
  /// are the same either way; false: the estimate alone decides (deterministic paths).
  bool measure_streaks = true;
};

/// Two proxies whose stored bounds overlap, with proxy_a < proxy_b.
struct BroadPair {
  std::int32_t proxy_a = -1;
  std::int32_t proxy_b = -1;
  /// The structure's own bookkeeping (the last rebuild that found the pair, whether the given
  /// bounds overlapped at the last update); means nothing to callers.
  std::uint32_t epoch = 0;
  std::uint32_t touching = 0;
};

/// Counters of the last update(), for benchmarks and diagnostics.
struct SweepAndPruneStats {
  std::int64_t swaps = 0;       ///< insertion-sort swaps over three axes
  bool rebuilt = false;         ///< fell back to a full sort-and-sweep
  int inserted = 0;             ///< proxies inserted (batched)
  int removed = 0;              ///< proxies removed (batched)
  int escaped = 0;              ///< proxies whose bounds left their enlarged bounds
  bool coasted = false;         ///< nothing was re-sorted (no proxy left its enlarged bounds)
  bool enlarged_all = false;    ///< every proxy was enlarged again (then re-sorted or rebuilt)
  int candidates = 0;           ///< pairs of enlarged bounds (pairs() is a subset)
  bool building_next = false;   ///< a slice of the next arrays was built (spread_updates)
  bool swapped_next = false;    ///< the next arrays were swapped in (a spread run's end)
  bool next_ready = false;      ///< the next arrays are built, waiting for their swap
  /// Coasting off: a rebuild streak was left for insertion sort, to measure it or because it
  /// measured cheaper (SweepAndPruneConfig::measure_streaks).
  bool left_streak = false;
  bool finished_next = false;   ///< the run ended first: the rest of the build was done at once
  /// The lead of enlargements after this update, in updates of each proxy's own displacement:
  /// coast_updates, twice that (a lead of at most 8) while coasting's runs last their longest
  /// (the long lead, see the class comment), 0 while coasting is off.
  double lead = 0.0;
};

class SweepAndPrune {
 public:
  using ProxyId = std::int32_t;

  /// Throws std::invalid_argument on a coast_updates or max_lead_fraction outside [0, 1e6], or
  /// a spread_updates outside [0, 1024].
  explicit SweepAndPrune(const SweepAndPruneConfig& config = SweepAndPruneConfig());
  ~SweepAndPrune();
  SweepAndPrune(SweepAndPrune&&) noexcept;
  SweepAndPrune& operator=(SweepAndPrune&&) noexcept;
  SweepAndPrune(const SweepAndPrune&) = delete;
  SweepAndPrune& operator=(const SweepAndPrune&) = delete;

  /// New proxy with the given bounds; it joins the structure (and its pairs are reported)
  /// at the next update(). Ids are small non-negative integers, reused after destroyProxy();
  /// callers map them to their own objects. Bounds must be valid(); throws otherwise.
  ProxyId createProxy(const Aabb& bounds);
  /// Remove a proxy; its pairs are reported as ended at the next update(). The id may be
  /// reused by a later createProxy().
  void destroyProxy(ProxyId proxy);
  /// New bounds for a live proxy; takes effect at the next update().
  void moveProxy(ProxyId proxy, const Aabb& bounds);

  /// Applies removals, moves and insertions; fills beganPairs() and endedPairs().
  void update();

  /// Every pair overlapping after the last update(), in no particular order.
  const std::vector<BroadPair>& pairs() const;
  /// Pairs that started overlapping in the last update(). With endedPairs() this is all a
  /// caller needs to keep its own per-pair state: pairs() after an update equals pairs()
  /// before it, minus endedPairs(), plus beganPairs() (the two never share a pair).
  const std::vector<BroadPair>& beganPairs() const;
  /// Pairs that stopped overlapping (or lost a proxy) in the last update(). They may name
  /// proxies destroyed in that update, whose ids a later createProxy() reuses.
  const std::vector<BroadPair>& endedPairs() const;
  /// True when (a, b), in either order, is one of pairs().
  bool hasPair(ProxyId a, ProxyId b) const;

  /// The bounds the structure tests with (the given ones, moved outward by at most one ulp).
  Aabb storedBounds(ProxyId proxy) const;
  /// The enlarged bounds the arrays hold for the proxy (they contain storedBounds()).
  Aabb enlargedBounds(ProxyId proxy) const;
  /// Every pair whose enlarged bounds overlap (closed intervals; pairs() is a subset), in no
  /// particular order: for diagnostics and tests.
  const std::vector<BroadPair>& candidatePairs() const;
  int proxyCount() const;
  const SweepAndPruneStats& stats() const;

 private:
  // Flat arrays by proxy id, shared by the jobs in src/core/sweep_and_prune_*.cpp.
  std::unique_ptr<sap::State> s_;
};

}  // namespace workspace_proximity
