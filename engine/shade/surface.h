// What shading needs at a hit: position, outward geometric and shading normals, uv.
#pragma once
#include "accel/world.h"

namespace epsray {

struct surface {
  vec3 p{0};
  vec3 ng{0};  // outward geometric normal (flipped by negative radii)
  vec3 ns{0};  // outward shading normal: ng except on patches
};

surface surface_at(const world& w, int prim, const ray& r, float t);
// Texture coordinates in world units along the surface (docs/scene-format.md).
vec2 surface_uv(const world& w, int prim, vec3 p);

// For planar surfaces (polygons, patches, disks, a box face holding p) the uv map is affine:
// uv = (dot(p - o, eu), dot(p - o, ev)). False for curved primitives.
bool planar_uv_frame(const world& w, int prim, vec3 p, vec3& o, vec3& eu, vec3& ev);

}  // namespace epsray
