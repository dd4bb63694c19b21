#include "workers.h"

#include <oneapi/tbb/parallel_for.h>

#include <thread>

namespace epsray {

int hardware_threads() {
  unsigned n = std::thread::hardware_concurrency();
  return n ? int(n) : 1;
}

workers::workers(int threads)
    : threads_(threads),
      limit_(tbb::global_control::max_allowed_parallelism, size_t(threads)),
      arena_(threads, 1) {}

void workers::warm_up() {
  run([&] { tbb::parallel_for(0, 64 * threads_, [](int) {}); });
}

}  // namespace epsray
