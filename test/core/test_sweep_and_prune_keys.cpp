// The endpoint arrays' full sort (sweep_and_prune_keys, private to the core): a radix sort by
// the 32 high bits that vary over the axis, in steps that the next arrays' build spreads over
// updates, then an insertion pass. Checked against std::sort of the same (key, owner) pairs,
// never against the sort's own output.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "sweep_and_prune_keys.hpp"

namespace sap = workspace_proximity::sap;

namespace {

struct Axis {
  std::vector<std::uint64_t> keys;
  std::vector<std::uint32_t> owners;
};

// An endpoint array (sentinels at both ends) of `n` endpoints at coordinates drawn by `draw`,
// in a random order, each with its own owner code.
template <typename Draw>
Axis makeAxis(std::size_t n, std::mt19937_64* rng, Draw draw) {
  Axis a;
  a.keys.push_back(sap::kLowSentinel);
  a.owners.push_back(sap::kSentinelOwner);
  for (std::size_t i = 0; i < n; ++i) {
    const double x = draw(*rng);
    a.keys.push_back(i % 2 == 0 ? sap::lower64(x) : sap::upper64(x));
    a.owners.push_back(static_cast<std::uint32_t>(i));
  }
  a.keys.push_back(sap::kHighSentinel);
  a.owners.push_back(sap::kSentinelOwner);
  return a;
}

// The oracle: the same (key, owner) pairs by std::sort (owners break ties, so that the two
// orders compare whatever either does with equal keys).
std::vector<std::pair<std::uint64_t, std::uint32_t>> sortedPairs(const Axis& a) {
  std::vector<std::pair<std::uint64_t, std::uint32_t>> p;
  for (std::size_t i = 0; i < a.keys.size(); ++i) p.emplace_back(a.keys[i], a.owners[i]);
  std::sort(p.begin(), p.end());
  return p;
}

void expectSortedLike(const Axis& sorted, const std::vector<std::pair<std::uint64_t, std::uint32_t>>& oracle) {
  ASSERT_EQ(sorted.keys.size(), oracle.size());
  for (std::size_t i = 0; i < oracle.size(); ++i) ASSERT_EQ(sorted.keys[i], oracle[i].first) << "position " << i;
  // The owners travelled with their keys: the pairs are the oracle's, up to ties.
  EXPECT_EQ(sortedPairs(sorted), oracle);
  EXPECT_EQ(sorted.owners.front(), sap::kSentinelOwner);
  EXPECT_EQ(sorted.owners.back(), sap::kSentinelOwner);
}

// The steps one at a time, the insertion pass in chunks of `chunk` work: as the next arrays'
// build does across updates. Returns the insertion pass' swaps.
std::int64_t sortInSteps(Axis* a, sap::SortScratch* scratch, std::int64_t chunk, int* steps) {
  sap::RadixSteps job;
  sap::beginRadixSort(a->keys, &job);
  *steps = 0;
  while (job.next != sap::RadixSteps::Step::kDone) {
    sap::radixSortStep(&a->keys, &a->owners, scratch, &job);
    ++*steps;
  }
  std::int64_t swaps = 0;
  std::size_t pos = 1;
  while (pos < a->keys.size() - 1) pos = sap::insertionSortFrom(&a->keys, &a->owners, pos, chunk, &swaps, {1, 0, 5});
  return swaps;
}

}  // namespace

TEST(SweepAndPruneKeys, RadixSortInStepsEqualsStdSortAtEverySize) {
  // Sizes on both sides of each switch: insertion only (<= 48 endpoints), two and three 8-bit
  // passes (256, 4 096), two and three 11-bit passes (65 536).
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> coordinate(-50.0, 50.0);
  for (std::size_t n : {1u, 48u, 49u, 255u, 256u, 2000u, 4095u, 4096u, 20000u, 65535u, 65536u, 70000u}) {
    SCOPED_TRACE(n);
    const Axis given = makeAxis(n, &rng, [&](std::mt19937_64& r) { return coordinate(r); });
    const auto oracle = sortedPairs(given);
    sap::SortScratch scratch;
    scratch.reserve(n / 2 + 1);
    Axis stepped = given;
    int steps = 0;
    const std::int64_t swaps = sortInSteps(&stepped, &scratch, 97, &steps);
    expectSortedLike(stepped, oracle);
    // The radix steps did the sorting: with prefixes 6-8 bits finer than the endpoints' count,
    // few endpoints share one, and the insertion pass moves little (a random order would take
    // about n^2 / 4 swaps).
    if (n > 48) {
      EXPECT_LT(swaps, static_cast<std::int64_t>(n / 8)) << "insertion pass swaps";
    }
    // Prefixes, counts, a scatter per pass, the gather; none at all for a small axis.
    const int passes = n < 256 ? 2 : n < 4096 ? 3 : n < 65536 ? 2 : 3;
    EXPECT_EQ(steps, n <= 48 ? 0 : 3 + passes);
    Axis whole = given;
    sap::sortEndpoints(&whole.keys, &whole.owners, &scratch);
    expectSortedLike(whole, oracle);
  }
}

