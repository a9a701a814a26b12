#include "workspace_proximity/event_tracker.hpp"

#include "workspace_proximity/hash_mix.hpp"

#include <algorithm>
#include <limits>

namespace workspace_proximity {
namespace {

std::uint32_t powerOfTwoAtLeast(std::uint32_t x) {
  std::uint32_t p = 16;
  while (p < x) p <<= 1;
  return p;
}

}  // namespace

EventTracker::EventTracker(int initial_capacity) {
  const std::uint32_t capacity = static_cast<std::uint32_t>(std::max(initial_capacity, 8));
  // The pool is built up front (the lecture's "array stack" of collision records); records
  // are recycled through the free list and the pool only grows when it runs out.
  records_.resize(capacity);
  for (std::uint32_t i = 0; i < capacity; ++i) {
    records_[i].active_pos = -1;
    records_[i].next_free = (i + 1 < capacity) ? static_cast<std::int32_t>(i + 1) : -1;
  }
  free_list_ = 0;
  active_.reserve(capacity);
  events_.reserve(2 * capacity);
  index_.assign(powerOfTwoAtLeast(2 * capacity), kEmpty);
  mask_ = static_cast<std::uint32_t>(index_.size() - 1);
}

std::int32_t EventTracker::find(std::uint64_t key) const {
  for (std::uint32_t s = static_cast<std::uint32_t>(mixKey(key)) & mask_;; s = (s + 1) & mask_) {
    const std::int32_t r = index_[s];
    if (r == kEmpty) return kEmpty;
    if (records_[r].key == key) return r;
  }
}

void EventTracker::indexInsert(std::uint64_t key, std::int32_t record) {
  std::uint32_t s = static_cast<std::uint32_t>(mixKey(key)) & mask_;
  while (index_[s] != kEmpty) s = (s + 1) & mask_;
  index_[s] = record;
}

void EventTracker::indexErase(std::uint64_t key) {
  std::uint32_t hole = static_cast<std::uint32_t>(mixKey(key)) & mask_;
  while (records_[index_[hole]].key != key) hole = (hole + 1) & mask_;
  // Backward-shift deletion keeps probe chains intact without tombstones.
  for (std::uint32_t s = (hole + 1) & mask_;; s = (s + 1) & mask_) {
    const std::int32_t r = index_[s];
    if (r == kEmpty) break;
    const std::uint32_t home = static_cast<std::uint32_t>(mixKey(records_[r].key)) & mask_;
    const bool home_between = hole <= s ? (hole < home && home <= s) : (hole < home || home <= s);
    if (!home_between) {
      index_[hole] = r;
      hole = s;
    }
  }
  index_[hole] = kEmpty;
}

void EventTracker::growIndex() {
  index_.assign(index_.size() * 2, kEmpty);
  mask_ = static_cast<std::uint32_t>(index_.size() - 1);
  for (std::int32_t r : active_) indexInsert(records_[r].key, r);
}

std::int32_t EventTracker::allocate(std::uint64_t key) {
  if (free_list_ < 0) {
    // Pool exhausted: double it. Only happens while the scene grows past its peak.
    const std::size_t old = records_.size();
    records_.resize(2 * old);
    for (std::size_t i = old; i < records_.size(); ++i) {
      records_[i].active_pos = -1;
      records_[i].next_free = (i + 1 < records_.size()) ? static_cast<std::int32_t>(i + 1) : -1;
    }
    free_list_ = static_cast<std::int32_t>(old);
    active_.reserve(records_.size());
    events_.reserve(2 * records_.size());
  }
  if (2 * (active_.size() + 1) > index_.size()) growIndex();
  const std::int32_t r = free_list_;
  free_list_ = records_[r].next_free;
  records_[r].key = key;
  records_[r].active_pos = static_cast<std::int32_t>(active_.size());
  active_.push_back(r);
  indexInsert(key, r);
  return r;
}

void EventTracker::release(std::int32_t r) {
  indexErase(records_[r].key);
  const std::int32_t pos = records_[r].active_pos;
  const std::int32_t moved = active_.back();
  active_[pos] = moved;
  records_[moved].active_pos = pos;
  active_.pop_back();
  records_[r].active_pos = -1;
  records_[r].next_free = free_list_;
  free_list_ = r;
}

void EventTracker::beginCycle() {
  ++cycle_;
  events_.clear();
}

void EventTracker::report(std::uint64_t key, const PairEvent& prediction) {
  std::int32_t r = find(key);
  ContactState state = ContactState::kOngoing;
  if (r == kEmpty) {
    r = allocate(key);
    state = ContactState::kBegin;
  }
  Record& rec = records_[r];
  rec.event = prediction;
  rec.event.state = state;
  rec.event.pair = r;
  rec.stamp = cycle_;
  events_.push_back(rec.event);
}

void EventTracker::endCycle() {
  // Pairs not reported this cycle end: one END each, then their records are recycled.
  for (std::size_t i = active_.size(); i-- > 0;) {
    const std::int32_t r = active_[i];
    if (records_[r].stamp == cycle_) continue;
    PairEvent end = records_[r].event;
    end.state = ContactState::kEnd;
    end.time_to_contact = std::numeric_limits<double>::infinity();
    end.time_to_separation = 0.0;
    events_.push_back(end);
    release(r);
  }
  // Earliest contact first; ties (e.g. several touching now) by body handles for a
  // deterministic order. std::sort on a reserved vector allocates nothing.
  std::sort(events_.begin(), events_.end(), [](const PairEvent& x, const PairEvent& y) {
    if (x.time_to_contact != y.time_to_contact) return x.time_to_contact < y.time_to_contact;
    if (x.body_a.index != y.body_a.index) return x.body_a.index < y.body_a.index;
    return x.body_b.index < y.body_b.index;
  });
}

void EventTracker::clear() {
  while (!active_.empty()) release(active_.back());
  events_.clear();
}

}  // namespace workspace_proximity
