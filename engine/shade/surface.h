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

}  // namespace epsray
