// A ray with its reciprocal direction precomputed for slab tests.
#pragma once
#include <glm/glm.hpp>

#include <cmath>

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

// The length of a vector whose squared length may leave float's range (a light seen from
// a sky dome 1e20 away): in float where it fits, as before, else in double.
inline float safe_length(vec3 v) {
  const float l2 = glm::dot(v, v);
  if (l2 < 3.4e38f && (l2 > 1e-37f || l2 == 0)) return std::sqrt(l2);
  return float(glm::length(glm::dvec3(v)));
}
inline vec3 safe_normalize(vec3 v) {
  const float l2 = glm::dot(v, v);
  if (l2 < 3.4e38f && l2 > 1e-37f) return glm::normalize(v);
  return vec3(glm::normalize(glm::dvec3(v)));
}

}  // namespace epsray
