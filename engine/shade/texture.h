// Textures modulate the diffuse colour only (docs/scene-format.md); uv are in world units.
#pragma once
#include "scene/scene.h"

namespace epsray {

vec3 sample_texture(const texture& t, vec2 uv);

// The least and greatest value sample_texture can return, per channel (bilinear filtering
// stays between texels).
struct texture_range {
  vec3 lo{1}, hi{1};
};
texture_range range_of(const texture& t);

}  // namespace epsray
