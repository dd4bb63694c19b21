// Textures modulate the diffuse colour only (docs/scene-format.md); uv are in world units.
#pragma once
#include "scene/scene.h"

namespace epsray {

vec3 sample_texture(const texture& t, vec2 uv);

}  // namespace epsray
