#include "workspace_proximity/event_tracker.hpp"

#include <algorithm>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace workspace_proximity {

EventTracker::EventTracker(int initial_capacity)
    : index_(static_cast<std::size_t>(std::max(initial_capacity, 8))) {
  // The pool is built up front (the lecture's "array stack" of collision records); records
  // are recycled through the free list and the pool only grows when it runs out.
  growPool(static_cast<std::size_t>(std::max(initial_capacity, 8)));
  radix_counts_.assign(static_cast<std::size_t>(kRadixPasses) << kRadixBits, 0);
}

void EventTracker::growPool(std::size_t size) {
  // New records join the free list.
  const std::size_t old = records_.size();
  records_.resize(size);
  rank_.resize(size, -1);
  for (std::size_t i = old; i < size; ++i) {
    records_[i].active_pos = -1;
    records_[i].next_free = (i + 1 < size) ? static_cast<std::int32_t>(i + 1) : -1;
  }
  free_list_ = static_cast<std::int32_t>(old);
  active_.reserve(size);
  events_.reserve(2 * size);
  last_events_.reserve(2 * size);
  sorted_.reserve(2 * size);
  sort_keys_.reserve(2 * size);
  placed_.reserve(2 * size);
  ranked_.reserve(2 * size);
  unranked_.reserve(2 * size);
  radix_keys_.reserve(2 * size);
  radix_spare_.reserve(2 * size);
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
  rank_[r] = -1;  // a new pair has no place yet
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
  last_events_.swap(events_);  // kept for the ENDs of pairs not reported this cycle
  events_.clear();
}

std::int32_t EventTracker::report(std::uint64_t key, const PairEvent& prediction, std::int32_t hint) {
  // Keys are never reused, and a free record has no place in active_: a hint that is an
  // active record with this key is the pair's record.
  std::int32_t r = hint;
  if (r < 0 || static_cast<std::size_t>(r) >= records_.size() || records_[r].active_pos < 0 ||
      records_[r].key != key) {
    r = find(key);
  }
  ContactState state = ContactState::kOngoing;
  if (r == HashIndex::kNone) {
    r = allocate(key);
    state = ContactState::kBegin;
  }
  records_[r].stamp = cycle_;
  events_.push_back(prediction);
  events_.back().state = state;
  events_.back().pair = r;
  return r;
}

