#pragma once
/// SweepAndPrune's keys and the full sort of an endpoint array (private to the core).
///
/// A bound (double, m) is stored as a 64-bit key in the same order; the low bit is 0 for lower
/// and 1 for upper endpoints, so that touching boxes overlap. An endpoint array of one axis is
/// two parallel arrays, keys and owners (owner = proxy << 1 | is_upper), with a sentinel at
/// each end: key 0 first, all ones last.

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace workspace_proximity {
namespace sap {

constexpr std::uint32_t kSentinelOwner = 0xFFFFFFFFu;
constexpr std::uint64_t kLowSentinel = 0u;
constexpr std::uint64_t kHighSentinel = ~std::uint64_t{0};
constexpr std::uint64_t kSign64 = 0x8000000000000000ull;

/// Order-preserving map double -> uint64: flip all bits of negatives, set the sign of
/// positives; without branches on the sign.
inline std::uint64_t sortable64(double d) {
  std::uint64_t bits;
  std::memcpy(&bits, &d, sizeof bits);
  bits = bits == kSign64 ? 0u : bits;  // -0 and +0 must map to the same key
  const std::uint64_t negative = static_cast<std::uint64_t>(static_cast<std::int64_t>(bits) >> 63);
  return bits ^ (negative | kSign64);
}

/// Key of a lower (low bit 0) and of an upper (low bit 1) bound.
inline std::uint64_t lower64(double d) { return sortable64(d) & ~std::uint64_t{1}; }
inline std::uint64_t upper64(double d) { return sortable64(d) | 1u; }

/// The double a key stands for (the tag bit read back as part of the mantissa).
inline double unsortable64(std::uint64_t key) {
  // Keys with the sign bit came from positives (clear it), the others from negatives (flip
  // every bit); without branches.
  const std::uint64_t flip = kSign64 | static_cast<std::uint64_t>(static_cast<std::int64_t>(~key) >> 63);
  const std::uint64_t bits = key ^ flip;
  double d;
  std::memcpy(&d, &bits, sizeof d);
  return d;
}

/// The 32 high bits of a key as a signed integer in the same order.
inline std::int32_t prefix32(std::uint64_t key) {
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(key >> 32) ^ 0x80000000u);
}

/// Scratch of the sorts, kept between updates so that steady-state updates allocate nothing.
struct SortScratch {
  std::vector<std::uint64_t> items, items2;  // radix sort items (also the insertion's merge)
  std::vector<std::uint64_t> tmp_keys;
  std::vector<std::uint32_t> tmp_owners;
  std::vector<std::uint32_t> counts;  // radix sort: each pass' digit counts
  void reserve(std::size_t slots);
};

/// A radix sort of one endpoint array by the 32 most significant bits that vary over the axis
/// (sortEndpoints' first part) cut into steps, so that the next arrays' build can spread it
/// over updates: each endpoint's prefix, the digits of every pass counted, one scatter per
/// pass, the gather of keys and owners in that order. insertionSortFrom() from position 1
/// then finishes it (endpoints that share a prefix). Between steps nothing else may touch the
/// array or the scratch.
struct RadixSteps {
  enum class Step : std::uint8_t { kPrefixes, kCounts, kScatter, kGather, kDone };
  Step next = Step::kDone;
  int pass = 0;             ///< kScatter: the pass
  int passes = 0;           ///< digits of the prefix (2 or 3)
  bool wide = false;        ///< 11-bit digits (else 8)
  bool in_second = false;   ///< the order so far is in SortScratch::items2 (else items)
  std::size_t endpoints = 0;  ///< without the sentinels
};
/// Starts a radix sort of `keys` (sentinels in place); an array of at most 48 endpoints is
/// left to the insertion pass (the job is done at once).
void beginRadixSort(const std::vector<std::uint64_t>& keys, RadixSteps* job);
/// Does the job's next step; returns true once the radix part is done.
bool radixSortStep(std::vector<std::uint64_t>* keys, std::vector<std::uint32_t>* owners,
                   SortScratch* scratch, RadixSteps* job);

/// Insertion sort without pair events of one endpoint array (sentinels in place) from position
/// `from` on, the positions before it in order already: stops at the high sentinel or once
/// `max_work` is done (a position counts 1, a swap `swap_work`). Returns the next position to
/// insert; adds the swaps to *swaps. (Resumable: the next arrays sort a slice at a time.)
std::size_t insertionSortFrom(std::vector<std::uint64_t>* keys, std::vector<std::uint32_t>* owners,
                              std::size_t from, std::int64_t max_work, std::int64_t* swaps,
                              std::int64_t swap_work = 1);

/// Sorts one axis' endpoint array (sentinels in place) from scratch: radix sort by the 32
/// most significant bits that vary over the axis, then an insertion pass for the endpoints
/// that share them. No pair events (a rebuild's sweep finds the pairs).
void sortEndpoints(std::vector<std::uint64_t>* keys, std::vector<std::uint32_t>* owners,
                   SortScratch* scratch);

}  // namespace sap
}  // namespace workspace_proximity
