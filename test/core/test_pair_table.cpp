// Tests of PairTable against an ordered std::map model (the oracle) under long random
// sequences of insert / find / erase / eraseAt / clear, including growth.

#include <algorithm>
#include <cstdint>
#include <iterator>
#include <map>
#include <random>
#include <set>
#include <utility>

#include <gtest/gtest.h>

#include "workspace_proximity/pair_table.hpp"

using workspace_proximity::PairTable;
using workspace_proximity::ProxyPair;

namespace {

using Key = std::pair<int, int>;
Key ordered(int a, int b) { return a < b ? Key(a, b) : Key(b, a); }

// Full comparison of the table with the model: same size, same set of pairs, each stored
// once with proxy_a < proxy_b and with the user value the model remembers; find() returns
// the stored record for both argument orders.
void expectSameAsModel(PairTable& table, const std::map<Key, std::uint32_t>& model) {
  ASSERT_EQ(table.size(), static_cast<int>(model.size()));
  ASSERT_EQ(table.pairs().size(), model.size());
  std::set<Key> seen;
  for (const ProxyPair& p : table.pairs()) {
    ASSERT_LT(p.proxy_a, p.proxy_b);
    Key k(p.proxy_a, p.proxy_b);
    ASSERT_TRUE(seen.insert(k).second) << "duplicate " << p.proxy_a << "," << p.proxy_b;
    auto it = model.find(k);
    ASSERT_NE(it, model.end()) << "unexpected " << p.proxy_a << "," << p.proxy_b;
    EXPECT_EQ(p.user, it->second);
  }
  for (const auto& [k, user] : model) {
    ProxyPair* f = table.find(k.first, k.second);
    ProxyPair* g = table.find(k.second, k.first);
    ASSERT_NE(f, nullptr);
    EXPECT_EQ(f, g);
    EXPECT_EQ(f->proxy_a, k.first);
    EXPECT_EQ(f->proxy_b, k.second);
    EXPECT_EQ(f->user, user);
  }
}

// One random run of `ops` operations on ids in [0, id_range). `max_size` receives the
// largest size the table reached.
void runRandomSequence(std::uint64_t seed, int initial_capacity, int ops, int id_range,
                       int check_every, int* max_size) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> id(0, id_range - 1);
  std::uniform_int_distribution<int> op(0, 99);
  PairTable table(initial_capacity);
  std::map<Key, std::uint32_t> model;
  std::uint32_t next_user = 1;
  // Bias toward growth for the first part of the run, toward shrinking later, so both
  // a large table and an emptied one are exercised.
  for (int i = 0; i < ops; ++i) {
    int o = op(rng);
    int insert_share = i < ops / 2 ? 60 : 30;
    int a = id(rng), b = id(rng);
    if (a == b) b = (b + 1) % id_range;
    Key k = ordered(a, b);
    if (o < insert_share) {
      bool inserted = false;
      ProxyPair* p = table.insert(a, b, &inserted);
      ASSERT_NE(p, nullptr);
      EXPECT_EQ(p->proxy_a, k.first);
      EXPECT_EQ(p->proxy_b, k.second);
      bool expect_new = model.count(k) == 0;
      ASSERT_EQ(inserted, expect_new) << "insert(" << a << "," << b << ") at op " << i;
      if (inserted) {
        p->user = next_user++;
        model[k] = p->user;
      } else {
        EXPECT_EQ(p->user, model[k]);  // an existing record is returned untouched
      }
    } else if (o < insert_share + 15) {
      ProxyPair* p = table.find(a, b);
      auto it = model.find(k);
      if (it == model.end()) {
        EXPECT_EQ(p, nullptr);
      } else {
        ASSERT_NE(p, nullptr);
        EXPECT_EQ(p->proxy_a, k.first);
        EXPECT_EQ(p->proxy_b, k.second);
        EXPECT_EQ(p->user, it->second);
      }
    } else if (o < insert_share + 35) {
      ProxyPair removed;
      bool was = table.erase(a, b, &removed);
      auto it = model.find(k);
      ASSERT_EQ(was, it != model.end()) << "erase(" << a << "," << b << ") at op " << i;
      if (was) {
        EXPECT_EQ(removed.proxy_a, k.first);
        EXPECT_EQ(removed.proxy_b, k.second);
        EXPECT_EQ(removed.user, it->second);
        model.erase(it);
      }
      EXPECT_EQ(table.find(a, b), nullptr);
    } else if (o < insert_share + 36 && i % 7 == 0) {
      // Rare: erase without the optional output argument.
      bool was = table.erase(b, a);
      ASSERT_EQ(was, model.erase(k) == 1);
    } else if (o < 99 || i % 50 != 0) {
      if (table.size() == 0) continue;
      int pos = std::uniform_int_distribution<int>(0, table.size() - 1)(rng);
      ProxyPair victim = table.pairs()[pos];
      table.eraseAt(pos);
      ASSERT_EQ(model.erase(Key(victim.proxy_a, victim.proxy_b)), 1u);
      EXPECT_EQ(table.find(victim.proxy_a, victim.proxy_b), nullptr);
    } else {
      table.clear();
      model.clear();
      EXPECT_EQ(table.size(), 0);
      EXPECT_EQ(table.find(a, b), nullptr);
    }
    ASSERT_EQ(table.size(), static_cast<int>(model.size())) << "after op " << i;
    *max_size = std::max(*max_size, table.size());
    if (i % check_every == 0) {
      expectSameAsModel(table, model);
      if (::testing::Test::HasFatalFailure()) return;
    }
  }
  expectSameAsModel(table, model);
}

}  // namespace

