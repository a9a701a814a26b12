#pragma once
/// SweepAndPrune's incremental path (private to the core): insertion sort of every axis from
/// the last update's order, reporting pair events as endpoints pass each other, and the
/// relocation of a few proxies' endpoints (coasting's escapers) in arrays otherwise in order.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace workspace_proximity {
namespace sap {

struct State;

/// Insertion sort of every axis (reading the proxies' keys first when `refresh`), reporting
/// pair events; false when the swaps exceeded `budget` (the pair events so far are then to be
/// rolled back). Sets stats.swaps.
bool sortAxes(State& s, bool refresh, std::int64_t budget);
/// Undoes the pair events listed after the given marks of cand_began and cand_ended.
void rollBack(State& s, std::size_t began_mark, std::size_t ended_mark);

/// Reads every endpoint's current key into the endpoint arrays (refreshKeys), or one axis'.
void refreshKeys(State& s);
void refreshAxis(State& s, int axis);
/// Reads the keys of the axes in order and estimates the swaps of an insertion sort of all
/// (after a streak rebuild: of the sweep axis alone, scaled by its last share).
std::int64_t estimateAllSwaps(State& s);

/// The swaps an insertion sort of one endpoint array would make, estimated from its keys (a
/// sample of the inversions at distances 1 to 64).
std::int64_t estimateSwapsOf(const std::vector<std::uint64_t>& keys);

/// Gives the escapers (the few proxies that left their enlarged bounds) new enlarged bounds
/// and moves their endpoints alone, with pair events; returns the swaps.
std::size_t moveEscapers(State& s);

}  // namespace sap
}  // namespace workspace_proximity
