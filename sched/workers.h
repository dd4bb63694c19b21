// The thread pool a render runs on: a oneTBB arena of exactly N threads (the caller
// included). N may exceed the cores (stress tests); images never depend on N.
#pragma once
#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/task_arena.h>
#include <oneapi/tbb/task_scheduler_observer.h>

#include <atomic>
#include <memory>

#include "tiles.h"
#include "topology.h"

namespace epsray {

class workers {
 public:
  // pin: bind each thread that works in the arena to its own core through hwloc (the
  // calling thread too, which stays bound afterwards).
  explicit workers(int threads, bool pin = false);
  ~workers();
  int threads() const { return threads_; }
  int pinned() const { return pinned_.load(); }  // threads that were bound to a core
  template <class F>
  void run(F&& f) {
    arena_.execute(std::forward<F>(f));
  }
  // Starts every worker thread now (oneTBB starts them on first use, ~5-10 ms).
  void warm_up();
  // Last frame's tile costs, for the next frame's order (tile_queue.h).
  tile_history& history() { return history_; }

 private:
  int threads_;
  tbb::global_control limit_;  // lets the arena have more threads than cores
  tbb::task_arena arena_;
  struct pin_observer;
  std::unique_ptr<pin_observer> pin_;
  std::atomic<int> pinned_{0};
  tile_history history_;
};

int hardware_threads();

}  // namespace epsray
