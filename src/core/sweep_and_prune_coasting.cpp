#include "sweep_and_prune_coasting.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace workspace_proximity {
namespace sap {

void enlarge(State& s, ProxyId id, double lead) {
  s.setFat(s.info[static_cast<std::size_t>(id)], enlargeInto(s, id, lead, s.ends, 0.0));
}

namespace {

// The drift: the centre's displacement per update averaged over about kDriftMemory updates
// (a few runs), so that one run's noise does not set it.
constexpr double kDriftMemory = 16.0;

// enlargeInto()'s work; kAhead false: `ahead` is 0 (every enlargement but the next arrays'),
// and its terms drop out (exactly: they add +0 or nothing). A run's end enlarges everybody
// with it, ~40 % of that end in a steady scene (bench/results/NOTES.md section 29).
template <bool kAhead>
bool enlargeBody(State& s, ProxyId id, double lead, std::vector<std::uint64_t>* ends, double ahead) {
  // Lead ahead of each side that moved outward since the last enlargement: `lead` updates of
  // its displacement per update; behind it (and on a side that moved inward) one update's, so
  // that a body that turns or stops does not leave at once. A side that did not move gets no
  // room: a resting body never leaves its bounds.
  const std::size_t o = 2 * static_cast<std::size_t>(id);
  std::uint64_t* t = s.tight.data() + 6 * static_cast<std::size_t>(id);
  std::uint64_t* b = s.base.data() + 6 * static_cast<std::size_t>(id);
  ProxyInfo& info = s.info[static_cast<std::size_t>(id)];
  const std::uint32_t elapsed = s.updates - info.enlarged_at;
  info.enlarged_at = s.updates;
  if (!(lead > 0.0)) {
    for (int axis = 0; axis < 3; ++axis) {
      std::uint64_t* e = ends[axis].data() + o;
      e[0] = b[2 * axis] = t[2 * axis];
      e[1] = b[2 * axis + 1] = t[2 * axis + 1];
      s.max_width[axis] = std::max(s.max_width[axis], unsortable64(e[1]) - unsortable64(e[0]));
    }
    return false;
  }
  ProxyMotion& m = s.motion[static_cast<std::size_t>(id)];
  // At rest since the last enlargement, with no jitter or drift learnt (a shelf, a parked
  // cart, a fixed link: most of a warehouse): what follows would give it no room on any side
  // (its bounds are finite: moveProxy and createProxy check them) and learn nothing but the
  // memory's length. The same in a few instructions (enlarging everybody in the warehouse
  // scene: 53 -> 29 us at N = 1 000; bench/results/NOTES.md section 35).
  if (m.jitter == 0.0f && m.drift[0] == 0.0f && m.drift[1] == 0.0f && m.drift[2] == 0.0f &&
      std::equal(t, t + 6, b)) {
    m.memory = static_cast<float>(std::min(kDriftMemory, static_cast<double>(elapsed) + static_cast<double>(m.memory)));
    for (int axis = 0; axis < 3; ++axis) {
      std::uint64_t* e = ends[axis].data() + o;
      e[0] = t[2 * axis];
      e[1] = t[2 * axis + 1];
      s.max_width[axis] = std::max(s.max_width[axis], unsortable64(e[1]) - unsortable64(e[0]));
    }
    return false;
  }
  // The given bounds now and at the last enlargement, as numbers (read once: the stores
  // below may alias them for the compiler).
  double lo[3], hi[3], base_lo[3], base_hi[3], extent = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    lo[axis] = unsortable64(t[2 * axis]);
    hi[axis] = unsortable64(t[2 * axis + 1]);
    base_lo[axis] = unsortable64(b[2 * axis]);
    base_hi[axis] = unsortable64(b[2 * axis + 1]);
    extent = std::max(extent, hi[axis] - lo[axis]);
  }
  // (Enlarging everybody divides by the same count again and again.)
  if (elapsed != s.recip_of) {
    s.recip_of = elapsed;
    s.recip = 1.0 / static_cast<double>(std::max<std::uint32_t>(1, elapsed));
  }
  const double per_update = s.recip;
  const double cap = s.config.max_lead_fraction * extent;
  // Tracker jitter: the part of the centre's displacement since the last enlargement that
  // neither rest nor its drift explains. A steady motion leaves none; a box reported a few
  // millimetres off in a random direction every frame leaves up to twice its noise. The bound
  // keeps the largest seen, forgotten slowly at each enlargement that does not see it again;
  // every side gets kJitterRoom times it on top of its lead, and the lead is sized from the
  // displacement beyond it, so that a box that comes back inside the bounds it had costs
  // nothing.
  const double span = static_cast<double>(elapsed);
  double centre[3], u[3];
  for (int axis = 0; axis < 3; ++axis) {
    centre[axis] = 0.5 * ((lo[axis] - base_lo[axis]) + (hi[axis] - base_hi[axis]));
    // The smaller of what rest and what the drift leave unexplained: a drift measured from
    // noise over a short run must not be extrapolated over a long one. (std::max keeps `seen`
    // when the residual is not a number.)
    const double drifted = centre[axis] - span * static_cast<double>(m.drift[axis]);
    const double unexplained = std::min(std::abs(centre[axis]), std::abs(drifted));
    u[axis] = unexplained >= 0.0 ? unexplained : 0.0;  // (not a number: none)
  }
  // A tracker's noise moves the centre on every axis it measures; a steady motion that bounced
  // off a wall or changed speed along one axis leaves a residual on that axis alone (the
  // others' are rounding). Such a one-axis residual is a manoeuvre, not noise: the bound then
  // learns the middle residual of the three (next to nothing). Learning it made the uniform
  // 5 % rows 1.2x slower (bench/results/jitter.md): the boxes that bounced carried room on
  // every side for many runs. Planar tracking (one axis exact) still has two noisy axes.
  constexpr double kQuiet = 1.0 / 4096;  // a residual below this fraction of the size: none
  const double largest = std::max(u[0], std::max(u[1], u[2]));
  const double middle = std::max(std::min(u[0], u[1]), std::min(std::max(u[0], u[1]), u[2]));
  double seen = middle > kQuiet * extent ? largest : middle;
  // Room per unit of that bound: one sample of it is often below the largest displacement
  // noise gives (a uniform noise's differences reach twice its amplitude).
  constexpr double kJitterRoom = 3.0;
  // What the bound keeps at each enlargement that does not see it again: it forgets slowly,
  // so that it holds the largest of several samples (one is often small).
  constexpr double kJitterKeep = 0.875;
  // Without a drift measured yet (the first enlargement since the proxy was created), a
  // displacement may be a steady motion's: it is not taken for jitter.
  if (!(m.memory > 0.0f)) seen = 0.0;
  // Nor is a jump of more than an eighth of the box's size (a turn, a swept box flipping
  // round): a tracker's noise is smaller, and a bound learnt from a manoeuvre would give the
  // box room on every side for many runs.
  constexpr double kLargestJitter = 0.125;
  if (largest > kLargestJitter * extent) seen = 0.0;
  const double jitter = std::min(cap, std::max(seen, kJitterKeep * static_cast<double>(m.jitter)));
  m.jitter = static_cast<float>(jitter);
  const double explained = jitter * per_update;
  auto beyond = [explained](double d) {
    return d > explained ? d - explained : d < -explained ? d + explained : 0.0;
  };
  const double memory = static_cast<double>(m.memory);
  const double weight = 1.0 / std::max(1.0, span + memory);
  m.memory = static_cast<float>(std::min(kDriftMemory, span + memory));
  bool fat = false;
  for (int axis = 0; axis < 3; ++axis) {
    const double drift = (centre[axis] + memory * static_cast<double>(m.drift[axis])) * weight;
    m.drift[axis] = std::isfinite(drift) ? static_cast<float>(drift) : 0.0f;
    // Displacements per update of the lower and the upper side beyond the jitter (positive:
    // upward).
    const double d_lo = beyond((lo[axis] - base_lo[axis]) * per_update);
    const double d_hi = beyond((hi[axis] - base_hi[axis]) * per_update);
    double below, above;
    CoastPolicy::room(d_lo, d_hi, kAhead ? lead + ahead : lead, cap, &below, &above);
    // A slow drift under the jitter leads as a steady motion does, and further, up to a whole
    // run's drift (4 leads), by at most twice the jitter's room again: otherwise drifting
    // boxes leave their bounds one by one in the last third of each run, and each costs a
    // search and swaps. (Once the jitter's room: at +-0.5 % jitter and a 0.2 % drift per
    // update, 120 of 1 000 boxes left in each 30-update run, ~13 % of the mean update.)
    // (A steady motion has no jitter: its lead is as before.)
    constexpr double kDriftJitterRoom = 2.0 * kJitterRoom;
    const double v = static_cast<double>(m.drift[axis]);
    const double own_room = std::min(4.0 * lead * std::abs(v), lead * std::abs(v) + kDriftJitterRoom * jitter);
    const double drift_room = kAhead ? ahead * std::abs(v) + own_room : own_room;
    below = std::max(below, std::min(cap, v < 0.0 ? drift_room : 0.0));
    above = std::max(above, std::min(cap, v > 0.0 ? drift_room : 0.0));
    below = std::min(cap, (below > 0.0 ? below : 0.0) + kJitterRoom * jitter);
    above = std::min(cap, (above > 0.0 ? above : 0.0) + kJitterRoom * jitter);
    // The next arrays' bounds (ahead > 0) take over `ahead` updates from now: their room
    // ahead of a moving side (and of the drift) is what it would be then plus the motion until
    // then, and a side moving inward starts where it will be one update before then (the
    // current bounds cover it until then). A side that moves less is outside at the swap and
    // moves alone then.
    double lo_from = lo[axis], hi_from = hi[axis];
    std::uint64_t lo_key = t[2 * axis], hi_key = t[2 * axis + 1];
    const double trim = ahead - 1.0;
    if (kAhead && trim > 0.0) {
      const double lo_t = d_lo > 0.0 ? lo_from + trim * d_lo : lo_from;
      const double hi_t = d_hi < 0.0 ? hi_from + trim * d_hi : hi_from;
      if (std::isfinite(lo_t) && std::isfinite(hi_t) && lo_t <= hi_t) {
        lo_from = lo_t;
        hi_from = hi_t;
        lo_key = lower64(lo_from);
        hi_key = upper64(hi_from);
      }
    }
    // Not a number: no room on that side. Finite: keys of infinities read back as NaN.
    constexpr double kMax = std::numeric_limits<double>::max();
    const double lo_e = std::max(-kMax, lo_from - (below > 0.0 ? below : 0.0));
    const double hi_e = std::min(kMax, hi_from + (above > 0.0 ? above : 0.0));
    std::uint64_t* e = ends[axis].data() + o;
    // Outward of the given keys whatever the rounding of the subtraction above.
    const std::uint64_t e_lo = std::min(lo_key, lower64(lo_e));
    const std::uint64_t e_hi = std::max(hi_key, upper64(hi_e));
    e[0] = e_lo;
    e[1] = e_hi;
    fat |= (e_lo != t[2 * axis]) | (e_hi != t[2 * axis + 1]);
    // (Widths only bound the windows of insertions, which allow for rounding.)
    s.max_width[axis] = std::max(s.max_width[axis], hi_e - lo_e);
    b[2 * axis] = t[2 * axis];
    b[2 * axis + 1] = t[2 * axis + 1];
  }
  return fat;
}

}  // namespace

