#include "cycle_clock.h"

#include <chrono>

namespace epsray {

double ticks_per_ms() {
  static const double rate = [] {
    auto t0 = std::chrono::steady_clock::now();
    std::uint64_t c0 = cycle_now();
    while (std::chrono::steady_clock::now() - t0 < std::chrono::milliseconds(2)) {
    }
    std::uint64_t c1 = cycle_now();
    double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return double(c1 - c0) / ms;
  }();
  return rate;
}

}  // namespace epsray
