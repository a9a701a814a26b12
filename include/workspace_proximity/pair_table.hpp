#pragma once
/// Open-addressing hash set of unordered proxy pairs with dense storage.

#include <cstdint>
#include <vector>

namespace workspace_proximity {

/// An unordered pair of proxies, stored with proxy_a < proxy_b.
struct ProxyPair {
  std::int32_t proxy_a = -1;
  std::int32_t proxy_b = -1;
  std::uint32_t user = 0;   ///< free for the owner of the table (e.g. a cached filter verdict)
  std::uint32_t stamp = 0;  ///< internal: last rebuild epoch that saw the pair
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
  ProxyPair* find(std::int32_t a, std::int32_t b);
  /// Removes (a, b); returns false if it was absent. `removed` receives a copy.
  bool erase(std::int32_t a, std::int32_t b, ProxyPair* removed = nullptr);
  /// Removes the pair at dense position i (order of the rest may change).
  void eraseAt(int i);
  void clear();

  const std::vector<ProxyPair>& pairs() const { return dense_; }
  std::vector<ProxyPair>& mutablePairs() { return dense_; }
  int size() const { return static_cast<int>(dense_.size()); }

  static std::uint64_t key(std::int32_t a, std::int32_t b) {
    if (a > b) { std::int32_t t = a; a = b; b = t; }
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
           static_cast<std::uint32_t>(b);
  }

 private:
  static constexpr std::int32_t kEmpty = -1;
  std::uint32_t slotOf(std::uint64_t key) const;
  void grow();

  std::vector<ProxyPair> dense_;
  std::vector<std::int32_t> index_;   // dense position or kEmpty
  std::uint32_t mask_ = 0;
};

}  // namespace workspace_proximity
