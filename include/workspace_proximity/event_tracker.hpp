#pragma once
/// Turns per-cycle predictions into BEGIN / ONGOING / END events, earliest first.

#include <cstdint>
#include <vector>

#include "workspace_proximity/hash_index.hpp"
#include "workspace_proximity/pair_event.hpp"

namespace workspace_proximity {

/// Keeps one record per predicted pair between cycles, in a pool of recycled records
/// addressed through an open-addressing index (no per-pair heap nodes). Usage per cycle:
/// beginCycle(); report(...) for every pair predicted to touch; endCycle(); read events().
/// Pairs not reported in a cycle get one END event and their record returns to the pool.
class EventTracker {
 public:
  explicit EventTracker(int initial_capacity = 256);

  void beginCycle();
  /// `key` identifies the pair for its whole life (never reused for another pair).
  /// The event's state and pair number (PairEvent::pair, the pair's record in the pool) are
  /// set by the tracker; everything else is copied.
  /// `hint`: the record this pair had (report's return value last time) or -1; used only
  /// when it is still this key's, so any value is safe, and a right one saves the index's
  /// look-up (a few cache misses per pair at ten thousand pairs). Returns the pair's record.
  std::int32_t report(std::uint64_t key, const PairEvent& prediction, std::int32_t hint = -1);
  /// Emits END for unreported pairs and sorts the events by time to contact.
  void endCycle();

  /// This cycle's events, ordered by time_to_contact (END events, at +infinity, last).
  const std::vector<PairEvent>& events() const { return events_; }
  /// Pairs currently predicted (BEGIN or ONGOING this cycle).
  int activeCount() const { return static_cast<int>(active_.size()); }
  /// Records the pool holds in all (grows only when exceeded).
  int poolCapacity() const { return static_cast<int>(records_.size()); }
  /// Forgets every pair without emitting END (e.g. after a reset of the caller's world).
  void clear();
  /// How the last endCycle() ordered the events: false from the last cycle's order (insertion
  /// and a merge), true by a radix sort of every key (most pairs far from their last place).
  bool radixSorted() const { return radix_sorted_; }

 private:
  // A pair's record holds no event: its latest one is in last_events_ (at rank_[record]),
  // which is where its END comes from. Small records, and each event copied once less.
  struct Record {
    std::uint64_t key;
    std::uint32_t stamp;     // cycle that last reported it
    std::int32_t active_pos; // position in active_, -1 when free
    std::int32_t next_free;
  };
  std::int32_t find(std::uint64_t key) const {
    return index_.find(key, [this](std::int32_t r) { return records_[r].key; });
  }
  std::int32_t allocate(std::uint64_t key);
  void release(std::int32_t record);
  void growPool(std::size_t records);
  void growIndex();
  void sortEvents();

  std::vector<Record> records_;        // the pool
  std::int32_t free_list_ = -1;
  std::vector<std::int32_t> active_;   // records in use
  HashIndex index_;                    // key -> record
  std::uint32_t cycle_ = 0;
  std::vector<PairEvent> events_;
  std::vector<PairEvent> last_events_;  // last cycle's events, in order
  // Sorting: the events' keys, and the events in order (swapped with events_ once gathered).
  struct SortKey {
    double time;           // time to contact, s
    std::uint64_t bodies;  // body_a's index, then body_b's
    std::uint32_t event;   // position in events_
  };
  std::vector<SortKey> sort_keys_;
  std::vector<PairEvent> sorted_;
  // Temporal coherence (the devlog's idea, applied to the events): a pair's events keep nearly
  // the same place from one cycle to the next, so the keys start in the last cycle's order and
  // are insertion-sorted, but for the few far out of place: sorted apart and merged back in.
  std::vector<std::int32_t> rank_;     // per record: its event's place last cycle, or -1
  std::vector<std::int32_t> placed_;   // per last cycle's place: this cycle's event, or -1
  std::vector<SortKey> ranked_;        // keys of pairs that had a place, as they arrived
  std::vector<SortKey> unranked_;      // keys of the others (new pairs, ENDs, far out of place)
  // Places a key of the last order may move by insertion; one further off is sorted apart.
  static constexpr std::size_t kMaxInsertion = 32;
  std::size_t last_count_ = 0;         // events last cycle
  // When more than an eighth of the last order would move far (a crowd whose tracks' ages
  // differ from cycle to cycle: times to contact shift by tens of milliseconds, keys by
  // hundreds of places), every key is radix-sorted by its time's bits instead, in
  // kRadixPasses passes of kRadixBits, and keys with equal times by their bodies.
  void radixSortKeys(std::size_t fresh);
  struct RadixKey {
    std::uint64_t time;    // the time's bits, ordered as the times are
    std::uint64_t bodies;
    std::uint32_t event;
  };
  static constexpr int kRadixBits = 11;
  static constexpr int kRadixPasses = 6;  // 6 x 11 bits cover the 64
  std::vector<RadixKey> radix_keys_, radix_spare_;
  std::vector<std::uint32_t> radix_counts_;  // kRadixPasses x 2^kRadixBits
  bool radix_sorted_ = false;
};

}  // namespace workspace_proximity
