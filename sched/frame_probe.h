// The probe of a frame with cells that follows none (object_gate::probe_due): a walk's
// first frame, or the first after plain frames. The gate has no counts of that view, and
// building cells for every pixel before learning that they do not pay is what such frames
// lost (teapot-s6's first frame took 1.8 base frames, gears-s2's 1.4). So a sparse grid of
// the frame's pixels takes the interpolate path first, building the cells it reaches, and
// its counts decide (object_gate::probe) whether the frame goes plain. Cells built for
// probe pixels serve the frame when it keeps its cells.
#pragma once
#include <cstdint>
#include <vector>

#include "interp/interp_shade.h"
#include "interp/object_gate.h"
#include "workers.h"

namespace epsray {

// The spacing of the probe's grid: about probe_pixels pixels whatever the image size, since
// the estimate's spread depends on how many pixels it counts, and its cost too. At that
// spacing (32 pixels at 640x480) probe pixels fall in cells of their own (a moving camera's
// cells cover 32-1024 pixels), so the probe builds a small part of the frame's cells; its
// share of the rays the cells save came within 0.03 of a grid four times as dense on the
// SPD orbits and the art-room walk.
constexpr int probe_pixels = 300;
int probe_step(const camera& cam);

struct frame_probe {
  std::vector<gate_entry> tallies;  // per probe pixel, in raster order
  ray_counts rays;                  // every ray the probe cast, builds included
  std::uint64_t own_rays = 0;       // those its pixels cast themselves
  std::uint64_t pixels = 0;
  std::uint64_t build_ticks = 0;
  // The same pixels traced under their allowance (shade_within), as a plain frame may:
  // the rays it bounded and those it cast (shadow and secondary).
  std::uint64_t bounded = 0, cast = 0;
};

// Shades the probe pixels of frame f through the interpolate path and under their
// allowance (their radiance is not kept: the frame shades them again by its own path), in
// parallel over rows. What it counts does not depend on the threads.
frame_probe probe_frame(workers& pool, const interp_frame& f);

}  // namespace epsray
