// What any ray can carry: per depth of the ray tree, the least and greatest radiance
// whitted.md section 4 can give a ray of that depth, per channel, from the scene's
// materials, textures, lights and background alone. An error allowance (whitted.h) may
// take a weak secondary term at the middle of this range instead of tracing it, when its
// weight times half the range fits in what the pixel may still be off by.
#pragma once
#include <glm/glm.hpp>

namespace epsray {

using glm::vec3;

constexpr int max_depth = 5;  // eye ray = depth 1 (SPD testing procedure)

struct radiance_range {
  vec3 lo[max_depth + 1] = {}, hi[max_depth + 1] = {};  // indexed by depth, 1 to max_depth
};

struct world;
struct material;

// What a ray of depth d that meets material m can carry, where any ray of depth d + 1
// carries lo_next..hi_next (unwidened): A Kd C + sum of Ij (Kd C dot + Ks spec) +
// (Ks + T) L(depth + 1), with dot and spec in [0, 1] and each light lit or not.
void material_radiance(const world& w, const material& m, int d, vec3 lo_next, vec3 hi_next, vec3& lo, vec3& hi);

// lo..hi widened for float rounding, as bound_radiance widens its ranges.
inline void widen_radiance(vec3& lo, vec3& hi) {
  lo = lo * (1 - 1e-4f);
  hi = hi * (1 + 1e-4f) + 1e-7f;
}

// Every material some primitive uses: L = A Kd C + sum of Ij (Kd C dot + Ks spec) + (Ks + T)
// L(depth + 1), with dot and spec in [0, 1] and each light lit or not, C over the texture's
// range; a miss gives the background. Widened by a relative 1e-4 for float rounding.
radiance_range bound_radiance(const world& w);

}  // namespace epsray