void EventTracker::endCycle() {
  // Pairs not reported this cycle end: one END each, then their records are recycled (so
  // a record, and the pair number it gives its events, is reused only after the END).
  for (std::size_t i = active_.size(); i-- > 0;) {
    const std::int32_t r = active_[i];
    if (records_[r].stamp == cycle_) continue;
    // Not reported now, so reported last cycle (a pair unreported for a cycle has ended):
    // its event of then is at its place of then.
    const std::int32_t rank = rank_[r];
    if (rank < 0 || static_cast<std::size_t>(rank) >= last_events_.size() ||
        last_events_[rank].pair != r) {
      throw std::logic_error("EventTracker: an active pair without last cycle's event");
    }
    PairEvent end = last_events_[rank];
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
  // deterministic order (the keys are unique: one event per pair). The sort moves 24-byte
  // keys, not the events (about 150 bytes each), which are then gathered once; on reserved
  // vectors nothing is allocated.
  //
  // From one cycle to the next every time to contact shrinks by about the cycle's length, so
  // the order barely changes: the keys start in the last cycle's order (new pairs and ENDs
  // after them). Three kinds of change: neighbours trading places, a few keys jumping far (in
  // a dense crowd a pair whose contact came nearer than its neighbours', or reached 0, moves
  // thousands of places forward), and most keys moving far (people whose growing margins
  // start from track ages that differ every cycle: 72 places at the median among 22 700). An
  // insertion sort handles the first; a key that would move more than kMaxInsertion places
  // leaves instead, and the keys that left and the new ones are sorted alone and merged in
  // from the back: O(n kMaxInsertion + k log k) for k keys that left. Past an eighth of the
  // keys leaving, every key is radix-sorted (radixSortKeys): O(n). (Until session 14 an
  // insertion sort alone, with a full sort past 4 n + 64 moves: at 10 000 dense walkers every
  // cycle ended in it.)
  const auto earlier = [](const SortKey& x, const SortKey& y) {
    if (x.time != y.time) return x.time < y.time;
    return x.bodies < y.bodies;
  };
  const std::size_t n = events_.size();
  ranked_.clear();
  unranked_.clear();
  placed_.assign(last_count_, -1);
  for (std::size_t i = 0; i < n; ++i) {
    const PairEvent& e = events_[i];
    // Handles are non-negative: as unsigned numbers they keep their order.
    const std::uint64_t bodies = (std::uint64_t{static_cast<std::uint32_t>(e.body_a.index)} << 32) |
                                 static_cast<std::uint32_t>(e.body_b.index);
    const SortKey key{e.time_to_contact, bodies, static_cast<std::uint32_t>(i)};
    // An END's record was released (and is not reused before this sort): it has no place.
    const std::int32_t rank = e.state == ContactState::kEnd ? -1 : rank_[e.pair];
    if (rank >= 0 && static_cast<std::size_t>(rank) < last_count_ && placed_[rank] < 0) {
      placed_[rank] = static_cast<std::int32_t>(ranked_.size());
      ranked_.push_back(key);
    } else {
      unranked_.push_back(key);
    }
  }
  // The last cycle's order, insertion-sorted into sort_keys_ but for the keys that would move
  // far, which join unranked_ (sort_keys_ stays sorted, so one comparison tells). Past an
  // eighth of the keys moving far, the order is no guide: everything is radix-sorted.
  sort_keys_.clear();
  const std::size_t fresh = unranked_.size();
  const std::size_t most_far = n / 8 + kMaxInsertion;
  bool coherent = true;
  for (const std::int32_t slot : placed_) {
    if (slot < 0) continue;
    const SortKey k = ranked_[static_cast<std::size_t>(slot)];
    std::size_t j = sort_keys_.size();
    if (j >= kMaxInsertion && earlier(k, sort_keys_[j - kMaxInsertion])) {
      unranked_.push_back(k);
      if (unranked_.size() - fresh > most_far) {
        coherent = false;
        break;
      }
      continue;
    }
    sort_keys_.push_back(k);
    while (j > 0 && earlier(k, sort_keys_[j - 1])) {
      sort_keys_[j] = sort_keys_[j - 1];
      --j;
    }
    sort_keys_[j] = k;
  }
  radix_sorted_ = !coherent;
  if (coherent) {
    std::sort(unranked_.begin(), unranked_.end(), earlier);
    // Merge from the back: the kept keys move up in place, no third buffer (the keys are
    // unique).
    std::size_t kept = sort_keys_.size(), rest = unranked_.size();
    sort_keys_.resize(kept + rest);
    for (std::size_t out = kept + rest; rest > 0;) {
      if (kept > 0 && earlier(unranked_[rest - 1], sort_keys_[kept - 1])) {
        sort_keys_[--out] = sort_keys_[--kept];
      } else {
        sort_keys_[--out] = unranked_[--rest];
      }
    }
  } else {
    radixSortKeys(fresh);
  }
  sorted_.clear();
  // The gather reads the events in their new order, from all over events_ (15 000 events of
  // ~150 bytes at 10 000 dense walkers): each is asked for a few keys ahead.
  const std::size_t count = sort_keys_.size();
  for (std::size_t i = 0; i < count; ++i) {
    if (i + 8 < count) {
      const char* ahead = reinterpret_cast<const char*>(&events_[sort_keys_[i + 8].event]);
      __builtin_prefetch(ahead);
      __builtin_prefetch(ahead + 64);
      __builtin_prefetch(ahead + 128);
    }
    const PairEvent& e = events_[sort_keys_[i].event];
    if (e.state != ContactState::kEnd) rank_[e.pair] = static_cast<std::int32_t>(sorted_.size());
    sorted_.push_back(e);
  }
  last_count_ = sorted_.size();
  events_.swap(sorted_);
}

void EventTracker::radixSortKeys(std::size_t fresh) {
  // Every key once: all of ranked_ (the last order's) and the first `fresh` of unranked_ (new
  // pairs and ENDs; the rest are ranked_'s keys set aside).
  radix_keys_.clear();
  const auto add = [this](const SortKey& k) {
    // A time's bits as an unsigned number in the times' order: non-negative times (and
    // +infinity) with the sign bit set, negative ones inverted. -0 + 0 is +0, which the
    // comparison takes for equal to -0 and so must the bits.
    const double t = k.time + 0.0;
    std::uint64_t bits;
    std::memcpy(&bits, &t, sizeof bits);
    bits = (bits >> 63) != 0 ? ~bits : bits | (std::uint64_t{1} << 63);
    radix_keys_.push_back(RadixKey{bits, k.bodies, k.event});
  };
  for (const SortKey& k : ranked_) add(k);
  for (std::size_t i = 0; i < fresh; ++i) add(unranked_[i]);
  const std::size_t n = radix_keys_.size();
  sort_keys_.resize(n);
  if (n == 0) return;
  radix_spare_.resize(n);
  // Least significant digit first, every digit's counts in one pass; a digit that every key
  // shares (the times' top bits, often) takes no pass.
  constexpr std::size_t kDigits = std::size_t{1} << kRadixBits;
  constexpr std::uint64_t kMask = kDigits - 1;
  std::fill(radix_counts_.begin(), radix_counts_.end(), 0u);
  for (const RadixKey& k : radix_keys_) {
    for (int pass = 0; pass < kRadixPasses; ++pass) {
      ++radix_counts_[(static_cast<std::size_t>(pass) << kRadixBits) + ((k.time >> (kRadixBits * pass)) & kMask)];
    }
  }
  for (int pass = 0; pass < kRadixPasses; ++pass) {
    std::uint32_t* count = radix_counts_.data() + (static_cast<std::size_t>(pass) << kRadixBits);
    const int shift = kRadixBits * pass;
    if (count[(radix_keys_.front().time >> shift) & kMask] == n) continue;
    std::uint32_t sum = 0;
    for (std::size_t d = 0; d < kDigits; ++d) {
      const std::uint32_t c = count[d];
      count[d] = sum;
      sum += c;
    }
    for (const RadixKey& k : radix_keys_) radix_spare_[count[(k.time >> shift) & kMask]++] = k;
    radix_keys_.swap(radix_spare_);
  }
  // Equal times (several pairs touching now) by their bodies.
  for (std::size_t first = 0; first < n;) {
    std::size_t last = first + 1;
    while (last < n && radix_keys_[last].time == radix_keys_[first].time) ++last;
    if (last - first > 1) {
      std::sort(radix_keys_.begin() + static_cast<std::ptrdiff_t>(first),
                radix_keys_.begin() + static_cast<std::ptrdiff_t>(last),
                [](const RadixKey& x, const RadixKey& y) { return x.bodies < y.bodies; });
    }
    first = last;
  }
  for (std::size_t i = 0; i < n; ++i) {
    const RadixKey& k = radix_keys_[i];
    const std::uint64_t bits = (k.time >> 63) != 0 ? k.time & ~(std::uint64_t{1} << 63) : ~k.time;
    double t;
    std::memcpy(&t, &bits, sizeof t);
    sort_keys_[i] = SortKey{t, k.bodies, k.event};
  }
}

void EventTracker::clear() {
  while (!active_.empty()) release(active_.back());
  events_.clear();
  last_events_.clear();
  last_count_ = 0;  // no event has a place to keep
}

}  // namespace workspace_proximity
