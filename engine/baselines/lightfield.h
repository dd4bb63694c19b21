// Baseline (c) of the speed-against-accuracy suite: interpolation without the error
// predicate, as light fields do it. Each object's linetrees are cut uniformly, every axis
// halved `depth` times, and a cell whose 16 corner lines all hit the object is interpolated:
// no ray-tree test, no shafts, no bound. Only the parameterisation's own limits (a line
// that misses the object, an eye inside the slab) send a pixel to the tracer.
#pragma once
#include "interp/interp_shade.h"

namespace epsray {

pixel_result shade_pixel_lightfield(const interp_frame& f, int depth, int x, int y, trace_state& st,
                                    interp_scratch& scratch);

}  // namespace epsray
