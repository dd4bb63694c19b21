// The thread pool a render runs on: a oneTBB arena of exactly N threads (the caller
// included). N may exceed the cores (stress tests); images never depend on N.
#pragma once
#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/task_arena.h>

namespace epsray {

class workers {
 public:
  explicit workers(int threads);
  int threads() const { return threads_; }
  template <class F>
  void run(F&& f) {
    arena_.execute(std::forward<F>(f));
  }
  // Starts every worker thread now (oneTBB starts them on first use, ~5-10 ms).
  void warm_up();

 private:
  int threads_;
  tbb::global_control limit_;  // lets the arena have more threads than cores
  tbb::task_arena arena_;
};

int hardware_threads();

}  // namespace epsray
