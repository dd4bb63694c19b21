// Frames are split into bands of whole scanlines: each tile owns its pixels, so no pixel
// is ever written by two threads and the image cannot depend on the schedule.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace epsray {

struct tile {
  int y0 = 0, y1 = 0;  // rows [y0, y1)
};

// Rows per tile when the caller does not choose: small enough that every thread gets
// several tiles (load balance), large enough to amortise task overhead (~1 µs each).
int default_tile_rows(int height, int threads);
std::vector<tile> make_tiles(int height, int rows_per_tile);

// The order in which a frame's tiles are handed out (tile_queue.h): top to bottom, or by
// last frame's cost, dearest first.
enum class tile_order { scan, costly_first };

// Last frame's cost of each tile, carried from frame to frame (by workers, which every
// caller keeps across frames). Forgotten when the tiling changes.
struct tile_history {
  std::vector<std::uint64_t> ticks;
  std::vector<std::uint32_t> order(size_t tiles, tile_order how) const;
};

}  // namespace epsray
