#include "sweep_and_prune_keys.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace workspace_proximity {
namespace sap {
namespace {

// LSD radix sort of 64-bit items by the bits from 32 up, kDigit bits per pass (stable): the
// digits of every pass counted in one read of the items, then one scatter per pass (a pass in
// which every item has the same digit is skipped). The counts are laid out pass after pass,
// 2^kDigit each.
// (The number of passes a template argument: the loop over them unrolled. With it a runtime
// count, the counting read took a third more instructions.)
template <int kDigit, int kPasses>
void countDigits(const std::uint64_t* in, std::size_t n, std::uint32_t* count) {
  constexpr std::uint64_t kMask = (std::uint64_t{1} << kDigit) - 1;
  std::memset(count, 0, sizeof(std::uint32_t) * (kMask + 1) * kPasses);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint64_t x = in[i];
    for (int pass = 0; pass < kPasses; ++pass) ++count[(kMask + 1) * pass + ((x >> (32 + kDigit * pass)) & kMask)];
  }
}

template <int kDigit>
void countDigits(const std::uint64_t* in, std::size_t n, int passes, std::uint32_t* count) {
  if (passes == 2) {
    countDigits<kDigit, 2>(in, n, count);
  } else {
    countDigits<kDigit, 3>(in, n, count);
  }
}

// One pass from src to dst; false (nothing moved) when every item has the same digit.
template <int kDigit>
bool scatterPass(const std::uint64_t* src, std::uint64_t* dst, std::size_t n, int pass, std::uint32_t* count) {
  constexpr std::uint64_t kMask = (std::uint64_t{1} << kDigit) - 1;
  const int shift = 32 + kDigit * pass;
  std::uint32_t* c = count + (kMask + 1) * pass;
  if (c[(src[0] >> shift) & kMask] == n) return false;
  std::uint32_t sum = 0;
  for (std::uint64_t d = 0; d <= kMask; ++d) {
    const std::uint32_t t = c[d];
    c[d] = sum;
    sum += t;
  }
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint64_t x = src[i];
    dst[c[(x >> shift) & kMask]++] = x;
  }
  return true;
}

// Each endpoint's prefix above its index: the coordinate's place in [lo, hi] in
// 2^prefix_bits steps (monotone in the key). Keys themselves are spaced logarithmically: on an
// axis that crosses zero, or spans many octaves, their high bits would leave most coordinates
// in a few prefixes, and the insertion pass after the radix sort would do the sorting.
void writePrefixes(const std::vector<std::uint64_t>& keys, int prefix_bits, std::vector<std::uint64_t>* out) {
  const std::size_t n = keys.size() - 2;
  std::uint64_t lo = keys[1], hi = keys[1];
  for (std::size_t i = 2; i <= n; ++i) {
    lo = std::min(lo, keys[i]);
    hi = std::max(hi, keys[i]);
  }
  std::vector<std::uint64_t>& items = *out;
  items.resize(n);
  const double x_lo = unsortable64(lo), span = unsortable64(hi) - x_lo;
  if (std::isfinite(span) && span > 0.0) {
    const double top = std::ldexp(1.0, prefix_bits) - 1.0;
    const double scale = top / span;
    for (std::size_t i = 0; i < n; ++i) {
      const double v = (unsortable64(keys[i + 1]) - x_lo) * scale;
      const std::uint64_t prefix = static_cast<std::uint64_t>(v < top ? (v > 0.0 ? v : 0.0) : top);
      items[i] = (prefix << 32) | i;
    }
  } else {
    // Infinite bounds: the keys' own high bits.
    const std::uint64_t range = hi - lo;
    const int width = range == 0 ? 0 : 64 - __builtin_clzll(range);
    const int shift = std::max(0, width - prefix_bits);
    for (std::size_t i = 0; i < n; ++i) items[i] = (((keys[i + 1] - lo) >> shift) << 32) | i;
  }
}

// Keys and owners in the order of the sorted items, by trading buffers with the scratch (both
// reserved alike): no copy back.
void gatherSorted(const std::uint64_t* sorted, std::vector<std::uint64_t>& keys, std::vector<std::uint32_t>& owners,
                  SortScratch& scratch) {
  const std::size_t n = keys.size() - 2;
  std::vector<std::uint64_t>& tmp_keys = scratch.tmp_keys;
  std::vector<std::uint32_t>& tmp_owners = scratch.tmp_owners;
  tmp_keys.resize(n + 2);
  tmp_owners.resize(n + 2);
  tmp_keys[0] = kLowSentinel;
  tmp_owners[0] = kSentinelOwner;
  tmp_keys[n + 1] = kHighSentinel;
  tmp_owners[n + 1] = kSentinelOwner;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t from = static_cast<std::uint32_t>(sorted[i]) + 1;
    tmp_keys[i + 1] = keys[from];
    tmp_owners[i + 1] = owners[from];
  }
  keys.swap(tmp_keys);
  owners.swap(tmp_owners);
}

}  // namespace

