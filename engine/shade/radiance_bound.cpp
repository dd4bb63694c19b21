#include "shade/radiance_bound.h"

#include <algorithm>
#include <vector>

#include "accel/world.h"

namespace epsray {

void material_radiance(const world& w, const material& m, int d, vec3 lo_next, vec3 hi_next, vec3& lo, vec3& hi) {
  vec3 power{0};
  for (const vec3& p : w.light_power) power += p;
  vec3 cmin = m.color, cmax = m.color;
  if (m.texture >= 0) cmin *= w.texture_ranges[size_t(m.texture)].lo, cmax *= w.texture_ranges[size_t(m.texture)].hi;
  // Secondary rays are traced below max_depth only; a term is there when its k > 0.
  const float k = d < max_depth ? (m.ks > 0 ? m.ks : 0.0f) + (m.t > 0 ? m.t : 0.0f) : 0.0f;
  const float spec = m.shine > 0 ? m.ks : 0.0f;
  hi = w.ambient * m.kd * cmax + power * (m.kd * cmax) + power * spec + k * hi_next;
  lo = w.ambient * m.kd * cmin + k * lo_next;  // every light blocked
}

radiance_range bound_radiance(const world& w) {
  std::vector<char> used(w.sc.materials.size(), 0);
  for (size_t i = 0; i < w.scene_prims; ++i) used[size_t(w.info[i].material)] = 1;
  radiance_range r;
  vec3 lo_next{0}, hi_next{0};  // depth + 1's range
  for (int d = max_depth; d >= 1; --d) {
    vec3 lo = w.background, hi = w.background;
    for (size_t i = 0; i < used.size(); ++i) {
      if (!used[i]) continue;
      vec3 mlo, mhi;
      material_radiance(w, w.sc.materials[i], d, lo_next, hi_next, mlo, mhi);
      lo = glm::min(lo, mlo), hi = glm::max(hi, mhi);
    }
    r.lo[d] = lo, r.hi[d] = hi;
    widen_radiance(r.lo[d], r.hi[d]);
    lo_next = lo, hi_next = hi;
  }
  return r;
}

}  // namespace epsray
