#pragma once
/// SweepAndPrune's batched insertion (private to the core): the proxies created since the
/// last update join the sorted arrays in one merge per axis, then their pairs are found,
/// either in the windows of the endpoint arrays that can hold a box overlapping them (a few
/// insertions) or with a sweep (many).

namespace workspace_proximity {
namespace sap {

struct State;

/// Inserts every pending proxy and begins its pairs; sets stats.inserted.
void insertPending(State& s);

}  // namespace sap
}  // namespace workspace_proximity
