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

// A unit vector perpendicular to n, the same for the same n.
vec3 perpendicular(vec3 n);

// The affine uv map of a polygon, patch or disk (docs/scene-format.md):
// uv = (dot(p - o, eu), dot(p - o, ev)), eu and ev unit vectors in its plane.
struct uv_frame {
  vec3 o{0}, eu{0}, ev{0};
};
// Zero vectors for the other kinds, whose maps are not one affine frame.
uv_frame fixed_uv_frame(const scene& s, const primitive& p);

}  // namespace epsray