TEST(SweepAndPruneKeys, RadixSortInStepsHandlesTiesCrowdsAndInfiniteBounds) {
  std::mt19937_64 rng(11);
  sap::SortScratch scratch;
  int steps = 0;
  // Many endpoints on a few coordinates (every prefix shared: the insertion pass sorts).
  {
    std::uniform_int_distribution<int> few(0, 3);
    Axis a = makeAxis(3000, &rng, [&](std::mt19937_64& r) { return 0.25 * few(r); });
    const auto oracle = sortedPairs(a);
    sortInSteps(&a, &scratch, 1, &steps);
    expectSortedLike(a, oracle);
  }
  // A crowd near zero and a few far away (keys spaced over many octaves, both signs).
  {
    std::normal_distribution<double> crowd(0.0, 1e-3);
    std::uniform_int_distribution<int> pick(0, 99);
    Axis a = makeAxis(5000, &rng, [&](std::mt19937_64& r) { return pick(r) == 0 ? 1e6 * crowd(r) * 1e3 : crowd(r); });
    const auto oracle = sortedPairs(a);
    sortInSteps(&a, &scratch, 1000, &steps);
    expectSortedLike(a, oracle);
  }
  // Infinite bounds (a span that is not finite: the keys' own high bits).
  {
    const double inf = std::numeric_limits<double>::infinity();
    std::uniform_real_distribution<double> coordinate(-10.0, 10.0);
    std::uniform_int_distribution<int> pick(0, 49);
    Axis a = makeAxis(1000, &rng, [&](std::mt19937_64& r) {
      const int k = pick(r);
      return k == 0 ? -inf : k == 1 ? inf : coordinate(r);
    });
    const auto oracle = sortedPairs(a);
    sortInSteps(&a, &scratch, 50, &steps);
    expectSortedLike(a, oracle);
  }
}

// What insertionSortFrom() counts, against counts taken from the unsorted array alone: an
// endpoint moves when a larger key stands anywhere before it (it is not a running maximum),
// and the places moved are the inversions (brute force, every pair). A slice resumed after
// any amount of work counts the same in total.
TEST(SweepAndPruneKeys, InsertionSortCountsPositionsMovesAndPlacesAsWeighted) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> coordinate(-5.0, 5.0);
  std::uniform_int_distribution<int> few(0, 3);
  std::normal_distribution<double> nudge(0.0, 1e-9);
  const sap::InsertionWork weights{2, 12, 1};
  for (int scene = 0; scene < 3; ++scene) {
    SCOPED_TRACE(scene);
    // Random order; four heights a few nanometres apart (the walkers' upright extents: one
    // radix prefix each); nearly in order (each key a little off its place).
    Axis given = scene == 0 ? makeAxis(600, &rng, [&](std::mt19937_64& r) { return coordinate(r); })
                 : scene == 1 ? makeAxis(600, &rng, [&](std::mt19937_64& r) { return 0.5 * few(r) + nudge(r); })
                              : makeAxis(600, &rng, [&](std::mt19937_64&) { return 0.0; });
    if (scene == 2) {
      for (std::size_t i = 1; i + 1 < given.keys.size(); ++i) {
        given.keys[i] = sap::lower64(0.01 * static_cast<double>(i) + (i % 7 == 0 ? 0.05 : 0.0));
      }
    }
    const std::size_t last = given.keys.size() - 1;
    std::int64_t inversions = 0, moved = 0;
    for (std::size_t i = 1; i < last; ++i) {
      bool larger_before = false;
      for (std::size_t j = 1; j < i; ++j) {
        inversions += given.keys[j] > given.keys[i];
        larger_before = larger_before || given.keys[j] > given.keys[i];
      }
      moved += larger_before;
    }
    const std::int64_t positions = static_cast<std::int64_t>(last - 1);
    const std::int64_t expected = weights.position * positions + weights.moved * moved + weights.swap * inversions;
    for (std::int64_t chunk : {std::numeric_limits<std::int64_t>::max(), std::int64_t{1}, std::int64_t{37}}) {
      Axis a = given;
      std::int64_t swaps = 0, work = 0;
      std::size_t pos = 1;
      while (pos < last) pos = sap::insertionSortFrom(&a.keys, &a.owners, pos, chunk, &swaps, weights, &work);
      expectSortedLike(a, sortedPairs(given));
      EXPECT_EQ(swaps, inversions);
      EXPECT_EQ(work, expected) << "chunk " << chunk;
    }
  }
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}

