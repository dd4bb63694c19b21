#include "tile_queue.h"

#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/partitioner.h>

#include <algorithm>

#include "cycle_clock.h"

namespace epsray {

namespace {
struct alignas(64) thread_span {  // one cache line each: only its own thread writes it
  std::uint64_t first = ~std::uint64_t(0), last = 0;
};
}  // namespace

phase_times run_tiles(workers& pool, const std::vector<std::uint32_t>& order, const std::function<void(size_t)>& fn) {
  const int n = pool.threads();
  std::vector<thread_span> spans(size_t(n) + 1);
  std::atomic<size_t> next{0};
  const std::uint64_t t0 = cycle_now();
  pool.run([&] {
    // One task per thread, each a loop over the shared counter: a task that starts after
    // the tiles ran out does nothing.
    tbb::parallel_for(0, n, [&](int) {
      const int slot = std::clamp(tbb::this_task_arena::current_thread_index(), 0, n);
      thread_span& s = spans[size_t(slot)];
      for (size_t k; (k = next.fetch_add(1, std::memory_order_relaxed)) < order.size();) {
        const std::uint64_t c0 = cycle_now();
        s.first = std::min(s.first, c0);
        fn(order[k]);
        s.last = cycle_now();
      }
    }, tbb::simple_partitioner());
  });
  const std::uint64_t t1 = cycle_now();
  const double tick_ms = ticks_per_ms();
  phase_times out;
  out.wall_ms = double(t1 - t0) / tick_ms;
  for (int i = 0; i < n; ++i) {
    const thread_span& s = spans[size_t(i)];
    const bool took = s.last != 0;
    out.join_ms += double((took ? s.first : t1) - t0) / tick_ms / n;
    out.tail_ms += double(took ? t1 - s.last : 0) / tick_ms / n;
  }
  return out;
}

}  // namespace epsray
