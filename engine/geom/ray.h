// A ray with its reciprocal direction precomputed for slab tests.
#pragma once
#include <glm/glm.hpp>

namespace epsray {

using glm::vec3;

struct ray {
  vec3 o{0};
  vec3 d{0, 0, 1};  // unit length everywhere in the tracer (whitted.md 4)
  vec3 inv_d{0, 0, 1};
};

inline ray make_ray(vec3 o, vec3 d) {
  ray r;
  r.o = o;
  r.d = d;
  // 1/0 = inf is what the slab test wants; keep the sign of zero so -0 gives -inf.
  r.inv_d = vec3(1.0f / d.x, 1.0f / d.y, 1.0f / d.z);
  return r;
}

}  // namespace epsray
