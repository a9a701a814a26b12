#pragma once
/// Open-addressing hash index from 64-bit keys to dense int32 positions, shared by the pair
/// table, the event tracker and the world's pair cache.
///
/// The index stores positions only; the keys live with the owner's records, and every call
/// that needs a stored key takes a `keyOf(position)` function to read it. Linear probing in a
/// power-of-two slot array at most half full; deletion shifts the rest of the probe chain
/// back, so no tombstones build up. It allocates only in reset(), which the owner calls when
/// its capacity is exceeded (and then re-inserts its entries).

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace workspace_proximity {

/// The 64-bit finaliser of MurmurHash3 (fmix64). Proxy ids and body serials are small
/// consecutive integers, so keys need mixing before masking or probe sequences cluster.
inline std::uint64_t mixKey(std::uint64_t k) {
  k ^= k >> 33;
  k *= 0xff51afd7ed558ccdULL;
  k ^= k >> 33;
  k *= 0xc4ceb9fe1a85ec53ULL;
  k ^= k >> 33;
  return k;
}

class HashIndex {
 public:
  static constexpr std::int32_t kNone = -1;

  /// Room for `capacity` entries (at least 8).
  explicit HashIndex(std::size_t capacity = 8) { reset(capacity); }

  /// Entries it holds before the owner must reset() it larger: half its slots.
  std::size_t capacity() const { return slots_.size() / 2; }

  /// Forgets every entry and makes room for at least `capacity` entries: the slot count
  /// becomes the smallest power of two >= 2 capacity (and >= 16). Allocates when it grows.
  void reset(std::size_t capacity) {
    std::size_t size = 16;
    while (size < 2 * capacity) size <<= 1;
    slots_.assign(size, kNone);
    mask_ = static_cast<std::uint32_t>(size - 1);
  }

  /// Forgets every entry, keeping the size.
  void clear() { std::fill(slots_.begin(), slots_.end(), kNone); }

  /// Position stored under `key`, or kNone. Inline: the sweep-and-prune probes on every
  /// overlap that ends on one axis, most of them for absent pairs.
  template <class KeyOf>
  std::int32_t find(std::uint64_t key, const KeyOf& keyOf) const {
    for (std::uint32_t s = home(key);; s = next(s)) {
      const std::int32_t i = slots_[s];
      if (i == kNone || keyOf(i) == key) return i;
    }
  }

  /// Stores `position` under `key`, which must be absent; the owner keeps the entry count
  /// within capacity().
  void insert(std::uint64_t key, std::int32_t position) {
    std::uint32_t s = home(key);
    while (slots_[s] != kNone) s = next(s);
    slots_[s] = position;
  }

  /// Position stored under `key` if there is one; otherwise stores `position` under it and
  /// returns kNone (one probe sequence for both). The owner keeps the entry count within
  /// capacity().
  template <class KeyOf>
  std::int32_t findOrInsert(std::uint64_t key, std::int32_t position, const KeyOf& keyOf) {
    std::uint32_t s = home(key);
    for (;; s = next(s)) {
      const std::int32_t i = slots_[s];
      if (i == kNone) break;
      if (keyOf(i) == key) return i;
    }
    slots_[s] = position;
    return kNone;
  }

  /// Removes the entry `position`, stored under `key`, by backward shifting: each later
  /// entry of the probe chain moves into the hole unless its home lies cyclically in
  /// (hole, its slot].
  template <class KeyOf>
  void erase(std::uint64_t key, std::int32_t position, const KeyOf& keyOf) {
    std::uint32_t hole = home(key);
    while (slots_[hole] != position) hole = next(hole);
    for (std::uint32_t s = next(hole);; s = next(s)) {
      const std::int32_t i = slots_[s];
      if (i == kNone) break;
      const std::uint32_t h = home(keyOf(i));
      const bool home_between = hole <= s ? (hole < h && h <= s) : (hole < h || h <= s);
      if (!home_between) {
        slots_[hole] = i;
        hole = s;
      }
    }
    slots_[hole] = kNone;
  }

  /// The entry under `key` now lives at position `to` instead of `from` (its owner moved it).
  void move(std::uint64_t key, std::int32_t from, std::int32_t to) {
    std::uint32_t s = home(key);
    while (slots_[s] != from) s = next(s);
    slots_[s] = to;
  }

 private:
  std::uint32_t home(std::uint64_t key) const {
    return static_cast<std::uint32_t>(mixKey(key)) & mask_;
  }
  std::uint32_t next(std::uint32_t s) const { return (s + 1) & mask_; }

  std::vector<std::int32_t> slots_;  // position or kNone
  std::uint32_t mask_ = 0;
};

}  // namespace workspace_proximity
