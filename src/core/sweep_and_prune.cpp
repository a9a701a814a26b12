#include "workspace_proximity/sweep_and_prune.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace workspace_proximity {
namespace {

constexpr std::uint32_t kSentinelOwner = 0xFFFFFFFFu;
constexpr std::uint32_t kLowSentinel = 0u;
constexpr std::uint32_t kHighSentinel = 0xFFFFFFFFu;

// Order-preserving map float -> uint32: flip all bits of negatives, set the sign of positives.
std::uint32_t sortable(float f) {
  if (f == 0.0f) f = 0.0f;  // -0 and +0 must map to the same key
  std::uint32_t bits;
  std::memcpy(&bits, &f, sizeof bits);
  return (bits & 0x80000000u) ? ~bits : (bits | 0x80000000u);
}

float unsortable(std::uint32_t key) {
  const std::uint32_t bits = (key & 0x80000000u) ? (key & 0x7FFFFFFFu) : ~key;
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

}  // namespace

std::uint32_t SweepAndPrune::lowerKey(double value) {
  float f = static_cast<float>(value);
  if (static_cast<double>(f) > value) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  // Clearing the low bit moves the key down (outward) and tags it as a lower endpoint.
  return sortable(f) & ~1u;
}

std::uint32_t SweepAndPrune::upperKey(double value) {
  float f = static_cast<float>(value);
  if (static_cast<double>(f) < value) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return sortable(f) | 1u;
}

double SweepAndPrune::keyValue(std::uint32_t key) { return static_cast<double>(unsortable(key)); }

SweepAndPrune::SweepAndPrune(const SweepAndPruneConfig& config)
    : config_(config), pairs_(config.initial_pair_capacity) {
  const std::size_t capacity = static_cast<std::size_t>(std::max(config.initial_proxy_capacity, 1));
  proxies_.reserve(capacity);
  is_new_.reserve(capacity);
  active_pos_.reserve(capacity);
  active_.reserve(capacity);
  active_new_.reserve(capacity);
  pending_insert_.reserve(capacity);
  pending_remove_.reserve(capacity);
  scratch_.reserve(2 * capacity + 2);
  began_.reserve(static_cast<std::size_t>(config.initial_pair_capacity));
  ended_.reserve(static_cast<std::size_t>(config.initial_pair_capacity));
  for (int axis = 0; axis < 3; ++axis) {
    keys_[axis].reserve(2 * capacity + 2);
    owners_[axis].reserve(2 * capacity + 2);
    // Sentinels end every inner loop without a bounds check.
    keys_[axis] = {kLowSentinel, kHighSentinel};
    owners_[axis] = {kSentinelOwner, kSentinelOwner};
  }
}

SweepAndPrune::ProxyId SweepAndPrune::createProxy(const Aabb& bounds, std::uint32_t user_data) {
  if (!bounds.valid()) throw std::invalid_argument("SweepAndPrune::createProxy: invalid bounds");
  ProxyId id;
  if (free_list_ >= 0) {
    id = free_list_;
    free_list_ = proxies_[id].next_free;
  } else {
    id = static_cast<ProxyId>(proxies_.size());
    proxies_.emplace_back();
    is_new_.push_back(0);
    active_pos_.push_back(-1);
  }
  Proxy& p = proxies_[id];
  for (int axis = 0; axis < 3; ++axis) {
    p.lower[axis] = lowerKey(bounds.lower[axis]);
    p.upper[axis] = upperKey(bounds.upper[axis]);
    p.lower_index[axis] = -1;
    p.upper_index[axis] = -1;
  }
  p.user = user_data;
  p.next_free = -1;
  p.state = ProxyState::kPendingInsert;
  p.pending_remove = false;
  pending_insert_.push_back(id);
  return id;
}

void SweepAndPrune::destroyProxy(ProxyId id) {
  Proxy& p = proxies_.at(static_cast<std::size_t>(id));
  if (p.state == ProxyState::kFree || p.pending_remove) {
    throw std::invalid_argument("SweepAndPrune::destroyProxy: proxy is not live");
  }
  if (p.state == ProxyState::kPendingInsert) {
    // Never entered the arrays: forget it now.
    auto it = std::find(pending_insert_.begin(), pending_insert_.end(), id);
    *it = pending_insert_.back();
    pending_insert_.pop_back();
    p.state = ProxyState::kFree;
    p.next_free = free_list_;
    free_list_ = id;
    return;
  }
  // Live: it keeps its slot (so the id is not reused) until update() takes it out.
  p.pending_remove = true;
  pending_remove_.push_back(id);
}

void SweepAndPrune::moveProxy(ProxyId id, const Aabb& bounds) {
  if (!bounds.valid()) throw std::invalid_argument("SweepAndPrune::moveProxy: invalid bounds");
  Proxy& p = proxies_.at(static_cast<std::size_t>(id));
  if (p.state == ProxyState::kFree || p.pending_remove) {
    throw std::invalid_argument("SweepAndPrune::moveProxy: proxy is not live");
  }
  for (int axis = 0; axis < 3; ++axis) {
    p.lower[axis] = lowerKey(bounds.lower[axis]);
    p.upper[axis] = upperKey(bounds.upper[axis]);
    if (p.state == ProxyState::kLive) {
      // The arrays are re-sorted in update(); only the key values change here.
      keys_[axis][p.lower_index[axis]] = p.lower[axis];
      keys_[axis][p.upper_index[axis]] = p.upper[axis];
    }
  }
}

Aabb SweepAndPrune::storedBounds(ProxyId id) const {
  const Proxy& p = proxies_.at(static_cast<std::size_t>(id));
  Aabb box;
  for (int axis = 0; axis < 3; ++axis) {
    box.lower[axis] = keyValue(p.lower[axis]);
    box.upper[axis] = keyValue(p.upper[axis]);
  }
  return box;
}

void SweepAndPrune::setIndex(std::uint32_t owner, int axis, std::int32_t index) {
  Proxy& p = proxies_[owner >> 1];
  if (owner & 1u) {
    p.upper_index[axis] = index;
  } else {
    p.lower_index[axis] = index;
  }
}

void SweepAndPrune::beginPair(std::int32_t a, std::int32_t b) {
  bool inserted = false;
  ProxyPair* pair = pairs_.insert(a, b, &inserted);
  if (inserted) {
    pair->user = 0;
    pair->stamp = epoch_;
    began_.push_back(*pair);
  }
}

void SweepAndPrune::endPair(std::int32_t a, std::int32_t b) {
  ProxyPair removed;
  if (pairs_.erase(a, b, &removed)) ended_.push_back(removed);
}

void SweepAndPrune::update() {
  stats_ = SweepAndPruneStats();
  began_.clear();
  ended_.clear();

  applyRemovals();

  const std::size_t began_mark = began_.size();
  const std::size_t ended_mark = ended_.size();
  if (!sortAxes()) {
    // Motion too large for insertion sort to pay: undo its partial pair changes, then
    // sort from scratch and diff the new pair set against the old one.
    rollBack(began_mark, ended_mark);
    rebuild();
    stats_.rebuilt = true;
  }

  insertPending();
}

void SweepAndPrune::applyRemovals() {
  if (pending_remove_.empty()) return;
  stats_.removed = static_cast<int>(pending_remove_.size());

  // Their pairs end. Walk backwards so eraseAt's swap-with-last never skips a pair.
  std::vector<ProxyPair>& dense = pairs_.mutablePairs();
  for (int i = static_cast<int>(dense.size()) - 1; i >= 0; --i) {
    if (proxies_[dense[i].proxy_a].pending_remove || proxies_[dense[i].proxy_b].pending_remove) {
      ended_.push_back(dense[i]);
      pairs_.eraseAt(i);
    }
  }

  // Compact the endpoint arrays in one pass per axis.
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<std::uint32_t>& keys = keys_[axis];
    std::vector<std::uint32_t>& owners = owners_[axis];
    const std::size_t last = keys.size() - 1;
    std::size_t w = 1;
    for (std::size_t r = 1; r < last; ++r) {
      const std::uint32_t owner = owners[r];
      if (proxies_[owner >> 1].pending_remove) continue;
      keys[w] = keys[r];
      owners[w] = owner;
      setIndex(owner, axis, static_cast<std::int32_t>(w));
      ++w;
    }
    keys[w] = kHighSentinel;
    owners[w] = kSentinelOwner;
    keys.resize(w + 1);
    owners.resize(w + 1);
  }

