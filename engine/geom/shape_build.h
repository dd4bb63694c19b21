// Turns parsed primitives into traceable shapes and their bounds.
#pragma once
#include <vector>

#include "geom/shapes.h"
#include "scene/scene.h"

namespace epsray {

// Appends an n-gon's 2D projection (n > 3) and edge bands to `pd`.
shape make_shape(const scene& s, const primitive& p, polygon_data& pd);
bounds primitive_bounds(const scene& s, const primitive& p);
// Unit normal of a planar primitive's plane, from its first two edges (whitted.md 2).
vec3 polygon_normal(const scene& s, const primitive& p);

}  // namespace epsray
