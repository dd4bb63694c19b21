#include "tiles.h"

#include <algorithm>
#include <numeric>

namespace epsray {

int default_tile_rows(int height, int threads) {
  // About 8 tiles per thread: the threads take tiles dearest first (tile_queue.h), so the
  // tiles left at the end are cheap and the threads finish together without many tiles.
  // Fewer, taller tiles keep locality: neighbouring rows reuse the same cells, and one-row
  // tiles taken in cost order cost 7% more thread time in full mode even on one thread.
  // At least one row, at most 16.
  int rows = height / std::max(1, 8 * threads);
  return std::clamp(rows, 1, 16);
}

std::vector<tile> make_tiles(int height, int rows_per_tile) {
  std::vector<tile> out;
  rows_per_tile = std::max(1, rows_per_tile);
  for (int y = 0; y < height; y += rows_per_tile) out.push_back({y, std::min(height, y + rows_per_tile)});
  return out;
}

std::vector<std::uint32_t> tile_history::order(size_t tiles, tile_order how) const {
  std::vector<std::uint32_t> out(tiles);
  std::iota(out.begin(), out.end(), 0u);
  if (how == tile_order::costly_first && ticks.size() == tiles)
    std::stable_sort(out.begin(), out.end(), [&](std::uint32_t a, std::uint32_t b) { return ticks[a] > ticks[b]; });
  return out;
}

}  // namespace epsray