std::size_t insertionSortFrom(std::vector<std::uint64_t>* keys, std::vector<std::uint32_t>* owners,
                              std::size_t from, std::int64_t max_work, std::int64_t* swaps,
                              const InsertionWork& weights, std::int64_t* work_done) {
  // Plain insertion sort, no pair events.
  std::uint64_t* key = keys->data();
  std::uint32_t* owner = owners->data();
  const std::size_t last = keys->size() - 1;  // the high sentinel
  std::int64_t work = 0, places = 0;
  std::size_t i = std::max<std::size_t>(from, 1);
  for (; i < last && work < max_work; ++i) {
    work += weights.position;
    const std::uint64_t k = key[i];
    if (key[i - 1] <= k) continue;
    const std::uint32_t o = owner[i];
    std::size_t j = i;
    do {
      key[j] = key[j - 1];
      owner[j] = owner[j - 1];
      --j;
    } while (key[j - 1] > k);
    key[j] = k;
    owner[j] = o;
    work += weights.moved + weights.swap * static_cast<std::int64_t>(i - j);
    places += static_cast<std::int64_t>(i - j);
  }
  *swaps += places;
  if (work_done != nullptr) *work_done += work;
  return i;
}

void SortScratch::reserve(std::size_t slots) {
  items.reserve(2 * slots);
  items2.reserve(2 * slots);
  tmp_keys.reserve(2 * slots + 2);
  tmp_owners.reserve(2 * slots + 2);
  counts.resize(3 << 11);  // three passes of 11-bit digits at most
}

void beginRadixSort(const std::vector<std::uint64_t>& keys, RadixSteps* job) {
  // Prefix bits: about 6-8 more than log2(n), so that few endpoints share a prefix. 8-bit
  // digits below 4 096 endpoints (16 or 24 bits), 11-bit digits from there (22 or 32 bits: one
  // pass fewer; the counts still fit in L1).
  const std::size_t n = keys.size() - 2;
  job->endpoints = n;
  job->pass = 0;
  job->in_second = false;
  job->wide = n >= 4096;
  job->passes = n < 256 ? 2 : n < 4096 ? 3 : n < 65536 ? 2 : 3;
  // Small axes go to the insertion pass directly.
  job->next = n <= 48 ? RadixSteps::Step::kDone : RadixSteps::Step::kPrefixes;
}

bool radixSortStep(std::vector<std::uint64_t>* keys, std::vector<std::uint32_t>* owners,
                   SortScratch* scratch, RadixSteps* job) {
  using Step = RadixSteps::Step;
  const std::size_t n = job->endpoints;
  switch (job->next) {
    case Step::kPrefixes:
      writePrefixes(*keys, std::min(32, (job->wide ? 11 : 8) * job->passes), &scratch->items);
      scratch->items2.resize(n);
      if (scratch->counts.size() < (std::size_t{3} << 11)) scratch->counts.resize(std::size_t{3} << 11);
      job->next = Step::kCounts;
      break;
    case Step::kCounts:
      if (job->wide) countDigits<11>(scratch->items.data(), n, job->passes, scratch->counts.data());
      else countDigits<8>(scratch->items.data(), n, job->passes, scratch->counts.data());
      job->next = Step::kScatter;
      break;
    case Step::kScatter: {
      const std::uint64_t* src = job->in_second ? scratch->items2.data() : scratch->items.data();
      std::uint64_t* dst = job->in_second ? scratch->items.data() : scratch->items2.data();
      const bool moved = job->wide ? scatterPass<11>(src, dst, n, job->pass, scratch->counts.data())
                                   : scatterPass<8>(src, dst, n, job->pass, scratch->counts.data());
      job->in_second ^= moved;
      if (++job->pass == job->passes) job->next = Step::kGather;
      break;
    }
    case Step::kGather:
      gatherSorted(job->in_second ? scratch->items2.data() : scratch->items.data(), *keys, *owners, *scratch);
      job->next = Step::kDone;
      break;
    case Step::kDone:
      break;
  }
  return job->next == Step::kDone;
}

void sortEndpoints(std::vector<std::uint64_t>* keys, std::vector<std::uint32_t>* owners,
                   SortScratch* scratch) {
  RadixSteps job;
  beginRadixSort(*keys, &job);
  while (!radixSortStep(keys, owners, scratch, &job)) {
  }
  std::int64_t swaps = 0;
  insertionSortFrom(keys, owners, 1, std::numeric_limits<std::int64_t>::max(), &swaps);
}

}  // namespace sap
}  // namespace workspace_proximity
