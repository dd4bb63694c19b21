// The lock-free insert-only map behind the unique-ray hash (sched/ray_hash.h).
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace epsray
