// Frames are split into bands of whole scanlines: each tile owns its pixels, so no pixel
// is ever written by two threads and the image cannot depend on the schedule.
#pragma once
#include <vector>

namespace epsray {

struct tile {
  int y0 = 0, y1 = 0;  // rows [y0, y1)
};

// Rows per tile when the caller does not choose: small enough that every thread gets
// several tiles (load balance), large enough to amortise task overhead (~1 µs each).
int default_tile_rows(int height, int threads);
std::vector<tile> make_tiles(int height, int rows_per_tile);

}  // namespace epsray
