// Baseline (b) of the speed-against-accuracy suite: reprojection of the previous frame's
// pixels without error control, as a render cache does. Each traced pixel keeps its first
// hit point and radiance; the next frame projects those points into its view, the nearest
// point on each pixel lends its radiance unchanged (view-dependent shading, shadows and
// reflections go stale), and pixels no point reaches are traced. A point is reused for at
// most max_age frames, then traced again.
#pragma once
#include <atomic>
#include <cstdint>
#include <vector>

#include "image/image.h"
#include "scene/camera.h"
#include "shade/whitted.h"

namespace epsray {

struct reuse_pixels {
  int width = 0, height = 0;
  std::vector<glm::vec3> point, rad;  // per pixel: the surface point seen, its radiance
  std::vector<std::uint16_t> age;     // frames the radiance has been carried; no_point: none
  static constexpr std::uint16_t no_point = 0xffff;
  void resize(int w, int h);
};

// What a walk carries from frame to frame: last frame's pixels, and the ones being written.
struct reuse_state {
  reuse_pixels last, next;
};

// Splats last-frame pixels [i0, i1) into `cam`: nearest[p] keeps the smallest (depth bits,
// index) of the points landing on pixel p, so the result does not depend on the order.
void splat_points(const reuse_pixels& last, const camera& cam, int max_age, std::size_t i0, std::size_t i1,
                  std::atomic<std::uint64_t>* nearest);

// Rows [y0, y1): pixels a point reached take its radiance, the rest are traced. Writes each
// pixel's point into `next`; returns the pixels reused.
std::uint64_t shade_rows_reuse(const world& w, const camera& cam, const reuse_pixels& last,
                               const std::atomic<std::uint64_t>* nearest, int y0, int y1, image& out,
                               reuse_pixels& next, trace_state& st);

}  // namespace epsray