  for (ProxyId id : pending_remove_) {
    Proxy& p = proxies_[id];
    p.state = ProxyState::kFree;
    p.pending_remove = false;
    p.next_free = free_list_;
    free_list_ = id;
    --live_count_;
  }
  pending_remove_.clear();
}

bool SweepAndPrune::sortAxes() {
  const double n = 2.0 * live_count_;
  const std::int64_t budget =
      static_cast<std::int64_t>(std::max(64.0, config_.rebuild_factor * n * std::log2(n + 2.0)));
  std::int64_t swaps = 0;

  for (int axis = 0; axis < 3; ++axis) {
    std::uint32_t* key = keys_[axis].data();
    std::uint32_t* owner = owners_[axis].data();
    const int last = static_cast<int>(keys_[axis].size()) - 1;  // high sentinel
    for (int i = 2; i < last; ++i) {
      const std::uint32_t k = key[i];
      if (key[i - 1] <= k) continue;  // already in place: the common case for small motion

      const std::uint32_t o = owner[i];
      const std::uint32_t o_upper = o & 1u;
      const std::int32_t p = static_cast<std::int32_t>(o >> 1);
      int j = i;
      do {
        const std::uint32_t o2 = owner[j - 1];
        if ((o2 & 1u) != o_upper) {
          const std::int32_t q = static_cast<std::int32_t>(o2 >> 1);
          if (o_upper == 0u) {
            // p's lower passes below q's upper: they may now overlap on every axis.
            if (overlaps(proxies_[p], proxies_[q])) beginPair(p, q);
          } else {
            // p's upper passes below q's lower: separated on this axis.
            endPair(p, q);
          }
        }
        key[j] = key[j - 1];
        owner[j] = o2;
        setIndex(o2, axis, j);
        --j;
      } while (key[j - 1] > k);  // the low sentinel (key 0) stops this
      key[j] = k;
      owner[j] = o;
      setIndex(o, axis, j);

      swaps += i - j;
      if (swaps > budget) {
        stats_.swaps = swaps;
        return false;
      }
    }
  }
  stats_.swaps = swaps;
  return true;
}

