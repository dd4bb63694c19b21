// Base shading of a band of scanlines: every pixel traced by the Whitted tracer.
#pragma once
#include "image/image.h"
#include "scene/camera.h"
#include "shade/ray_tree_store.h"
#include "shade/whitted.h"

namespace epsray {

// Traces rows [y0, y1) into `out`; appends each pixel's ray tree to `trees` when non-null.
void shade_rows_base(const world& w, const camera& cam, int y0, int y1, image& out, trace_state& st,
                     ray_tree_store* trees);

// Pixel (x, y) traced with its error allowance spent down its ray tree (shade_within).
vec3 shade_pixel_within(const world& w, const camera& cam, int x, int y, float eps, trace_state& st);

// Traces rows [y0, y1) with each pixel's error allowance spent down its ray tree
// (shade_within, eps > 0): full mode's plain frames (object_gate.h).
void shade_rows_within(const world& w, const camera& cam, int y0, int y1, float eps, image& out, trace_state& st);

}  // namespace epsray
