// --verify: the Whitted radiance of every pixel, and the error of whitted.md section 6 of
// an accelerated image against it. Never changes the image it checks.
#pragma once
#include <cstdint>

#include "frame_render.h"

namespace epsray {

struct verify_result {
  double max_rel_err = 0;
  std::uint64_t violations = 0;  // pixels with max_c e_c > eps
  double p999_rel_err = 0;       // 99.9th percentile of the per-pixel error
  double mean_rel_err = 0;
};

// e_c = |La_c - Lw_c| / max(Lw_c, 1/255); a pixel's error is the largest over c.
double pixel_error(glm::vec3 la, glm::vec3 lw);
verify_result verify_frame(workers& pool, const world& w, const camera& cam, const image& accelerated, float eps);

}  // namespace epsray
