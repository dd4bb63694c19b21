#include "tiles.h"

#include <algorithm>

namespace epsray {

int default_tile_rows(int height, int threads) {
  // Aim at 8 tiles per thread or more; at least one row, at most 8.
  int rows = height / std::max(1, 8 * threads);
  return std::clamp(rows, 1, 8);
}

std::vector<tile> make_tiles(int height, int rows_per_tile) {
  std::vector<tile> out;
  rows_per_tile = std::max(1, rows_per_tile);
  for (int y = 0; y < height; y += rows_per_tile) out.push_back({y, std::min(height, y + rows_per_tile)});
  return out;
}

}  // namespace epsray
