// Cheap per-pixel timing: the time-stamp counter costs a few nanoseconds a read, where a
// steady_clock read costs tens, and the interpolate path is a few hundred nanoseconds.
#pragma once
#include <cstdint>
#include <x86intrin.h>

namespace epsray {

inline std::uint64_t cycle_now() { return __rdtsc(); }

// Counter ticks per millisecond, measured once against steady_clock (about 2 ms, the
// first time: call it before a timed region).
double ticks_per_ms();

}  // namespace epsray
