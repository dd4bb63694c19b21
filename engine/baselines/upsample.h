// Baseline (a) of the speed-against-accuracy suite: the base tracer at 1/k of the
// resolution along each axis, upsampled bilinearly to the full frame. Every k-th pixel is
// Whitted radiance; the rest are screen-space guesses with no error control.
#pragma once
#include "image/image.h"
#include "scene/camera.h"

namespace epsray {

// The same eye and view through ceil(W/k) x ceil(H/k) pixels, k times the step.
camera reduced_camera(const camera& cam, int k);

// Rows [y0, y1) of the full frame `cam`, sampled bilinearly from `low` (rendered through
// reduced_camera(cam, k)); edges clamp.
void upsample_rows(const image& low, const camera& cam, int k, int y0, int y1, image& out);

}  // namespace epsray
