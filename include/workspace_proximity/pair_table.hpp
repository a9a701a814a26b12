#pragma once
/// Open-addressing hash set of unordered proxy pairs with dense storage.

#include <cstdint>
#include <vector>

#include "workspace_proximity/hash_mix.hpp"

namespace workspace_proximity {

/// An unordered pair of proxies, stored with proxy_a < proxy_b.
struct ProxyPair {
  std::int32_t proxy_a = -1;
  std::int32_t proxy_b = -1;
  std::uint32_t user = 0;   ///< free for the owner of the table (e.g. a cached filter verdict)
  std::uint32_t stamp = 0;  ///< free for the owner too (sweep-and-prune: last rebuild epoch)
};

/// Pairs live in a dense array (iteration is a linear scan); a linear-probing index of
/// power-of-two size maps the 64-bit pair key to the dense slot. Erase swaps the last pair
/// into the hole and deletes from the index by backward shifting, so no tombstones build up.
/// Memory grows only when a capacity is exceeded, never in steady state.
class PairTable {
 public:
  explicit PairTable(int initial_capacity = 1024);

  /// Inserts (a, b) if absent. Returns the record and sets `inserted`.
  ProxyPair* insert(std::int32_t a, std::int32_t b, bool* inserted);
  ProxyPair* find(std::int32_t a, std::int32_t b) {
    const std::int32_t i = indexOf(key(a, b));
    return i == kEmpty ? nullptr : &dense_[i];
  }
  /// Removes (a, b); returns false if it was absent. `removed` receives a copy.
  bool erase(std::int32_t a, std::int32_t b, ProxyPair* removed = nullptr) {
    const std::int32_t i = indexOf(key(a, b));
    if (i == kEmpty) return false;
    if (removed) *removed = dense_[i];
    eraseAt(i);
    return true;
  }
  /// Dense position of the pair with this key, or -1. (Inline: the sweep-and-prune probes
  /// the table on every overlap that ends on one axis, most of them for absent pairs.)
  std::int32_t indexOf(std::uint64_t k) const {
    for (std::uint32_t s = slotOf(k);; s = (s + 1) & mask_) {
      const std::int32_t i = index_[s];
      if (i == kEmpty || keyAt(i) == k) return i;
    }
  }
  /// Removes the pair at dense position i (order of the rest may change).
  void eraseAt(int i);
  void clear();

  const std::vector<ProxyPair>& pairs() const { return dense_; }
  std::vector<ProxyPair>& mutablePairs() { return dense_; }
  int size() const { return static_cast<int>(dense_.size()); }
  /// Pairs held before the table grows (and allocates).
  std::size_t capacity() const { return dense_.capacity(); }
  /// Grows the table (if needed) to hold `pairs` pairs without growing again.
  void reserve(std::size_t pairs);

  static std::uint64_t key(std::int32_t a, std::int32_t b) {
    if (a > b) { std::int32_t t = a; a = b; b = t; }
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
           static_cast<std::uint32_t>(b);
  }

 private:
  static constexpr std::int32_t kEmpty = -1;
  std::uint32_t slotOf(std::uint64_t key) const {
    return static_cast<std::uint32_t>(mixKey(key)) & mask_;
  }
  std::uint64_t keyAt(std::int32_t i) const { return key(dense_[i].proxy_a, dense_[i].proxy_b); }
  void grow();

  std::vector<ProxyPair> dense_;
  std::vector<std::int32_t> index_;   // dense position or kEmpty
  std::uint32_t mask_ = 0;
};

}  // namespace workspace_proximity