void SweepAndPrune::rollBack(std::size_t began_mark, std::size_t ended_mark) {
  for (std::size_t i = began_mark; i < began_.size(); ++i) {
    pairs_.erase(began_[i].proxy_a, began_[i].proxy_b);
  }
  for (std::size_t i = ended_mark; i < ended_.size(); ++i) {
    ProxyPair* pair = pairs_.insert(ended_[i].proxy_a, ended_[i].proxy_b, nullptr);
    *pair = ended_[i];
  }
  began_.resize(began_mark);
  ended_.resize(ended_mark);
}

void SweepAndPrune::rebuild() {
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<std::uint32_t>& keys = keys_[axis];
    std::vector<std::uint32_t>& owners = owners_[axis];
    const std::size_t last = keys.size() - 1;
    scratch_.clear();
    for (std::size_t i = 1; i < last; ++i) {
      scratch_.push_back((static_cast<std::uint64_t>(keys[i]) << 32) | owners[i]);
    }
    std::sort(scratch_.begin(), scratch_.end());
    for (std::size_t i = 1; i < last; ++i) {
      keys[i] = static_cast<std::uint32_t>(scratch_[i - 1] >> 32);
      owners[i] = static_cast<std::uint32_t>(scratch_[i - 1]);
      setIndex(owners[i], axis, static_cast<std::int32_t>(i));
    }
  }

  // Stamp every pair the sweep finds; unstamped survivors ended.
  ++epoch_;
  sweepForPairs(false);
  std::vector<ProxyPair>& dense = pairs_.mutablePairs();
  for (int i = static_cast<int>(dense.size()) - 1; i >= 0; --i) {
    if (dense[i].stamp != epoch_) {
      ended_.push_back(dense[i]);
      pairs_.eraseAt(i);
    }
  }
}

