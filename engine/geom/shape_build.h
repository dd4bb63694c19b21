// Turns parsed primitives into traceable shapes and their bounds.
#pragma once
#include <vector>

#include "geom/shapes.h"
#include "scene/scene.h"

namespace epsray {

// Appends a polygon's 2D projection to `poly2d` when it needs one (n > 3).
shape make_shape(const scene& s, const primitive& p, std::vector<vec2>& poly2d);
bounds primitive_bounds(const scene& s, const primitive& p);
// Unit normal of a planar primitive's plane, from its first two edges (whitted.md 2).
vec3 polygon_normal(const scene& s, const primitive& p);

}  // namespace epsray
