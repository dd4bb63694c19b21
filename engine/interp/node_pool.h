// Memory for linetree nodes and interpolants. A cold frame builds tens of megabytes of
// them, and where a page fault is dear (this project's VM: about 6 us each, a sixth of the
// art room's first frame in the kernel) touching fresh 4 KB pages one by one costs more
// than the cells' arithmetic. The pool takes 2 MB chunks, asks for them as transparent huge
// pages (madvise; a no-op where the kernel has them off), and carves them into size
// classes of 64 bytes. A freed block goes on its class's list and is handed out again
// before any fresh memory, so a memory budget's evictions make room for new cells as
// malloc's did. Chunks are kept for the process. Under AddressSanitizer the pool steps
// aside (plain operator new), so freed nodes stay poisoned for the sanitizer build.
#pragma once
#include <cstddef>

namespace epsray::node_pool {

// Any thread. Blocks are 64-byte aligned; sizes over 2 KB go to operator new.
void* allocate(std::size_t bytes);
// Any thread, with the size given to allocate.
void deallocate(void* p, std::size_t bytes) noexcept;

// Whether blocks come from the pool (false under AddressSanitizer), and the chunks taken
// so far: for tests.
bool pooled();
std::size_t chunks();

}  // namespace epsray::node_pool
