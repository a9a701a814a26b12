#include "workspace_proximity/event_tracker.hpp"

#include <algorithm>
#include <limits>

namespace workspace_proximity {

EventTracker::EventTracker(int initial_capacity)
    : index_(static_cast<std::size_t>(std::max(initial_capacity, 8))) {
  // The pool is built up front (the lecture's "array stack" of collision records); records
  // are recycled through the free list and the pool only grows when it runs out.
  growPool(static_cast<std::size_t>(std::max(initial_capacity, 8)));
}

void EventTracker::growPool(std::size_t size) {
  // New records join the free list.
  const std::size_t old = records_.size();
  records_.resize(size);
  for (std::size_t i = old; i < size; ++i) {
    records_[i].active_pos = -1;
    records_[i].next_free = (i + 1 < size) ? static_cast<std::int32_t>(i + 1) : -1;
  }
  free_list_ = static_cast<std::int32_t>(old);
  active_.reserve(size);
  events_.reserve(2 * size);
  sorted_.reserve(2 * size);
  sort_keys_.reserve(2 * size);
}

void EventTracker::growIndex() {
  index_.reset(2 * index_.capacity());
  for (std::int32_t r : active_) index_.insert(records_[r].key, r);
}

std::int32_t EventTracker::allocate(std::uint64_t key) {
  // Pool exhausted: only happens while the scene grows past its peak.
  if (free_list_ < 0) growPool(2 * records_.size());
  if (active_.size() + 1 > index_.capacity()) growIndex();
  const std::int32_t r = free_list_;
  free_list_ = records_[r].next_free;
  records_[r].key = key;
  records_[r].active_pos = static_cast<std::int32_t>(active_.size());
  active_.push_back(r);
  index_.insert(key, r);
  return r;
}

void EventTracker::release(std::int32_t r) {
  index_.erase(records_[r].key, r, [this](std::int32_t i) { return records_[i].key; });
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
  if (r == HashIndex::kNone) {
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
  // Pairs not reported this cycle end: one END each, then their records are recycled (so
  // a record, and the pair number it gives its events, is reused only after the END).
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
  sortEvents();
}

void EventTracker::sortEvents() {
  // Earliest contact first; ties (e.g. several touching now) by body handles for a
  // deterministic order. The sort moves 24-byte keys, not the events (about 150 bytes
  // each), which are then gathered once; on reserved vectors nothing is allocated.
  sort_keys_.clear();
  for (std::size_t i = 0; i < events_.size(); ++i) {
    const PairEvent& e = events_[i];
    // Handles are non-negative: as unsigned numbers they keep their order.
    const std::uint64_t bodies = (std::uint64_t{static_cast<std::uint32_t>(e.body_a.index)} << 32) |
                                 static_cast<std::uint32_t>(e.body_b.index);
    sort_keys_.push_back({e.time_to_contact, bodies, static_cast<std::uint32_t>(i)});
  }
  std::sort(sort_keys_.begin(), sort_keys_.end(), [](const SortKey& x, const SortKey& y) {
    if (x.time != y.time) return x.time < y.time;
    return x.bodies < y.bodies;
  });
  sorted_.clear();
  for (const SortKey& k : sort_keys_) sorted_.push_back(events_[k.event]);
  events_.swap(sorted_);
}

void EventTracker::clear() {
  while (!active_.empty()) release(active_.back());
  events_.clear();
}

}  // namespace workspace_proximity
