#include "scene/scene.h"

#include <cmath>

namespace epsray {

namespace {
float spd_intensity(size_t n) { return n == 0 ? 0.0f : float(std::sqrt(double(n)) / (2.0 * double(n))); }
}  // namespace

vec3 scene_ambient(const scene& s) {
  return s.has_ambient ? s.ambient : vec3(spd_intensity(s.lights.size()));
}

vec3 light_intensity(const scene& s, const light& l) {
  return l.has_color ? l.color : vec3(spd_intensity(s.lights.size()));
}

}  // namespace epsray
