#pragma once
/// Set of unordered id pairs with dense storage and a hash index.

#include <cstdint>
#include <utility>
#include <vector>

#include "workspace_proximity/hash_index.hpp"

namespace workspace_proximity {

/// An unordered pair of ids, stored with proxy_a < proxy_b, with two words for the table's
/// owner (e.g. a marker id and the build that last showed it).
struct ProxyPair {
  std::int32_t proxy_a = -1;
  std::int32_t proxy_b = -1;
  std::uint32_t user = 0;
  std::uint32_t stamp = 0;
};

/// Pairs live in a dense array (iteration is a linear scan); a HashIndex maps the 64-bit
/// pair key to the dense position. Erase moves the last pair into the hole. Memory grows only
/// when a capacity is exceeded, never in steady state.
///
/// `Pair` is any record with std::int32_t fields proxy_a and proxy_b; the table keeps
/// proxy_a < proxy_b and value-initialises the rest of a new record, which belongs to the
/// owner.
template <class Pair>
class BasicPairTable {
 public:
  explicit BasicPairTable(int initial_capacity = 1024)
      : index_(static_cast<std::size_t>(initial_capacity < 8 ? 8 : initial_capacity)) {
    dense_.reserve(index_.capacity());
  }

  /// Inserts (a, b) if absent. Returns the record and sets `inserted` (if given).
  Pair* insert(std::int32_t a, std::int32_t b, bool* inserted) {
    if (a > b) std::swap(a, b);
    if (dense_.size() + 1 > index_.capacity()) reserve(2 * index_.capacity());
    const std::int32_t i = index_.findOrInsert(key(a, b), static_cast<std::int32_t>(dense_.size()),
                                               [this](std::int32_t j) { return keyAt(j); });
    if (i != HashIndex::kNone) {
      if (inserted) *inserted = false;
      return &dense_[static_cast<std::size_t>(i)];
    }
    Pair pair{};
    pair.proxy_a = a;
    pair.proxy_b = b;
    dense_.push_back(pair);
    if (inserted) *inserted = true;
    return &dense_.back();
  }

  Pair* find(std::int32_t a, std::int32_t b) {
    const std::int32_t i = indexOf(key(a, b));
    return i == HashIndex::kNone ? nullptr : &dense_[static_cast<std::size_t>(i)];
  }
  const Pair* find(std::int32_t a, std::int32_t b) const {
    const std::int32_t i = indexOf(key(a, b));
    return i == HashIndex::kNone ? nullptr : &dense_[static_cast<std::size_t>(i)];
  }

  /// Removes (a, b); returns false if it was absent. `removed` receives a copy.
  bool erase(std::int32_t a, std::int32_t b, Pair* removed = nullptr) {
    const std::int32_t i = indexOf(key(a, b));
    if (i == HashIndex::kNone) return false;
    if (removed) *removed = dense_[static_cast<std::size_t>(i)];
    eraseAt(i);
    return true;
  }

  /// Dense position of the pair with this key, or -1.
  std::int32_t indexOf(std::uint64_t k) const {
    return index_.find(k, [this](std::int32_t i) { return keyAt(i); });
  }

  /// Removes the pair at dense position i (the last pair moves into its place).
  void eraseAt(int i) {
    index_.erase(keyAt(i), i, [this](std::int32_t j) { return keyAt(j); });
    const int last = static_cast<int>(dense_.size()) - 1;
    if (i != last) {
      index_.move(keyAt(last), last, i);
      dense_[static_cast<std::size_t>(i)] = dense_[static_cast<std::size_t>(last)];
    }
    dense_.pop_back();
  }

  void clear() {
    dense_.clear();
    index_.clear();
  }

  const std::vector<Pair>& pairs() const { return dense_; }
  /// The records, for the owner's fields (proxy_a and proxy_b must not be changed).
  std::vector<Pair>& mutablePairs() { return dense_; }
  int size() const { return static_cast<int>(dense_.size()); }
  /// Pairs held before the table grows (and allocates).
  std::size_t capacity() const { return index_.capacity(); }

  /// Grows the table (if needed) to hold `pairs` pairs without growing again.
  void reserve(std::size_t pairs) {
    if (pairs <= index_.capacity()) return;
    index_.reset(pairs);
    for (std::int32_t i = 0; i < static_cast<std::int32_t>(dense_.size()); ++i) {
      index_.insert(keyAt(i), i);
    }
    dense_.reserve(index_.capacity());
  }

  static std::uint64_t key(std::int32_t a, std::int32_t b) {
    if (a > b) std::swap(a, b);
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
           static_cast<std::uint32_t>(b);
  }

 private:
  std::uint64_t keyAt(std::int32_t i) const {
    const Pair& p = dense_[static_cast<std::size_t>(i)];
    return key(p.proxy_a, p.proxy_b);
  }

  std::vector<Pair> dense_;
  HashIndex index_;
};

/// The pair table with ProxyPair records.
using PairTable = BasicPairTable<ProxyPair>;

}  // namespace workspace_proximity
