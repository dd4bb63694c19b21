#include "shade/texture.h"

#include <cmath>

namespace epsray {

vec3 sample_texture(const texture& t, vec2 uv) {
  vec2 s = uv / t.scale;  // repeats
  if (t.kind == texture_kind::checker) {
    // Two squares per repeat along each axis.
    long iu = long(std::floor(2 * s.x)), iv = long(std::floor(2 * s.y));
    return ((iu + iv) & 1) ? t.color_b : t.color_a;
  }
  // Bilinear, wrapping; v = 0 is the image's bottom row so pictures stand upright.
  float fx = (s.x - std::floor(s.x)) * float(t.width) - 0.5f;
  float fy = (1 - (s.y - std::floor(s.y))) * float(t.height) - 0.5f;
  float x0f = std::floor(fx), y0f = std::floor(fy);
  float ax = fx - x0f, ay = fy - y0f;
  auto wrap = [](long i, int n) { return int(((i % n) + n) % n); };
  int x0 = wrap(long(x0f), t.width), x1 = wrap(long(x0f) + 1, t.width);
  int y0 = wrap(long(y0f), t.height), y1 = wrap(long(y0f) + 1, t.height);
  auto at = [&](int x, int y) { return t.texels[size_t(y) * size_t(t.width) + size_t(x)]; };
  return glm::mix(glm::mix(at(x0, y0), at(x1, y0), ax), glm::mix(at(x0, y1), at(x1, y1), ax), ay);
}

texture_range range_of(const texture& t) {
  if (t.kind == texture_kind::checker) return {glm::min(t.color_a, t.color_b), glm::max(t.color_a, t.color_b)};
  if (t.texels.empty()) return {};
  texture_range r{t.texels[0], t.texels[0]};
  for (const vec3& c : t.texels) r.lo = glm::min(r.lo, c), r.hi = glm::max(r.hi, c);
  return r;
}

}  // namespace epsray
