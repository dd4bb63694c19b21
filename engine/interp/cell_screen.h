// Where a linetree cell lands on screen: the eye rays in a cell pass through its front and
// back faces, so they lie in the overlap of the two faces' projections. The cost model
// (how many pixels a cell covers) and reprojection (which pixels may lie in it) use it.
#pragma once
#include "interp/linetree.h"
#include "scene/camera.h"

namespace epsray {

// Pixel-centre coordinates relative to the image centre (x right, y up); bounded is false
// when a face crosses the eye's plane and has no bounded projection.
struct screen_box {
  float x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool bounded = true;
  bool empty() const { return !(x1 > x0 && y1 > y0); }
};

screen_box cell_screen_box(const camera& cam, const facepair& fp, const lt_node& n);

// Pixels whose eye rays may fall in the cell (an overestimate); infinite when unbounded.
float cell_pixels(const camera& cam, const facepair& fp, const lt_node& n);

// Pixels of the image that a box may cover: its corners' projections' bounding rectangle,
// clipped to the image; infinite when a corner is not in front of the eye.
float box_pixels(const camera& cam, const bounds& b);

// Raster rows and columns, half-open, that hold the pixel centres of a box, widened by a
// pixel against rounding and clamped to the image.
struct pixel_rect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool empty() const { return x1 <= x0 || y1 <= y0; }
};
pixel_rect raster_rect(const camera& cam, const screen_box& b);

}  // namespace epsray
