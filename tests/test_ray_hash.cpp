// The lock-free insert-only map behind the unique-ray hash (sched/ray_hash.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <thread>
#include <vector>

#include "sched/ray_hash.h"

namespace epsray {
namespace {

struct mix_hash {
  std::uint64_t operator()(std::uint64_t k) const {
    k ^= k >> 33;
    k *= 0xff51afd7ed558ccdull;
    return k ^ (k >> 33);
  }
};
using map = insert_only_map<std::uint64_t, std::uint64_t, mix_hash>;

std::uint64_t value_of(std::uint64_t k) { return k * 7 + 3; }  // the pure function being cached

TEST(RayHash, FindsWhatWasInserted) {
  map m(1024);
  EXPECT_EQ(m.find(5), nullptr);
  ASSERT_NE(m.insert(5, value_of(5)), nullptr);
  ASSERT_NE(m.find(5), nullptr);
  EXPECT_EQ(*m.find(5), value_of(5));
  // A second insert of the same key returns the first value and stores nothing new.
  EXPECT_EQ(*m.insert(5, 999), value_of(5));
  EXPECT_EQ(m.size(), 1u);
}

TEST(RayHash, FullTableRefusesInsteadOfLooping) {
  map m(16, 4);
  int stored = 0;
  for (std::uint64_t k = 1; k <= 100; ++k) stored += m.insert(k, value_of(k)) != nullptr;
  EXPECT_LE(stored, 16);
  EXPECT_EQ(m.size(), std::size_t(stored));
  for (std::uint64_t k = 1; k <= 100; ++k) {
    if (const std::uint64_t* v = m.find(k)) {
      EXPECT_EQ(*v, value_of(k));
    }
  }
}

TEST(RayHash, RacingThreadsStoreEachKeyOnceWithItsValue) {
  const std::uint64_t keys = 20000;
  map m(1 << 16);
  std::vector<std::thread> threads;
  for (int t = 0; t < 8; ++t)
    threads.emplace_back([&, t] {
      // Every thread inserts every key, in its own order, so writers of one key collide.
      for (std::uint64_t i = 0; i < keys; ++i) {
        std::uint64_t k = 1 + (i * 7919 + std::uint64_t(t) * 104729) % keys;
        if (const std::uint64_t* v = m.find(k)) {
          EXPECT_EQ(*v, value_of(k));
        } else if (const std::uint64_t* p = m.insert(k, value_of(k))) {
          EXPECT_EQ(*p, value_of(k));
        }
      }
    });
  for (std::thread& t : threads) t.join();
  EXPECT_LE(m.size(), keys);  // never a key twice
  std::uint64_t found = 0;
  for (std::uint64_t k = 1; k <= keys; ++k)
    if (const std::uint64_t* v = m.find(k)) {
      ++found;
      EXPECT_EQ(*v, value_of(k));
    }
  EXPECT_EQ(found, m.size());
  EXPECT_GT(found, keys * 99 / 100);  // only an insert racing a writer of the same slot gives up
}

// A table sized for a whole frame that holds a few lines keeps them together at the front
// of its entries' block, whatever their hashes: the memory it touches grows with what it
// holds, not with its capacity.
TEST(RayHash, FewEntriesLieTogetherInAWideTable) {
  struct entry {
    std::uint64_t v[16];  // about a line sample's size
  };
  insert_only_map<std::uint64_t, entry, mix_hash> m(std::size_t(1) << 18);
  std::vector<const entry*> at;
  for (std::uint64_t k = 1; k <= 1000; ++k) {
    entry e{};
    e.v[0] = value_of(k);
    const entry* p = m.insert(k * 0x9e3779b97f4a7c15ull, e);
    ASSERT_NE(p, nullptr);
    at.push_back(p);
  }
  const auto [lo, hi] = std::minmax_element(at.begin(), at.end());
  const std::size_t span = std::size_t(reinterpret_cast<const char*>(*hi) - reinterpret_cast<const char*>(*lo));
  EXPECT_LT(span, 1000 * (sizeof(std::uint64_t) + sizeof(entry)));
  for (std::uint64_t k = 1; k <= 1000; ++k) {
    const entry* p = m.find(k * 0x9e3779b97f4a7c15ull);
    ASSERT_NE(p, nullptr);
    EXPECT_EQ(p->v[0], value_of(k));
  }
}

// for_each visits every published value once; clear forgets them all, and the table takes
// new keys afterwards with their own values (entries are reused from the front).
TEST(RayHash, ForEachAndClear) {
  map m(256);
  for (std::uint64_t k = 1; k <= 100; ++k) ASSERT_NE(m.insert(k, value_of(k)), nullptr);
  std::multiset<std::uint64_t> seen;
  m.for_each([&](std::uint64_t v) { seen.insert(v); });
  ASSERT_EQ(seen.size(), 100u);
  for (std::uint64_t k = 1; k <= 100; ++k) EXPECT_EQ(seen.count(value_of(k)), 1u) << k;
  m.clear();
  EXPECT_EQ(m.size(), 0u);
  for (std::uint64_t k = 1; k <= 100; ++k) EXPECT_EQ(m.find(k), nullptr);
  for (std::uint64_t k = 101; k <= 200; ++k) ASSERT_NE(m.insert(k, value_of(k)), nullptr);
  for (std::uint64_t k = 101; k <= 200; ++k) EXPECT_EQ(*m.find(k), value_of(k));
  for (std::uint64_t k = 1; k <= 100; ++k) EXPECT_EQ(m.find(k), nullptr);
}

}  // namespace
}  // namespace epsray
