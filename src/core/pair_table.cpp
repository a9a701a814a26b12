#include "workspace_proximity/pair_table.hpp"

#include <algorithm>

namespace workspace_proximity {
namespace {

std::uint32_t nextPowerOfTwo(std::uint32_t x) {
  std::uint32_t p = 16;
  while (p < x) p <<= 1;
  return p;
}

}  // namespace

PairTable::PairTable(int initial_capacity) {
  const std::uint32_t capacity = static_cast<std::uint32_t>(std::max(initial_capacity, 8));
  // Index at most half full keeps linear probes short.
  index_.assign(nextPowerOfTwo(2 * capacity), kEmpty);
  mask_ = static_cast<std::uint32_t>(index_.size() - 1);
  dense_.reserve(index_.size() / 2);
}

ProxyPair* PairTable::insert(std::int32_t a, std::int32_t b, bool* inserted) {
  if (a > b) std::swap(a, b);
  if (2 * (dense_.size() + 1) > index_.size()) grow();
  const std::uint64_t k = key(a, b);
  std::uint32_t s = slotOf(k);
  for (;; s = (s + 1) & mask_) {
    const std::int32_t i = index_[s];
    if (i == kEmpty) break;
    if (key(dense_[i].proxy_a, dense_[i].proxy_b) == k) {
      if (inserted) *inserted = false;
      return &dense_[i];
    }
  }
  index_[s] = static_cast<std::int32_t>(dense_.size());
  ProxyPair pair;
  pair.proxy_a = a;
  pair.proxy_b = b;
  dense_.push_back(pair);
  if (inserted) *inserted = true;
  return &dense_.back();
}

void PairTable::eraseAt(int i) {
  // 1. Remove dense position i from the index with backward-shift deletion.
  const std::uint64_t k = key(dense_[i].proxy_a, dense_[i].proxy_b);
  std::uint32_t hole = slotOf(k);
  while (index_[hole] != i) hole = (hole + 1) & mask_;
  for (std::uint32_t s = (hole + 1) & mask_;; s = (s + 1) & mask_) {
    const std::int32_t j = index_[s];
    if (j == kEmpty) break;
    const std::uint32_t home = slotOf(key(dense_[j].proxy_a, dense_[j].proxy_b));
    // Move j into the hole unless its home lies cyclically in (hole, s].
    const bool home_between = hole <= s ? (hole < home && home <= s) : (hole < home || home <= s);
    if (!home_between) {
      index_[hole] = j;
      hole = s;
    }
  }
  index_[hole] = kEmpty;

  // 2. Fill the dense hole with the last pair and repoint its index slot.
  const int last = static_cast<int>(dense_.size()) - 1;
  if (i != last) {
    const std::uint64_t lk = key(dense_[last].proxy_a, dense_[last].proxy_b);
    std::uint32_t s = slotOf(lk);
    while (index_[s] != last) s = (s + 1) & mask_;
    index_[s] = i;
    dense_[i] = dense_[last];
  }
  dense_.pop_back();
}

void PairTable::clear() {
  dense_.clear();
  std::fill(index_.begin(), index_.end(), kEmpty);
}

void PairTable::reserve(std::size_t pairs) {
  if (2 * pairs <= index_.size()) return;
  std::uint32_t size = static_cast<std::uint32_t>(index_.size());
  while (size < 2 * pairs) size <<= 1;
  index_.assign(size, kEmpty);
  mask_ = size - 1;
  for (std::int32_t i = 0; i < static_cast<std::int32_t>(dense_.size()); ++i) {
    std::uint32_t s = slotOf(keyAt(i));
    while (index_[s] != kEmpty) s = (s + 1) & mask_;
    index_[s] = i;
  }
  dense_.reserve(index_.size() / 2);
}

void PairTable::grow() {
  index_.assign(index_.size() * 2, kEmpty);
  mask_ = static_cast<std::uint32_t>(index_.size() - 1);
  for (std::int32_t i = 0; i < static_cast<std::int32_t>(dense_.size()); ++i) {
    std::uint32_t s = slotOf(key(dense_[i].proxy_a, dense_[i].proxy_b));
    while (index_[s] != kEmpty) s = (s + 1) & mask_;
    index_[s] = i;
  }
  dense_.reserve(index_.size() / 2);
}

}  // namespace workspace_proximity
