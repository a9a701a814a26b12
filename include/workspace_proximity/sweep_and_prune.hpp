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
/// 64 updates, twice as long after each failure in a row (up to 4 096), then tries again.

#include <cstdint>
#include <vector>

#include "workspace_proximity/aabb.hpp"
#include "workspace_proximity/pair_table.hpp"

namespace workspace_proximity {

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
};

class SweepAndPrune {
 public:
  using ProxyId = std::int32_t;

  explicit SweepAndPrune(const SweepAndPruneConfig& config = SweepAndPruneConfig());

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
  const std::vector<BroadPair>& pairs() const { return *pairs_out_; }
  /// Pairs that started overlapping in the last update(). With endedPairs() this is all a
  /// caller needs to keep its own per-pair state: pairs() after an update equals pairs()
  /// before it, minus endedPairs(), plus beganPairs() (the two never share a pair).
  const std::vector<BroadPair>& beganPairs() const { return *began_out_; }
  /// Pairs that stopped overlapping (or lost a proxy) in the last update(). They may name
  /// proxies destroyed in that update, whose ids a later createProxy() reuses.
  const std::vector<BroadPair>& endedPairs() const { return *ended_out_; }
  /// True when (a, b), in either order, is one of pairs().
  bool hasPair(ProxyId a, ProxyId b) const {
    const BroadPair* c = cands_.find(a, b);
    return c != nullptr && (fat_count_ == 0 || c->touching != 0);
  }

  /// The bounds the structure tests with (the given ones, moved outward by at most one ulp).
  Aabb storedBounds(ProxyId proxy) const;
  /// The enlarged bounds the arrays hold for the proxy (they contain storedBounds()).
  Aabb enlargedBounds(ProxyId proxy) const;
  /// Every pair whose enlarged bounds overlap (closed intervals; pairs() is a subset), in no
  /// particular order: for diagnostics and tests.
  const std::vector<BroadPair>& candidatePairs() const { return cands_.pairs(); }
  int proxyCount() const { return live_count_; }
  const SweepAndPruneStats& stats() const { return stats_; }

 private:
  enum class ProxyState : std::uint8_t { kFree, kPendingInsert, kLive };

  struct ProxyInfo {
    std::int32_t next_free;
    ProxyState state;
    bool pending_remove;
    bool is_new;  // inserted in the current update
    bool escaped;  // listed in escapers_ this update
    bool fat;      // its enlarged bounds differ from its given ones
    std::uint32_t enlarged_at;  // update count at its last enlargement
  };

  // A pair of enlarged bounds (a candidate) is a BroadPair; `touching`: its given bounds
  // overlapped at the end of the last update (it is then one of pairs()). Not kept while no
  // proxy is enlarged (the candidates are the pairs then): see flags_valid_.
  using Candidate = BroadPair;

  // A proxy's keys on the two axes a sweep does not run along (b, c).
  struct EndKeys {
    std::uint64_t lb, ub, lc, uc;
  };

  // Open intervals of one sweep: structure of arrays over the two axes the sweep does not run
  // along, so the inner loop streams through contiguous keys. It holds 32-bit prefixes of the
  // keys (prefix32: monotone, so a < b implies prefix(a) <= prefix(b)): a test on prefixes,
  // four at a time, is a filter that never drops an overlap; the few it passes are tested on
  // the full keys (keys_b, keys_c: the ends_ arrays of the two axes). Arrays have 3 entries
  // past the capacity, read (and masked) by the last group of four.
  struct ActiveSet {
    std::vector<std::int32_t> id;
    std::vector<std::int32_t> lower_b, upper_b, lower_c, upper_c;
    std::vector<std::int32_t> first;  // slab sweep: -1 when this slab is the proxy's first, else 0
    const std::uint64_t* keys_b = nullptr;
    const std::uint64_t* keys_c = nullptr;
    std::size_t size = 0;
    void reserve(std::size_t n);
    void clear() { size = 0; }
    /// Appends a proxy with its keys on the two tested axes; returns its position.
    std::size_t push(std::int32_t p, const EndKeys& k, bool first_slab) {
      const std::size_t pos = size++;
      id[pos] = p;
      lower_b[pos] = prefix32(k.lb);
      upper_b[pos] = prefix32(k.ub);
      lower_c[pos] = prefix32(k.lc);
      upper_c[pos] = prefix32(k.uc);
      first[pos] = first_slab ? -1 : 0;
      return pos;
    }
    /// Removes position pos by moving the last entry into it; returns the moved proxy
    /// (now at pos), or -1 when pos was the last.
    std::int32_t removeAt(std::size_t pos) {
      const std::size_t back = --size;
      if (pos == back) return -1;
      id[pos] = id[back];
      lower_b[pos] = lower_b[back];
      upper_b[pos] = upper_b[back];
      lower_c[pos] = lower_c[back];
      upper_c[pos] = upper_c[back];
      first[pos] = first[back];
      return id[pos];
    }
  };
  // The 32 high bits of a key as a signed integer in the same order.
  static std::int32_t prefix32(std::uint64_t key) {
    return static_cast<std::int32_t>(static_cast<std::uint32_t>(key >> 32) ^ 0x80000000u);
  }