TEST(PairTable, KeyIsSymmetric) {
  EXPECT_EQ(PairTable::key(3, 7), PairTable::key(7, 3));
  EXPECT_NE(PairTable::key(3, 7), PairTable::key(3, 8));
  EXPECT_NE(PairTable::key(1, 2), PairTable::key(2, 3));
}

TEST(PairTable, InsertReversedFindsOrdered) {
  PairTable t(4);
  bool inserted = false;
  ProxyPair* p = t.insert(9, 2, &inserted);
  ASSERT_NE(p, nullptr);
  EXPECT_TRUE(inserted);
  EXPECT_EQ(p->proxy_a, 2);
  EXPECT_EQ(p->proxy_b, 9);
  p->user = 42;
  ProxyPair* q = t.insert(2, 9, &inserted);
  EXPECT_FALSE(inserted);
  EXPECT_EQ(q, t.find(9, 2));
  EXPECT_EQ(q->user, 42u);
  EXPECT_EQ(t.size(), 1);
  EXPECT_EQ(t.find(2, 8), nullptr);
}

TEST(PairTable, EraseAbsentReturnsFalse) {
  PairTable t(8);
  EXPECT_FALSE(t.erase(1, 2));
  bool inserted = false;
  t.insert(1, 2, &inserted);
  EXPECT_TRUE(t.erase(2, 1));
  EXPECT_FALSE(t.erase(1, 2));
  EXPECT_EQ(t.size(), 0);
}

TEST(PairTable, GrowthPastInitialCapacityKeepsEveryPair) {
  // Every pair of 0..119 (7140 pairs) into a table sized for 2, then erase half by key.
  PairTable t(2);
  std::map<Key, std::uint32_t> model;
  std::uint32_t u = 0;
  for (int a = 0; a < 120; ++a) {
    for (int b = a + 1; b < 120; ++b) {
      bool inserted = false;
      ProxyPair* p = (a + b) % 2 ? t.insert(a, b, &inserted) : t.insert(b, a, &inserted);
      ASSERT_TRUE(inserted);
      p->user = ++u;
      model[Key(a, b)] = u;
    }
  }
  expectSameAsModel(t, model);
  for (auto it = model.begin(); it != model.end();) {
    if ((it->first.first * 31 + it->first.second) % 2 == 0) {
      ASSERT_TRUE(t.erase(it->first.second, it->first.first));
      it = model.erase(it);
    } else {
      ++it;
    }
  }
  expectSameAsModel(t, model);
}

