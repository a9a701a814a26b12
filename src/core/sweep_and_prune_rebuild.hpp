#pragma once
/// SweepAndPrune's rebuild and sweep kernel (private to the core): sort every axis from
/// scratch, find every pair with one sweep along the axis with the fewest open intervals (in
/// slabs of a second axis when there are many bodies), and diff the new pair set against the
/// old one. The same sweeps find the pairs of inserted proxies (sweep_and_prune_insert).

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "sweep_and_prune_keys.hpp"

namespace workspace_proximity {
namespace sap {

struct State;

// A proxy's keys on the two axes a sweep does not run along (b, c).
struct EndKeys {
  std::uint64_t lb, ub, lc, uc;
};

// Open intervals of one sweep: structure of arrays over the two axes the sweep does not run
// along, so the inner loop streams through contiguous keys. It holds 32-bit prefixes of the
// keys (prefix32: monotone, so a < b implies prefix(a) <= prefix(b)): a test on prefixes,
// four at a time, is a filter that never drops an overlap; the few it passes are tested on
// the full keys (keys_b, keys_c: the State::ends arrays of the two axes). Arrays have 3
// entries past the capacity, read (and masked) by the last group of four.
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

/// Slabs of a second axis for a slab sweep; count 0: not worth it.
struct SlabGrid {
  int axis = -1;
  double lo = 0.0, scale = 0.0;  // slab of x: (x - lo) * scale
  std::size_t count = 0;
  std::uint32_t slabOf(std::uint64_t key) const {
    const double x = (unsortable64(key) - lo) * scale;
    return static_cast<std::uint32_t>(std::clamp(x, 0.0, static_cast<double>(count - 1)));
  }
};

/// Scratch of the sweeps, kept between updates.
struct SweepScratch {
  std::vector<std::uint32_t> slab_lo, slab_hi;  // slab sweep: per proxy, first and last slab
  std::vector<std::uint32_t> slab_owners;       // slab sweep: endpoints, slab after slab
  std::vector<std::size_t> slab_start, slab_pos;
  ActiveSet active;                       // open intervals of old proxies
  ActiveSet active_new;                   // open intervals of inserted proxies
  std::vector<std::int32_t> active_pos;   // per proxy: position in its active set
  void reserve(std::size_t slots);
};

/// What a sweep reports: kRebuild stamps every pair it finds (new ones also begin); kAllNew
/// begins every pair (all proxies new); kNewOnly begins the pairs with a new proxy.
enum class SweepMode : std::uint8_t { kRebuild, kAllNew, kNewOnly };

/// Sorts every axis from scratch (in a streak, `streak`, only the sweep axis, except on the
/// rebuilds that re-choose it; its keys were read), sweeps for every pair, and ends the pairs
/// it did not find. `keys_read`: every axis' keys were read already.
void rebuild(State& s, bool streak, bool keys_read);

/// The sorted axis along which a plain sweep makes the fewest overlap tests (stored in
/// *tests); a stale axis is never chosen.
int cheapestSweepAxis(const State& s, std::int64_t* tests);

/// Sweeps along `axis` for the pairs `mode` asks for (a slab sweep when a plain one would make
/// `tests` overlap tests, at least 16 per proxy, and every pair is wanted).
void findPairs(State& s, int axis, std::int64_t tests, SweepMode mode);

/// A sweep for every pair done in slices over several updates (the next arrays,
/// sweep_and_prune_next): where it is, along which axis, and its slabs (grid.count 0: a plain
/// sweep over endpoint positions [pos, end)). The open sets and the slab lists stay in
/// State::sweep between slices: nothing else may sweep meanwhile.
struct SweepCursor {
  int axis = 0;
  SlabGrid grid;
  std::size_t pos = 0, end = 0;  // next slab or endpoint position; one past the last
};

/// Starts a sliced sweep along `axis` for every pair (`tests`: a plain sweep's overlap tests,
/// which choose a slab sweep as findPairs does), in two steps that may go in different
/// slices: the plan (the widths and the slab grid); then, when it returns true, the slab
/// lists (binSweep).
bool planSweep(State& s, int axis, std::int64_t tests, SweepCursor* c);
/// The slab lists of a sweep planned in slabs (or a plain sweep when they would outgrow
/// their space).
void binSweep(State& s, SweepCursor* c);
/// Sweeps on by about `endpoints` endpoints (whole slabs, at least one); true when done.
bool sweepOn(State& s, SweepCursor* c, std::size_t endpoints);

}  // namespace sap
}  // namespace workspace_proximity
