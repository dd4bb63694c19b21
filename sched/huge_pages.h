// Large blocks asked for as transparent huge pages. On this project's VM a page fault costs
// about 6 us, and a cold frame first-touches tens of megabytes of hash slots and linetree
// nodes 4 KB at a time: a sixth of the art room's first frame went to the kernel. A block
// taken here is 2 MB aligned and advised MADV_HUGEPAGE, so the kernel may back it with 2 MB
// pages (one fault each) where transparent huge pages are on "always" or "madvise"; where
// they are off the advice is ignored and the block is plain memory. The memory is not
// touched here: pages are still faulted in as they are first written.
// Knows nothing of rendering.
#pragma once
#include <sys/mman.h>

#include <algorithm>
#include <cstddef>
#include <cstdlib>
#include <new>

namespace epsray {

constexpr std::size_t huge_page_bytes = std::size_t(2) << 20;

// At least `bytes`, rounded up to whole 2 MB pages; free with release_huge.
inline void* take_huge(std::size_t bytes) {
  const std::size_t size =
      std::max<std::size_t>(1, (bytes + huge_page_bytes - 1) / huge_page_bytes) * huge_page_bytes;
  void* p = std::aligned_alloc(huge_page_bytes, size);
  if (!p) throw std::bad_alloc();
#ifdef MADV_HUGEPAGE
  madvise(p, size, MADV_HUGEPAGE);  // advice only
#endif
  return p;
}

inline void release_huge(void* p) noexcept { std::free(p); }

struct huge_deleter {
  void operator()(void* p) const noexcept { release_huge(p); }
};

}  // namespace epsray