TEST(PairTable, LargeIdsAndClusteredKeys) {
  // Ids far apart and ids that differ only in high bits stress the hash.
  PairTable t(16);
  std::map<Key, std::uint32_t> model;
  std::uint32_t u = 0;
  for (int i = 0; i < 2000; ++i) {
    int a = (i % 50) << 16, b = ((i / 50) << 20) + 1 + (i % 3);
    if (a == b) continue;
    bool inserted = false;
    ProxyPair* p = t.insert(a, b, &inserted);
    Key k = ordered(a, b);
    ASSERT_EQ(inserted, model.count(k) == 0);
    if (inserted) {
      p->user = ++u;
      model[k] = u;
    }
  }
  expectSameAsModel(t, model);
}

TEST(PairTable, ClearThenReuse) {
  PairTable t(4);
  std::map<Key, std::uint32_t> model;
  bool inserted = false;
  for (int round = 0; round < 5; ++round) {
    t.clear();
    model.clear();
    for (int i = 0; i < 300; ++i) {
      ProxyPair* p = t.insert(i, i + 1 + round, &inserted);
      ASSERT_TRUE(inserted);
      p->user = static_cast<std::uint32_t>(i * 10 + round);
      model[Key(i, i + 1 + round)] = p->user;
    }
    expectSameAsModel(t, model);
  }
}

// The main oracle test: 100k random operations per run against the std::map model.
TEST(PairTable, RandomOperationsMatchModelSmallIdRange) {
  // Few ids: heavy reuse, many duplicate inserts and hits.
  int max_size = 0;
  runRandomSequence(1, 4, 100000, 24, 997, &max_size);
  EXPECT_GT(max_size, 200);  // close to all 276 pairs of 24 ids
}

TEST(PairTable, RandomOperationsMatchModelWideIdRange) {
  // Many ids: the table grows to thousands of pairs past its initial capacity of 1.
  int max_size = 0;
  runRandomSequence(2, 1, 100000, 400, 4999, &max_size);
  EXPECT_GT(max_size, 5000);
}

TEST(PairTable, RandomChurnInTinyIndexMatchesModel) {
  // At most 7 pairs live, drawn from 64 ids (2016 distinct keys), so the index stays at its
  // smallest size: clusters often wrap past its last slot, exercising backward-shift deletion
  // across the wrap. Fully checked after every operation.
  std::mt19937_64 rng(4);
  std::uniform_int_distribution<int> id(0, 63), coin(0, 2);
  PairTable table(1);
  std::map<Key, std::uint32_t> model;
  std::uint32_t next_user = 1;
  for (int i = 0; i < 100000; ++i) {
    if (model.size() < 7 && coin(rng) != 0) {
      int a = id(rng), b = id(rng);
      if (a == b) continue;
      bool inserted = false;
      ProxyPair* p = table.insert(a, b, &inserted);
      ASSERT_EQ(inserted, model.count(ordered(a, b)) == 0) << "op " << i;
      if (inserted) model[ordered(a, b)] = p->user = next_user++;
    } else if (!model.empty()) {
      if (coin(rng) == 0) {
        int pos = std::uniform_int_distribution<int>(0, table.size() - 1)(rng);
        ProxyPair victim = table.pairs()[pos];
        table.eraseAt(pos);
        ASSERT_EQ(model.erase(Key(victim.proxy_a, victim.proxy_b)), 1u);
      } else {
        auto it = model.begin();
        std::advance(it, std::uniform_int_distribution<int>(0, model.size() - 1)(rng));
        ASSERT_TRUE(table.erase(it->first.second, it->first.first)) << "op " << i;
        model.erase(it);
      }
    }
    expectSameAsModel(table, model);
    if (::testing::Test::HasFatalFailure()) return;
  }
}

TEST(PairTable, RandomOperationsMatchModelDefaultCapacity) {
  int max_size = 0;
  runRandomSequence(3, 1024, 100000, 120, 2999, &max_size);
  EXPECT_GT(max_size, 1024);  // past the initial capacity
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
