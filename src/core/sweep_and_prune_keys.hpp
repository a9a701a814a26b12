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
#include <limits>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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

/// moveProxy's coasting test for a live proxy, its six bounds two at a time (SSE2): when
/// `bounds` (lower x, y, z, then upper x, y, z, m) are valid (-inf < lower <= upper < +inf)
/// and their keys lie within the enlarged keys enlarged[axis][0] (lower) and [1] (upper),
/// writes those keys to `tight` (lower, upper per axis), sets `equal` when they are the
/// enlarged keys, and returns true. Otherwise writes nothing and returns false: the caller takes
/// the general path, which throws or lists an escaper. The same decisions and keys as
/// Aabb::valid(), lower64() and upper64() with the keys' unsigned order, bit for bit
/// (test_sweep_and_prune_keys). Without SSE2 it always returns false.
inline bool tightKeysInside(const double* bounds, const std::uint64_t* const enlarged[3], std::uint64_t* tight,
                            bool* equal) {
#if defined(__SSE2__)
  // The six bounds as they lie, two to a register: (lower x, lower y), (lower z, upper x),
  // (upper y, upper z); the enlarged keys gathered the same way.
  const __m128d zero = _mm_setzero_pd();
  const __m128d a = _mm_add_pd(_mm_loadu_pd(bounds), zero);  // + 0: -0 has +0's key
  const __m128d b = _mm_add_pd(_mm_loadu_pd(bounds + 2), zero);
  const __m128d c = _mm_add_pd(_mm_loadu_pd(bounds + 4), zero);
  // Valid: every bound finite (its magnitude below +inf: a NaN fails), lower <= upper.
  const __m128d magnitude = _mm_castsi128_pd(_mm_set1_epi64x(0x7FFFFFFFFFFFFFFF));
  const __m128d inf = _mm_set1_pd(std::numeric_limits<double>::infinity());
  const auto finite = [&](__m128d v) { return _mm_cmplt_pd(_mm_and_pd(v, magnitude), inf); };
  __m128d valid = _mm_and_pd(_mm_and_pd(finite(a), finite(b)), finite(c));
  valid = _mm_and_pd(valid, _mm_cmple_pd(a, _mm_loadu_pd(bounds + 3)));  // x, y
  // (z: lower z against upper z, lane 0 against lane 1 of c turned round; lane 1 is upper x
  // against upper y, true or not, and is masked out.)
  const int z_ordered = _mm_movemask_pd(_mm_cmple_pd(b, _mm_shuffle_pd(c, c, 1))) & 1;
  // The keys (sortable64: every bit of a negative flipped, a positive's sign set; then the tag
  // bit: 0 for a lower, 1 for an upper).
  const __m128i sign = _mm_set1_epi64x(static_cast<std::int64_t>(kSign64));
  const auto sortable = [&](__m128d v) {
    const __m128i negative = _mm_castpd_si128(_mm_cmplt_pd(v, zero));
    return _mm_xor_si128(_mm_castpd_si128(v), _mm_or_si128(negative, sign));
  };
  const __m128i one = _mm_set_epi64x(1, 1);
  const __m128i ka = _mm_andnot_si128(one, sortable(a));
  const __m128i kb = _mm_or_si128(_mm_andnot_si128(one, sortable(b)), _mm_set_epi64x(1, 0));
  const __m128i kc = _mm_or_si128(sortable(c), one);
  const __m128i ex = _mm_loadu_si128(reinterpret_cast<const __m128i*>(enlarged[0]));
  const __m128i ey = _mm_loadu_si128(reinterpret_cast<const __m128i*>(enlarged[1]));
  const __m128i ez = _mm_loadu_si128(reinterpret_cast<const __m128i*>(enlarged[2]));
  const __m128i ea = _mm_unpacklo_epi64(ex, ey);
  const __m128i eb = _mm_castpd_si128(_mm_move_sd(_mm_castsi128_pd(ex), _mm_castsi128_pd(ez)));
  const __m128i ec = _mm_unpackhi_epi64(ey, ez);
  // Outside: an enlarged lower above its lower, an upper above its enlarged upper (unsigned
  // 64-bit: x > y as ~y > ~x for b's upper lane, so that one comparison serves both lanes; the
  // halves' signed 32-bit comparisons with their signs flipped, the high half deciding unless
  // equal).
  const __m128i flip = _mm_set1_epi32(static_cast<std::int32_t>(0x80000000u));
  const __m128i flip_b = _mm_set_epi32(0x7FFFFFFF, 0x7FFFFFFF, static_cast<std::int32_t>(0x80000000u),
                                       static_cast<std::int32_t>(0x80000000u));
  const auto above = [](__m128i x, __m128i y) {
    const __m128i gt = _mm_cmpgt_epi32(x, y);
    return _mm_or_si128(gt, _mm_and_si128(_mm_cmpeq_epi32(x, y), _mm_slli_epi64(gt, 32)));
  };
  const __m128i outside_a = above(_mm_xor_si128(ea, flip), _mm_xor_si128(ka, flip));
  const __m128i outside_b = above(_mm_xor_si128(eb, flip_b), _mm_xor_si128(kb, flip_b));
  const __m128i outside_c = above(_mm_xor_si128(kc, flip), _mm_xor_si128(ec, flip));
  const __m128i outside = _mm_or_si128(_mm_or_si128(outside_a, outside_b), outside_c);
  // (The high half of each 64-bit lane carries its verdict: movemask_pd reads its sign.)
  const bool ok = (_mm_movemask_pd(valid) == 3) & (z_ordered != 0);
  if (!ok | (_mm_movemask_pd(_mm_castsi128_pd(outside)) != 0)) return false;
  // tight: lower, upper per axis.
  const auto store = [](std::uint64_t* to, __m128d keys) {
    _mm_storeu_si128(reinterpret_cast<__m128i*>(to), _mm_castpd_si128(keys));
  };
  const __m128d da = _mm_castsi128_pd(ka), db = _mm_castsi128_pd(kb), dc = _mm_castsi128_pd(kc);
  store(tight, _mm_move_sd(db, da));            // (lower x, upper x)
  store(tight + 2, _mm_shuffle_pd(da, dc, 1));  // (lower y, upper y)
  store(tight + 4, _mm_move_sd(dc, db));        // (lower z, upper z)
  const __m128i same =
      _mm_and_si128(_mm_and_si128(_mm_cmpeq_epi32(ka, ea), _mm_cmpeq_epi32(kb, eb)), _mm_cmpeq_epi32(kc, ec));
  *equal = _mm_movemask_epi8(same) == 0xFFFF;  // (every half equal: the keys are)
  return true;
#else
  (void)bounds, (void)enlarged, (void)tight, (void)equal;
  return false;
#endif
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

/// What insertionSortFrom() counts as work: each position it reads, each endpoint it moves
/// (the branch that ends its move guesses wrong once), each place one moves by (a shift of a
/// key and an owner along memory it has just read).
struct InsertionWork {
  std::int64_t position = 1;
  std::int64_t moved = 0;
  std::int64_t swap = 1;
};
/// Insertion sort without pair events of one endpoint array (sentinels in place) from position
/// `from` on, the positions before it in order already: stops at the high sentinel or once
/// `max_work` is done (counted with `weights`). Returns the next position to insert; adds the
/// swaps to *swaps and, when given, the work done to *work_done. (Resumable: the next arrays
/// sort a slice at a time.)
std::size_t insertionSortFrom(std::vector<std::uint64_t>* keys, std::vector<std::uint32_t>* owners,
                              std::size_t from, std::int64_t max_work, std::int64_t* swaps,
                              const InsertionWork& weights = InsertionWork(), std::int64_t* work_done = nullptr);

/// Sorts one axis' endpoint array (sentinels in place) from scratch: radix sort by the 32
/// most significant bits that vary over the axis, then an insertion pass for the endpoints
/// that share them. No pair events (a rebuild's sweep finds the pairs).
void sortEndpoints(std::vector<std::uint64_t>* keys, std::vector<std::uint32_t>* owners,
                   SortScratch* scratch);

}  // namespace sap
}  // namespace workspace_proximity
