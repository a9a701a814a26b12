#pragma once
/// SweepAndPrune's coasting mechanics (private to the core): the arrays hold each proxy's
/// bounds enlarged ahead of its motion (its given bounds are kept beside them, State::tight),
/// so the pairs the arrays give are candidates, and pairs() are the candidates whose given
/// bounds overlap. The decisions (how much room, when to enlarge, whether it pays) are
/// CoastPolicy's (sweep_and_prune_coast_policy.hpp).

#include <cstdint>
#include <vector>

#include "sweep_and_prune_state.hpp"
#include "workspace_proximity/aabb.hpp"

namespace workspace_proximity {
namespace sap {

/// Stores a proxy's given bounds as keys. Inline: moveProxy runs once per body and cycle.
inline void writeTight(State& s, ProxyId id, const Aabb& bounds) {
  std::uint64_t* t = s.tight.data() + 6 * static_cast<std::size_t>(id);
  for (int axis = 0; axis < 3; ++axis) {
    t[2 * axis] = lower64(bounds.lower[axis]);
    t[2 * axis + 1] = upper64(bounds.upper[axis]);
  }
}

/// writeTight(), then insideEnlarged() on the keys just written, in one pass (moveProxy's
/// coasting path: the keys stay in registers).
inline bool writeTightInside(State& s, ProxyId id, const Aabb& bounds, bool* equal) {
  const std::size_t o = 2 * static_cast<std::size_t>(id);
  std::uint64_t* t = s.tight.data() + 6 * static_cast<std::size_t>(id);
  bool inside = true, same = true;
  for (int axis = 0; axis < 3; ++axis) {
    const std::uint64_t lo = lower64(bounds.lower[axis]), hi = upper64(bounds.upper[axis]);
    t[2 * axis] = lo;
    t[2 * axis + 1] = hi;
    const std::uint64_t* e = s.ends[axis].data() + o;
    inside &= (e[0] <= lo) & (hi <= e[1]);
    same &= (e[0] == lo) & (hi == e[1]);
  }
  *equal = same;
  return inside;
}

/// True when the proxy's given bounds are within its enlarged ones; `equal`: the same.
inline bool insideEnlarged(const State& s, ProxyId id, bool* equal) {
  const std::size_t o = 2 * static_cast<std::size_t>(id);
  const std::uint64_t* t = s.tight.data() + 6 * static_cast<std::size_t>(id);
  bool inside = true, same = true;
  for (int axis = 0; axis < 3; ++axis) {
    const std::uint64_t* e = s.ends[axis].data() + o;
    inside &= (e[0] <= t[2 * axis]) & (t[2 * axis + 1] <= e[1]);
    same &= (e[0] == t[2 * axis]) & (t[2 * axis + 1] == e[1]);
  }
  *equal = same;
  return inside;
}

/// New enlarged bounds from the given ones, with `lead` (CoastPolicy::room; 0: the given
/// bounds themselves).
void enlarge(State& s, ProxyId id, double lead);
/// The same into `ends` (three arrays by endpoint code, as State::ends: the next arrays' while
/// they are built); returns whether they differ from the given bounds. Everything else it
/// learns (base, motion, enlarged_at, max_width) is the proxy's own, as in enlarge().
/// `ahead` (the next arrays: the updates until they are swapped in; 0 otherwise): the room is
/// what it would be then plus the motion until then, and a side moving inward starts
/// `ahead` - 1 updates of its displacement on (the bounds may then leave out the given ones of
/// now).
bool enlargeInto(State& s, ProxyId id, double lead, std::vector<std::uint64_t>* ends, double ahead);
/// The same for every live proxy.
void enlargeAll(State& s, double lead);
/// Coasting off: true when more than a quarter of the live proxies would leave bounds
/// enlarged with `lead` within CoastPolicy::kMinRun updates of their last displacement (the
/// room ahead is capped at max_lead_fraction of the box's largest extent). One pass over the
/// proxies, no allocation.
bool runsTooShort(const State& s, double lead);
/// Coasting on, before everybody is enlarged at once: true when more than a quarter of the live
/// proxies, moving as they did since their last enlargement, would leave bounds enlarged with
/// `lead` (capped at max_lead_fraction of their largest extent) within `min_run` updates.
bool steadyLeadCapped(const State& s, double lead, std::uint32_t min_run);
/// Makes every candidate's `touching` flag valid (before anybody is enlarged).
void validateFlags(State& s);
/// pairs(), beganPairs() and endedPairs() from the candidates and their changes.
void reportTouching(State& s);

}  // namespace sap
}  // namespace workspace_proximity