// moveProxy's coasting test, two bounds at a time (tightKeysInside), against the general path
// it stands for: Aabb::valid() (written out here), lower64() / upper64() and the keys'
// unsigned order. Bounds and enlarged keys from special values (signed zeros, denormals, the
// largest finite, infinities, NaNs of both signs) and their neighbours one key either side,
// each axis in turn with the other two comfortably inside.
namespace {

std::uint64_t bitsOf(double d) {
  std::uint64_t b;
  std::memcpy(&b, &d, sizeof b);
  return b;
}

struct Reference {
  bool inside = false, equal = false;
  std::uint64_t tight[6] = {};
};

Reference referenceInside(const double* lower, const double* upper, const std::uint64_t* const enlarged[3]) {
  Reference r;
  bool valid = true, inside = true, equal = true;
  for (int axis = 0; axis < 3; ++axis) {
    valid = valid && std::isfinite(lower[axis]) && std::isfinite(upper[axis]) && lower[axis] <= upper[axis];
    r.tight[2 * axis] = sap::lower64(lower[axis]);
    r.tight[2 * axis + 1] = sap::upper64(upper[axis]);
    inside = inside && enlarged[axis][0] <= r.tight[2 * axis] && r.tight[2 * axis + 1] <= enlarged[axis][1];
    equal = equal && enlarged[axis][0] == r.tight[2 * axis] && r.tight[2 * axis + 1] == enlarged[axis][1];
  }
  r.inside = valid && inside;
  r.equal = equal;
  return r;
}

std::vector<double> specialValues() {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const double tiny = std::numeric_limits<double>::denorm_min();
  const double big = std::numeric_limits<double>::max();
  const double least = std::numeric_limits<double>::min();
  std::vector<double> v{0.0, -0.0, tiny, -tiny, 2 * tiny, -2 * tiny, 3 * tiny, -3 * tiny, least, -least,
                        1.0, -1.0, 0.5, -0.5, 1.5, -1.5, big, -big, kInf, -kInf,
                        std::numeric_limits<double>::quiet_NaN(), -std::numeric_limits<double>::quiet_NaN()};
  // Neighbours one ulp either side (both parities of the mantissa's last bit).
  for (double x : {1.0, -1.0, 1.5, -1.5, least, -least, big, -big}) {
    v.push_back(std::nextafter(x, kInf));
    v.push_back(std::nextafter(x, -kInf));
  }
  return v;
}

void checkAgainstReference(const double* lower, const double* upper, const std::uint64_t* const enlarged[3]) {
  const Reference want = referenceInside(lower, upper, enlarged);
  std::uint64_t tight[6];
  for (std::uint64_t& t : tight) t = 0x5A5A5A5A5A5A5A5Aull;  // untouched unless inside
  bool equal = false;
  const double six[6] = {lower[0], lower[1], lower[2], upper[0], upper[1], upper[2]};
  const bool inside = sap::tightKeysInside(six, enlarged, tight, &equal);
#if defined(__SSE2__)
  ASSERT_EQ(inside, want.inside) << lower[0] << " " << upper[0] << " " << lower[1] << " " << upper[1] << " "
                                 << lower[2] << " " << upper[2];
  if (inside) {
    for (int i = 0; i < 6; ++i) ASSERT_EQ(tight[i], want.tight[i]) << i;
    ASSERT_EQ(equal, want.equal);
  } else {
    for (std::uint64_t t : tight) ASSERT_EQ(t, 0x5A5A5A5A5A5A5A5Aull);
  }
#else
  ASSERT_FALSE(inside);  // no fast path: the general path decides
  (void)want;
#endif
}

}  // namespace

