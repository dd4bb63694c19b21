#include "interp/node_pool.h"

#include <atomic>
#include <mutex>
#include <new>

#include "sched/huge_pages.h"

#if defined(__SANITIZE_ADDRESS__)
#define EPSRAY_POOL_OFF 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define EPSRAY_POOL_OFF 1
#endif
#endif

namespace epsray::node_pool {

namespace {

constexpr std::size_t grain = 64;
std::atomic<std::size_t> chunk_count{0};

#ifndef EPSRAY_POOL_OFF
constexpr std::size_t classes = 32, chunk_bytes = huge_page_bytes;

struct free_block {
  free_block* next;
};

// One class's freed blocks. `count` lets allocate skip the lock while the list is empty,
// as it is through a walk with no memory budget (only lost publish races free blocks).
struct class_list {
  std::mutex m;
  free_block* head = nullptr;
  std::atomic<std::size_t> count{0};
};

class_list lists[classes];

// Each thread carves its own chunk, so fresh blocks need no lock.
thread_local char* bump = nullptr;
thread_local char* bump_end = nullptr;

// The size class of a block of `bytes` (1 to classes), or 0: operator new's.
std::size_t class_of(std::size_t bytes) {
  const std::size_t c = (bytes + grain - 1) / grain;
  return c <= classes ? c : 0;
}

char* new_chunk() {
  void* p = take_huge(chunk_bytes);
  chunk_count.fetch_add(1, std::memory_order_relaxed);
  return static_cast<char*>(p);
}
#endif

}  // namespace

void* allocate(std::size_t bytes) {
#ifdef EPSRAY_POOL_OFF
  return ::operator new(bytes, std::align_val_t(grain));
#else
  const std::size_t c = class_of(bytes);
  if (c == 0) return ::operator new(bytes, std::align_val_t(grain));
  class_list& l = lists[c - 1];
  if (l.count.load(std::memory_order_relaxed) > 0) {
    std::lock_guard<std::mutex> g(l.m);
    if (free_block* b = l.head) {
      l.head = b->next;
      l.count.fetch_sub(1, std::memory_order_relaxed);
      return b;
    }
  }
  const std::size_t size = c * grain;
  if (std::size_t(bump_end - bump) < size) {  // the old chunk's tail, under 2 KB, stays unused
    bump = new_chunk();
    bump_end = bump + chunk_bytes;
  }
  void* p = bump;
  bump += size;
  return p;
#endif
}

void deallocate(void* p, std::size_t bytes) noexcept {
  if (!p) return;
#ifdef EPSRAY_POOL_OFF
  (void)bytes;
  ::operator delete(p, std::align_val_t(grain));
#else
  const std::size_t c = class_of(bytes);
  if (c == 0) {
    ::operator delete(p, std::align_val_t(grain));
    return;
  }
  class_list& l = lists[c - 1];
  std::lock_guard<std::mutex> g(l.m);
  free_block* b = static_cast<free_block*>(p);
  b->next = l.head;
  l.head = b;
  l.count.fetch_add(1, std::memory_order_relaxed);
#endif
}

bool pooled() {
#ifdef EPSRAY_POOL_OFF
  return false;
#else
  return true;
#endif
}

std::size_t chunks() { return chunk_count.load(std::memory_order_relaxed); }

}  // namespace epsray::node_pool
