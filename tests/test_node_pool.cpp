// The node pool (engine/interp/node_pool.h) and huge-page blocks (sched/huge_pages.h):
// blocks are distinct, aligned and writable from any thread, a freed block is handed out
// again before fresh memory (what keeps a memory budget's evictions useful), and the
// linetrees' own types come from it.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <set>
#include <thread>
#include <vector>

#include "interp/interpolant.h"
#include "interp/linetree.h"
#include "interp/node_pool.h"
#include "sched/huge_pages.h"

namespace epsray {
namespace {

bool aligned(const void* p, std::uintptr_t a) { return reinterpret_cast<std::uintptr_t>(p) % a == 0; }

TEST(NodePool, BlocksAreDistinctAlignedAndWritable) {
  std::vector<std::pair<void*, std::size_t>> blocks;
  for (std::size_t bytes : {1u, 63u, 64u, 65u, 520u, 1032u, 2048u, 2049u, 5000u})
    for (int k = 0; k < 50; ++k) {
      void* p = node_pool::allocate(bytes);
      ASSERT_NE(p, nullptr);
      EXPECT_TRUE(aligned(p, 64)) << bytes;
      std::memset(p, k & 0xff, bytes);
      blocks.emplace_back(p, bytes);
    }
  std::set<void*> distinct;
  for (auto& [p, bytes] : blocks) distinct.insert(p);
  EXPECT_EQ(distinct.size(), blocks.size());
  for (auto& [p, bytes] : blocks) node_pool::deallocate(p, bytes);
  node_pool::deallocate(nullptr, 64);  // as delete of a null pointer: nothing
}

TEST(NodePool, FreedBlocksAreHandedOutAgainBeforeFreshMemory) {
  if (!node_pool::pooled()) GTEST_SKIP() << "AddressSanitizer build: blocks come from operator new";
  constexpr int n = 5000;  // 5000 x 576 bytes: more than one 2 MB chunk
  std::vector<void*> first(n);
  for (void*& p : first) p = node_pool::allocate(sizeof(interpolant));
  for (void* p : first) node_pool::deallocate(p, sizeof(interpolant));
  const std::size_t chunks = node_pool::chunks();
  std::set<void*> again;
  for (int i = 0; i < n; ++i) again.insert(node_pool::allocate(sizeof(interpolant)));
  EXPECT_EQ(node_pool::chunks(), chunks) << "no fresh chunk while freed blocks of the class remain";
  EXPECT_EQ(again, std::set<void*>(first.begin(), first.end()));
  for (void* p : again) node_pool::deallocate(p, sizeof(interpolant));
}

TEST(NodePool, ThreadsAllocateAndFreeConcurrently) {
  constexpr int threads = 4, rounds = 20, per_round = 500;
  std::vector<std::thread> pool;
  std::vector<int> bad(threads, 0);
  for (int t = 0; t < threads; ++t)
    pool.emplace_back([t, &bad] {
      std::vector<std::uint32_t*> mine;
      for (int r = 0; r < rounds; ++r) {
        for (int i = 0; i < per_round; ++i) {
          auto* p = static_cast<std::uint32_t*>(node_pool::allocate(256));
          for (int w = 0; w < 64; ++w) p[w] = std::uint32_t(t * 1000003 + i);
          mine.push_back(p);
        }
        // Check what this thread wrote, then free half: another thread may take those.
        for (std::size_t i = 0; i < mine.size(); ++i)
          for (int w = 0; w < 64; ++w) bad[size_t(t)] += mine[i][w] != mine[i][0];
        for (std::size_t i = mine.size() / 2; i < mine.size(); ++i) node_pool::deallocate(mine[i], 256);
        mine.resize(mine.size() / 2);
      }
      for (std::uint32_t* p : mine) node_pool::deallocate(p, 256);
    });
  for (std::thread& th : pool) th.join();
  for (int t = 0; t < threads; ++t) EXPECT_EQ(bad[size_t(t)], 0) << "thread " << t << "'s blocks were overwritten";
}

TEST(NodePool, LinetreeTypesComeFromThePool) {
  if (!node_pool::pooled()) GTEST_SKIP() << "AddressSanitizer build: blocks come from operator new";
  const std::size_t before = node_pool::chunks();
  std::vector<interpolant*> made;
  // More than any freed blocks of the class (the test above leaves 5000) and a chunk besides.
  for (int i = 0; i < 10000 + 2 * int(huge_page_bytes / sizeof(interpolant)); ++i) made.push_back(new interpolant);
  EXPECT_GT(node_pool::chunks(), before) << "interpolants fill pool chunks";
  for (interpolant* ip : made) delete ip;
  lt_node root;
  lt_node* kids = subdivide(root, split_all);
  EXPECT_TRUE(aligned(kids, alignof(lt_node)));
  EXPECT_EQ(child_count(split_all), 16);
  for (int k = 0; k < 16; ++k) EXPECT_EQ(kids[k].parent_axes, split_all);
}

TEST(HugePages, BlocksAreWholeAlignedPages) {
  void* p = take_huge(1);
  EXPECT_TRUE(aligned(p, huge_page_bytes));
  std::memset(p, 7, huge_page_bytes);  // the whole rounded-up page is the caller's
  release_huge(p);
  void* q = take_huge(3 * huge_page_bytes + 1);
  EXPECT_TRUE(aligned(q, huge_page_bytes));
  static_cast<char*>(q)[4 * huge_page_bytes - 1] = 1;
  release_huge(q);
}

}  // namespace
}  // namespace epsray