void SweepAndPrune::insertPending() {
  if (pending_insert_.empty()) return;
  const std::size_t k = pending_insert_.size();
  stats_.inserted = static_cast<int>(k);

  // Batched insertion: sort the new endpoints, then merge them into each axis from the back,
  // so one insertion costs O(n + k log k) instead of k passes of insertion sort.
  for (int axis = 0; axis < 3; ++axis) {
    scratch_.clear();
    for (ProxyId id : pending_insert_) {
      const std::uint32_t owner = static_cast<std::uint32_t>(id) << 1;
      scratch_.push_back((static_cast<std::uint64_t>(proxies_[id].lower[axis]) << 32) | owner);
      scratch_.push_back((static_cast<std::uint64_t>(proxies_[id].upper[axis]) << 32) | owner | 1u);
    }
    std::sort(scratch_.begin(), scratch_.end());

    std::vector<std::uint32_t>& keys = keys_[axis];
    std::vector<std::uint32_t>& owners = owners_[axis];
    const std::size_t old_size = keys.size();
    keys.resize(old_size + 2 * k);
    owners.resize(old_size + 2 * k);
    std::int64_t i = static_cast<std::int64_t>(old_size) - 2;  // last old real endpoint
    std::int64_t j = static_cast<std::int64_t>(2 * k) - 1;
    std::int64_t w = static_cast<std::int64_t>(keys.size()) - 2;
    keys.back() = kHighSentinel;
    owners.back() = kSentinelOwner;
    while (j >= 0) {
      const std::uint32_t new_key = static_cast<std::uint32_t>(scratch_[j] >> 32);
      if (i >= 1 && keys[i] > new_key) {
        keys[w] = keys[i];
        owners[w] = owners[i];
        --i;
      } else {
        keys[w] = new_key;
        owners[w] = static_cast<std::uint32_t>(scratch_[j]);
        --j;
      }
      setIndex(owners[w], axis, static_cast<std::int32_t>(w));
      --w;
    }
  }

  for (ProxyId id : pending_insert_) {
    proxies_[id].state = ProxyState::kLive;
    is_new_[id] = 1;
  }
  live_count_ += static_cast<int>(k);

  sweepForPairs(true);

  for (ProxyId id : pending_insert_) is_new_[id] = 0;
  pending_insert_.clear();
}

void SweepAndPrune::foundPair(std::int32_t a, std::int32_t b, bool rebuild) {
  if (!rebuild) {
    beginPair(a, b);
    return;
  }
  bool inserted = false;
  ProxyPair* pair = pairs_.insert(a, b, &inserted);
  pair->stamp = epoch_;
  if (inserted) {
    pair->user = 0;
    began_.push_back(*pair);
  }
}

void SweepAndPrune::sweepForPairs(bool only_new) {
  // One sweep along x with lists of open intervals. With only_new, old proxies are
  // tested only against new ones, so an insertion costs O(n + k * overlaps).
  const std::uint32_t* owner = owners_[0].data();
  const std::size_t last = owners_[0].size() - 1;
  active_.clear();
  active_new_.clear();
  for (std::size_t i = 1; i < last; ++i) {
    const std::uint32_t o = owner[i];
    const std::int32_t p = static_cast<std::int32_t>(o >> 1);
    const bool p_new = only_new && is_new_[p];
    std::vector<std::int32_t>& list = p_new ? active_new_ : active_;
    if ((o & 1u) == 0u) {
      const Proxy& pp = proxies_[p];
      if (!only_new || p_new) {
        for (std::int32_t q : active_) {
          if (overlaps(pp, proxies_[q])) foundPair(p, q, !only_new);
        }
      }
      for (std::int32_t q : active_new_) {
        if (overlaps(pp, proxies_[q])) foundPair(p, q, !only_new);
      }
      active_pos_[p] = static_cast<std::int32_t>(list.size());
      list.push_back(p);
    } else {
      const std::int32_t pos = active_pos_[p];
      const std::int32_t moved = list.back();
      list[pos] = moved;
      active_pos_[moved] = pos;
      list.pop_back();
    }
  }
}

}  // namespace workspace_proximity