bool enlargeInto(State& s, ProxyId id, double lead, std::vector<std::uint64_t>* ends, double ahead) {
  return ahead == 0.0 ? enlargeBody<false>(s, id, lead, ends, ahead) : enlargeBody<true>(s, id, lead, ends, ahead);
}

void enlargeAll(State& s, double lead) {
  for (std::size_t p = 0, slots = s.info.size(); p < slots; ++p) {
    if (s.info[p].state == ProxyState::kLive) enlarge(s, static_cast<ProxyId>(p), lead);
  }
}

namespace {

// True when more than a quarter of the live proxies would leave bounds enlarged ahead of their
// fastest side within `run` updates: a side moving d per update gets min(cap, lead |d|) of room
// (cap: max_lead_fraction of the largest extent), so it stays inside for min(lead, cap / |d|)
// updates, and `run` <= lead. d is the displacement from base (the bounds `elapsed` updates
// ago: 1 for the last move while coasting is off; since the last enlargement while it is on).
// A proxy without a displacement (enlarged in this update) or with a NaN anywhere is not
// counted as short.
bool quarterLeaveWithin(const State& s, double run, bool since_enlargement) {
  std::size_t short_runs = 0, live = 0;
  for (std::size_t p = 0, slots = s.info.size(); p < slots; ++p) {
    const ProxyInfo& info = s.info[p];
    if (info.state != ProxyState::kLive) continue;
    ++live;
    const std::uint32_t elapsed = since_enlargement ? s.updates - info.enlarged_at : 1;
    if (elapsed == 0) continue;
    const std::uint64_t* t = s.tight.data() + 6 * p;
    const std::uint64_t* b = s.base.data() + 6 * p;
    double extent = 0.0, fastest = 0.0;
    for (int axis = 0; axis < 3; ++axis) {
      const double lo = unsortable64(t[2 * axis]), hi = unsortable64(t[2 * axis + 1]);
      extent = std::max(extent, hi - lo);
      fastest = std::max(fastest, std::abs(lo - unsortable64(b[2 * axis])));
      fastest = std::max(fastest, std::abs(hi - unsortable64(b[2 * axis + 1])));
    }
    short_runs += s.config.max_lead_fraction * extent * static_cast<double>(elapsed) < run * fastest;
  }
  return 4 * short_runs > live;
}

}  // namespace