  // Enlarged keys per axis (what the arrays are sorted by), indexed by endpoint code
  // o = 2 proxy + is_upper: ends_[axis][o].
  bool overlaps(std::int32_t a, std::int32_t b) const {
    const std::size_t x = 2 * static_cast<std::size_t>(a), y = 2 * static_cast<std::size_t>(b);
    const std::uint64_t* e0 = ends_[0].data();
    const std::uint64_t* e1 = ends_[1].data();
    const std::uint64_t* e2 = ends_[2].data();
    return (e0[x] < e0[y + 1]) & (e0[y] < e0[x + 1]) & (e1[x] < e1[y + 1]) & (e1[y] < e1[x + 1]) &
           (e2[x] < e2[y + 1]) & (e2[y] < e2[x + 1]);
  }
  // The same test, the two other axes first: a begin event already overlaps on `axis`, and
  // most candidates are apart on another axis.
  bool overlapsAcross(std::int32_t a, std::int32_t b, int axis) const {
    const std::size_t x = 2 * static_cast<std::size_t>(a), y = 2 * static_cast<std::size_t>(b);
    const std::uint64_t* e1 = ends_[axis == 0 ? 1 : 0].data();
    const std::uint64_t* e2 = ends_[axis == 2 ? 1 : 2].data();
    const std::uint64_t* e0 = ends_[axis].data();
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
      const std::uint64_t* e = other < axis ? ends_[other].data() : prev_ends_[other].data();
      if (!(e[x] < e[y + 1] && e[y] < e[x + 1])) return false;
    }
    return true;
  }
  // What a sweep reports: kRebuild stamps every pair it finds (new ones also begin); kAllNew
  // begins every pair (all proxies new); kNewOnly begins the pairs with a new proxy.
  enum class SweepMode : std::uint8_t { kRebuild, kAllNew, kNewOnly };

  // Slabs of a second axis for a slab sweep; count 0: not worth it.
  struct SlabGrid {
    int axis = -1;
    double lo = 0.0, scale = 0.0;  // slab of x: (x - lo) * scale
    std::size_t count = 0;
    std::uint32_t slabOf(std::uint64_t key) const;
  };

  // Endpoint positions [from, to) of one axis that a new proxy must look at.
  struct Window {
    std::size_t from = 0, to = 0;
  };

  void reserveSlots(std::size_t slots);
  void checkLive(ProxyId proxy, const char* what) const;
  void setFat(ProxyInfo& p, bool fat) {
    fat_count_ += static_cast<int>(fat) - static_cast<int>(p.fat);
    p.fat = fat;
  }
  void beginPair(std::int32_t a, std::int32_t b);
  void endPair(std::int32_t a, std::int32_t b);

  // Coasting.
  void writeTight(ProxyId proxy, const Aabb& bounds);
  // Given bounds within the enlarged ones; `equal`: the same.
  bool insideEnlarged(ProxyId proxy, bool* equal) const;
  void enlarge(ProxyId proxy, double lead);  // new enlarged bounds from the given ones
  // What an update did to the arrays: nothing, moved a few proxies' endpoints, or re-sorted.
  enum class Sorted : std::uint8_t { kNothing, kFew, kAll };
  Sorted handleEscapers();  // enlarges and re-sorts what left its bounds
  void enlargeAll(double lead);
  void validateFlags();                      // `touching` of every candidate, before enlarging
  void moveEscapers();                       // the few that left: only their endpoints move
  std::size_t findEndpoint(int axis, std::uint64_t key, std::uint32_t owner) const;
  std::size_t relocateEndpoint(int axis, std::size_t i, std::uint64_t key);  // returns swaps
  // Coasting's cost model (work units, see the constants in the source).
  double rebuildWork(double axes_sorted, double pairs) const;
  void judgeRun(double endpoints);
  void reportTouching();                     // pairs(), began and ended from the candidates
  bool touching(std::int32_t a, std::int32_t b) const {
    const std::uint64_t* x = tight_.data() + 6 * static_cast<std::size_t>(a);
    const std::uint64_t* y = tight_.data() + 6 * static_cast<std::size_t>(b);
    return (x[0] < y[1]) & (y[0] < x[1]) & (x[2] < y[3]) & (y[2] < x[3]) & (x[4] < y[5]) &
           (y[4] < x[5]);
  }

  // update() in steps: removals, re-sorting (incremental or rebuild), insertions.
  void applyRemovals();
  void dropRemovedEndpoints(int axis);
  // `jump`: the enlarged bounds of many proxies changed at once (skip the insertion-sort
  // attempt when the swaps estimated from the new keys exceed a rebuild); `allow_streak`:
  // a rebuild may leave two axes unsorted (not while coasting: moveEscapers needs them).
  void resort(bool jump, bool allow_streak);
  void keepHeadroom();
  // A rebuild's cost in swaps, scaled by rebuild_factor: the swap budget of insertion sort
  // (sorting all axes), or the swaps past which a streak goes on (the sweep axis only).
  std::int64_t rebuildCost(bool sweep_axis_only) const;
  void refreshKeys();           // reads every endpoint's current key into keys_
  void refreshAxis(int axis);   // the same for one axis
  // The swaps an insertion sort of `axis` would make, estimated from its keys (just read).
  std::int64_t estimateSwaps(int axis) const;
  // Reads the keys of the axes in order and estimates the swaps of an insertion sort of all.
  std::int64_t estimateAllSwaps();
  bool anyStale() const { return stale_[0] | stale_[1] | stale_[2]; }

  // Incremental path: insertion sort of every axis (reading the proxies' keys first when
  // `refresh`), reporting pair events; false when the swap budget ran out.
  bool sortAxes(bool refresh, std::int64_t budget);
  std::size_t findBreaks(int axis, bool refresh);  // positions where the order breaks
  bool sortRuns(int axis, std::size_t breaks, std::int64_t budget, std::int64_t* swaps);
  std::size_t sinkEndpoint(int axis, std::size_t i);  // returns its new position
  void rollBack(std::size_t began_mark, std::size_t ended_mark);

  // Rebuild path.
  // `streak`: sort only the sweep axis (except on the rebuilds that re-choose it), whose keys
  // were read; `keys_read`: every axis' keys were read.
  void rebuild(bool streak, bool keys_read);
  void sortAxisFully(int axis);
  void radixSortAxis(int axis);
  void insertionSortAxis(int axis);
  std::int64_t sweepTests(int axis) const;
  int cheapestSweepAxis(std::int64_t* tests) const;  // among the sorted axes
  void measureWidths(double* mean_width);

  // Sweeps for pairs, around one kernel (testOpen).
  void findPairs(int axis, std::int64_t tests, SweepMode mode);
  void sweepForPairs(int axis, bool only_new);
  // false: not worth it here, nothing done. `rebuild`: stamp pairs (else report them as begun).
  bool sweepSlabs(int axis, const double* mean_width, bool rebuild);
  SlabGrid slabGrid(int axis, const double* mean_width) const;
  bool binIntoSlabs(int axis, const SlabGrid& grid);
  std::int64_t sweepEachSlab(int axis, const SlabGrid& grid, bool rebuild);
  template <bool kSlabs>
  std::size_t testOpen(const ActiveSet& set, std::int32_t p, const EndKeys& k, bool p_first,
                       bool rebuild);
  void open(ActiveSet& set, std::int32_t p, const EndKeys& k, bool first_slab);
  // The exact test of p against the proxy at position j of `set`; reports the pair.
  void testExactly(const ActiveSet& set, std::size_t j, std::int32_t p, const EndKeys& k,
                   bool rebuild);
  void close(ActiveSet& set, std::int32_t p);
  void foundPair(std::int32_t a, std::int32_t b, bool rebuild);

  // Insertions.
  void insertPending();
  void mergeNewEndpoints(int axis);
  bool insertByWindows();
  int cheapestWindowAxis(std::int64_t limit) const;
  Window window(int axis, ProxyId p) const;

  SweepAndPruneConfig config_;
  std::vector<std::uint64_t> ends_[3];  // 2 keys per proxy slot and axis
  // Keys as of the last update (the order of the endpoint arrays) on axes 1 and 2.
  std::vector<std::uint64_t> prev_ends_[3];
  std::vector<ProxyInfo> info_;
  std::int32_t free_list_ = -1;
  std::size_t reserved_slots_ = 0;
  int live_count_ = 0;
  double max_width_[3] = {0.0, 0.0, 0.0};  // widest bound per axis since the last rebuild, m

  // Endpoint arrays per axis, sorted by key, with a sentinel at each end: key[0] = 0,
  // key[last] = ~0. owner = proxy << 1 | is_upper.
  std::vector<std::uint64_t> keys_[3];
  std::vector<std::uint32_t> owners_[3];

  std::vector<ProxyId> pending_insert_;
  std::vector<ProxyId> pending_remove_;

  // Candidates (pairs of enlarged bounds) and their changes in this update (began, ended).
  BasicPairTable<Candidate> cands_;
  std::vector<Candidate> cand_began_;
  std::vector<Candidate> cand_ended_;
  // What callers see: the touching candidates, and their changes; or, while no proxy is
  // enlarged, the candidates and theirs.
  std::vector<BroadPair> exact_;
  std::vector<BroadPair> began_;
  std::vector<BroadPair> ended_;
  const std::vector<BroadPair>* pairs_out_ = &exact_;
  const std::vector<BroadPair>* began_out_ = &began_;
  const std::vector<BroadPair>* ended_out_ = &ended_;
  int fat_count_ = 0;         // live proxies whose enlarged bounds differ from the given ones
  bool flags_valid_ = true;   // every candidate's `touching` is up to date
  bool tight_last_ = true;    // no proxy was enlarged at the end of the last update

  // Coasting. Given bounds as keys, six per slot (lower, upper per axis): tight_; the same at
  // the proxy's last enlargement: base_ (its displacement since then sizes the next lead).
  std::vector<std::uint64_t> tight_;
  std::vector<std::uint64_t> base_;
  std::vector<ProxyId> escapers_;            // proxies that left their enlarged bounds
  std::vector<std::uint64_t> escaper_old_;   // their previous enlarged keys, six each
  std::uint32_t updates_ = 0;                // update() calls so far
  double lead_ = 0.0;                        // coast_updates while coasting, else 0
  std::uint32_t last_global_ = 0;            // update of the last enlargement of everybody
  std::uint32_t retry_at_ = 0;               // coasting off: the update that tries it again
  std::uint32_t backoff_ = 64;               // updates it stays off after failing
  bool moved_ = false;                       // not coasting: a live proxy moved
  double run_work_ = 0.0;                    // work of the coasting run under way
  bool judge_next_ = false;                  // a run is under way (judged when it ends)
  std::int64_t last_estimate_ = -1;          // swaps estimated by the last re-sort after a jump
  std::uint32_t recip_of_ = 1;               // enlarge(): 1 / recip_of_ = recip_
  double recip_ = 1.0;

  // Rebuild heuristics.
  bool last_rebuilt_ = false;
  double swap_scale_ = 3.0;      // all axes' estimated swaps / the sweep axis' (last estimate)
  // Axes a streak rebuild left out of order: no pair events may come from them until a full
  // rebuild sorts them (insertion sort from a stale order misses pairs that separated and
  // re-joined, or the reverse, since it was sorted); nothing looks up keys in them either.
  bool stale_[3] = {false, false, false};
  std::int64_t sweep_tests_ = 0;       // overlap tests of the last full sweep
  std::int64_t plain_tests_ = 0;       // of a plain sweep along the axis when last chosen
  int sweep_axis_ = 0;                 // axis of the rebuild sweeps
  unsigned rebuilds_since_choice_ = 0;
  double mean_width_[3] = {0.0, 0.0, 0.0};  // mean bound width per axis when last measured, m
  bool widths_due_ = true;                  // the next rebuild's slab sweep re-measures them

  // Scratch, kept between updates so steady-state updates allocate nothing.
  std::vector<std::uint64_t> sort_items_, sort_items2_;
  std::vector<std::uint64_t> tmp_keys_;
  std::vector<std::uint32_t> tmp_owners_;
  std::vector<std::uint32_t> breaks_;     // insertion sort: positions where the order breaks
  std::vector<std::uint32_t> slab_lo_, slab_hi_;  // slab sweep: per proxy, first and last slab
  std::vector<std::uint32_t> slab_owners_;        // slab sweep: endpoints, slab after slab
  std::vector<std::size_t> slab_start_, slab_pos_;
  ActiveSet active_;                      // sweep: open intervals of old proxies
  ActiveSet active_new_;                  // sweep: open intervals of inserted proxies
  std::vector<std::int32_t> active_pos_;  // per proxy: position in its active set
  SweepAndPruneStats stats_;
  std::uint32_t epoch_ = 0;
};

}  // namespace workspace_proximity
