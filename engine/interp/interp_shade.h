// The interpolate path (section 8.3, path 2): a visibility ray finds the object, its
// linetree gives the cell, and the cell's interpolant gives the radiance when the proven
// bound meets epsilon for this pixel; otherwise the pixel is traced.
#pragma once
#include <array>
#include <cstdint>

#include "image/image.h"
#include "interp/linetree.h"
#include "scene/camera.h"
#include "shade/whitted.h"

namespace epsray {

struct interp_params {
  float eps = 0.05f;
  float min_cell_pixels = 8;   // no subdivision into children covering fewer pixels
  float max_cell_pixels = 4096;  // larger cells are subdivided without building an interpolant
  int max_depth = 16;          // halvings of any axis below the root (floats keep ~7 digits)
  bool four_way = true;        // halve only the axes the failure points at (section 8.6)
};

// How a pixel got its radiance, and why an interpolant was not used.
enum class pixel_path : std::uint8_t { fast, interp, base };
enum class pixel_reason : std::uint8_t {
  interpolated,     // success
  discontinuity,    // cell_reason values, in the same order
  missed,
  blocked,
  nonlinear,
  traced,           // base-traced for another reason: background, eye behind the face, ...
};

// Per-thread scratch for building interpolants: reused, never reallocated per ray.
struct interp_scratch {
  std::array<ray_tree, 16> trees;
  // The last leaf found: neighbouring pixels mostly fall in the same cell, so the lookup
  // starts there when the line lies strictly inside it (the same leaf a descent from the
  // root would reach).
  const linetree* hint_tree = nullptr;
  lt_node* hint = nullptr;
};

struct interp_frame {
  const world* w = nullptr;
  linetree_set* trees = nullptr;
  const camera* cam = nullptr;
  interp_params p;
};

struct pixel_result {
  glm::vec3 L{0};
  pixel_path path = pixel_path::base;
  pixel_reason reason = pixel_reason::traced;
};

pixel_result shade_pixel_interp(const interp_frame& f, int x, int y, trace_state& st, interp_scratch& scratch);

// The paper's colours for the error-coded image.
glm::vec3 reason_colour(pixel_reason r);

}  // namespace epsray