TEST(SweepAndPruneKeys, CoastingFastPathDecidesAsTheGeneralPath) {
  const std::vector<double> values = specialValues();
  // Enlarged keys from pairs a <= b, infinite ones too (a room that overflowed), and the keys
  // just beside them (an enlarged upper key of -denorm_min is one no double has: -0 maps to
  // +0's key).
  std::vector<std::pair<std::uint64_t, std::uint64_t>> enlarged;
  for (double a : values) {
    for (double b : values) {
      if (!(a <= b)) continue;
      enlarged.emplace_back(sap::lower64(a), sap::upper64(b));
    }
  }
  std::vector<double> probes = values;
  for (const auto& [lo, hi] : enlarged) {
    for (std::uint64_t key : {lo, hi}) {
      for (std::uint64_t k : {key - 2, key - 1, key, key + 1, key + 2}) probes.push_back(sap::unsortable64(k));
    }
  }
  std::sort(probes.begin(), probes.end(), [](double x, double y) { return bitsOf(x) < bitsOf(y); });
  probes.erase(std::unique(probes.begin(), probes.end(), [](double x, double y) { return bitsOf(x) == bitsOf(y); }),
               probes.end());
  // The other axes' enlarged keys and bounds: inside, not equal.
  const std::uint64_t wide[2] = {sap::lower64(-10.0), sap::upper64(10.0)};
  std::mt19937_64 rng(11);
  std::size_t calls = 0, inside = 0;
  for (const auto& [elo, ehi] : enlarged) {
    const std::uint64_t tested[2] = {elo, ehi};
    // Every probe pair would be 2.5 M calls per enlarged pair: a random sample of them, and
    // every probe as lower and as upper with the other at the enlarged bound's own double.
    for (int axis = 0; axis < 3; ++axis) {
      const std::uint64_t* e[3] = {wide, wide, wide};
      e[axis] = tested;
      double lower[3] = {-1.0, -1.0, -1.0}, upper[3] = {1.0, 1.0, 1.0};
      for (double p : probes) {
        lower[axis] = p;
        upper[axis] = sap::unsortable64(ehi);
        checkAgainstReference(lower, upper, e);
        lower[axis] = sap::unsortable64(elo);
        upper[axis] = p;
        checkAgainstReference(lower, upper, e);
        calls += 2;
      }
      std::uniform_int_distribution<std::size_t> pick(0, probes.size() - 1);
      for (int i = 0; i < 64; ++i) {
        lower[axis] = probes[pick(rng)];
        upper[axis] = probes[pick(rng)];
        checkAgainstReference(lower, upper, e);
        ++calls;
      }
      // Equal on every axis.
      for (int k = 0; k < 3; ++k) {
        lower[k] = sap::unsortable64(e[k][0]);
        upper[k] = sap::unsortable64(e[k][1]);
      }
      checkAgainstReference(lower, upper, e);
      inside += referenceInside(lower, upper, e).inside;
      ++calls;
    }
  }
  // Random boxes among random enlarged ones a few keys apart (every axis at once).
  std::uniform_real_distribution<double> coord(-2.0, 2.0);
  std::uniform_int_distribution<int> step(-3, 3);
  for (int trial = 0; trial < 200000; ++trial) {
    std::uint64_t keys[3][2];
    const std::uint64_t* e[3];
    double lower[3], upper[3];
    for (int axis = 0; axis < 3; ++axis) {
      double a = coord(rng), b = coord(rng);
      if (a > b) std::swap(a, b);
      keys[axis][0] = sap::lower64(a);
      keys[axis][1] = sap::upper64(b);
      e[axis] = keys[axis];
      lower[axis] = sap::unsortable64(keys[axis][0] + static_cast<std::uint64_t>(step(rng)));
      upper[axis] = sap::unsortable64(keys[axis][1] + static_cast<std::uint64_t>(step(rng)));
    }
    checkAgainstReference(lower, upper, e);
    inside += referenceInside(lower, upper, e).inside;
    ++calls;
  }
  EXPECT_GT(calls, 500000u);
  EXPECT_GT(inside, 5000u);  // both answers asked often
}
