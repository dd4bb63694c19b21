#include "workers.h"

#include <oneapi/tbb/parallel_for.h>

#include <thread>

namespace epsray {

int hardware_threads() {
  unsigned n = std::thread::hardware_concurrency();
  return n ? int(n) : 1;
}

// Binds each thread entering the arena to the core of its slot, once per thread.
struct workers::pin_observer : tbb::task_scheduler_observer {
  core_pinning pins;
  std::atomic<int>& pinned;
  pin_observer(tbb::task_arena& a, std::atomic<int>& count) : tbb::task_scheduler_observer(a), pinned(count) {
    observe(true);
  }
  ~pin_observer() override { observe(false); }
  void on_scheduler_entry(bool) override {
    thread_local const void* done_for = nullptr;  // pin once per thread and pool
    if (done_for == this) return;
    done_for = this;
    if (pins.pin_current_thread(tbb::this_task_arena::current_thread_index())) ++pinned;
  }
};

workers::workers(int threads, bool pin)
    : threads_(threads),
      limit_(tbb::global_control::max_allowed_parallelism, size_t(threads)),
      arena_(threads, 1) {
  if (pin) {
    arena_.initialize();
    pin_ = std::make_unique<pin_observer>(arena_, pinned_);
  }
}

workers::~workers() = default;

void workers::warm_up() {
  run([&] { tbb::parallel_for(0, 64 * threads_, [](int) {}); });
}

}  // namespace epsray