bool runsTooShort(const State& s, double lead) {
  // While coasting is off, moveProxy keeps each proxy's bounds before its last move in base:
  // its last displacement per side. (A NaN leaves the decision to the retry.)
  return quarterLeaveWithin(s, std::min(lead, CoastPolicy::kMinRun), false);
}

bool steadyLeadCapped(const State& s, double lead, std::uint32_t min_run) {
  // While coasting, base holds each proxy's bounds at its last enlargement.
  return quarterLeaveWithin(s, std::min(lead, static_cast<double>(min_run)), true);
}

void validateFlags(State& s) {
  // Somebody is enlarged in this update: from here on candidates and pairs may differ, and each
  // candidate's `touching` must say what it was. Not kept so far, the candidates were the pairs
  // (those that ended in this update so far too).
  if (s.flags_valid) return;
  for (Candidate& c : s.cands.mutablePairs()) c.touching = 1;
  for (Candidate& c : s.cand_ended) c.touching = 1;
  s.flags_valid = true;
}

void reportTouching(State& s) {
  std::vector<Candidate>& dense = s.cands.mutablePairs();
  s.stats.candidates = static_cast<int>(dense.size());
  // No enlarged bounds, now and at the last update: the candidates are the pairs, and their
  // changes the changes. (The first update without them still scans: a candidate of enlarged
  // bounds that did not touch may have begun to, without being a new candidate.)
  const bool was_tight = s.tight_last;
  s.tight_last = s.fat_count == 0;
  if (s.fat_count == 0 && was_tight) {
    s.pairs_out = &dense;
    s.began_out = &s.cand_began;
    s.ended_out = &s.cand_ended;
    // Coasting on (a box that shrinks inside its bounds is enlarged, without an update that
    // enlarges): keep `touching` up to date, for the new candidates only. Off: not needed until
    // coasting starts again (validateFlags).
    if (s.coast.lead() > 0.0 && s.flags_valid) {
      for (const Candidate& c : s.cand_began) {
        Candidate* pair = s.cands.find(c.proxy_a, c.proxy_b);
        if (pair != nullptr) pair->touching = 1;
      }
    } else {
      s.flags_valid = false;
    }
    return;
  }
  // pairs() = the candidates whose given bounds overlap; began and ended = the changes of that.
  s.pairs_out = &s.exact;
  s.began_out = &s.began;
  s.ended_out = &s.ended;
  s.began.clear();
  s.ended.clear();
  s.exact.clear();
  for (const Candidate& c : s.cand_ended) {
    if (c.touching != 0) s.ended.push_back(c);
  }
  for (Candidate& c : dense) {
    const std::uint32_t now = s.touching(c.proxy_a, c.proxy_b) ? 1u : 0u;
    if (now != c.touching) {
      c.touching = now;
      (now != 0 ? s.began : s.ended).push_back(c);
    }
    if (now != 0) s.exact.push_back(c);
  }
  s.coast.scanned(dense.size());
}

}  // namespace sap
}  // namespace workspace_proximity
