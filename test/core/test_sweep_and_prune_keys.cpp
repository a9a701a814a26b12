// The endpoint arrays' full sort (sweep_and_prune_keys, private to the core): a radix sort by
// the 32 high bits that vary over the axis, in steps that the next arrays' build spreads over
// updates, then an insertion pass. Checked against std::sort of the same (key, owner) pairs,
// never against the sort's own output.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
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
  while (pos < a->keys.size() - 1) pos = sap::insertionSortFrom(&a->keys, &a->owners, pos, chunk, &swaps, 5);
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
    if (n > 48) EXPECT_LT(swaps, static_cast<std::int64_t>(n / 8)) << "insertion pass swaps";
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

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
