// How a frame's tiles are handed to the threads. Each thread takes the next tile from one
// shared counter until none is left, so a thread that joins late (woken from sleep) just
// takes fewer. With `costly_first`, the order is last frame's tile costs, dearest first
// (longest-processing-time scheduling): the tiles left at the end are the cheap ones, so
// the threads finish together. Which thread runs a tile never changes what it computes.
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <vector>

#include "tiles.h"
#include "workers.h"

namespace epsray {

// Where a tile phase's thread time went besides the tiles (means over the arena's threads).
struct phase_times {
  double wall_ms = 0;  // the phase, first tile taken to last tile done
  double join_ms = 0;  // from the phase's start to a thread's first tile (a thread that took none: all of it)
  double tail_ms = 0;  // from a thread's last tile to the phase's end
};

// Runs fn(i) once for each tile i of `order` on the pool's threads; returns how long the
// phase took and how much of it the threads spent waiting.
phase_times run_tiles(workers& pool, const std::vector<std::uint32_t>& order, const std::function<void(size_t)>& fn);

}  // namespace epsray
