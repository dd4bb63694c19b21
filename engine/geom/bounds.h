// Axis-aligned boxes for the BVH.
#pragma once
#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>
#include <limits>

#include "geom/ray.h"

namespace epsray {

struct bounds {
  vec3 lo{std::numeric_limits<float>::max()};
  vec3 hi{-std::numeric_limits<float>::max()};

  void grow(vec3 p) { lo = glm::min(lo, p), hi = glm::max(hi, p); }
  void grow(const bounds& b) { lo = glm::min(lo, b.lo), hi = glm::max(hi, b.hi); }
  bool empty() const { return lo.x > hi.x; }
  vec3 centre() const { return (lo + hi) * 0.5f; }
  vec3 extent() const { return empty() ? vec3(0) : hi - lo; }
  float area() const {
    vec3 e = extent();
    return 2 * (e.x * e.y + e.y * e.z + e.z * e.x);
  }
};

// ~100 ulps of coordinates of magnitude up to mag: how far points computed in floats from
// their own rays may lie from where exact arithmetic puts them.
inline float rounding_margin(float mag) { return 1e-5f * (1 + mag); }

// b grown by the rounding margin of the largest coordinate magnitude of b and of `also`
// (an eye, say): points computed in floats from their own rays may lie that far outside a
// box proven for them in exact arithmetic.
inline bounds with_rounding_margin(bounds b, vec3 also = vec3(0)) {
  float mag = 0;
  for (int i = 0; i < 3; ++i) mag = std::max({mag, std::fabs(b.lo[i]), std::fabs(b.hi[i]), std::fabs(also[i])});
  const vec3 m(rounding_margin(mag));
  b.lo -= m, b.hi += m;
  return b;
}

// The distance between box a and the box [lo, hi] (a point where lo = hi), 0 where they
// meet, in double; callers round it down for their use.
inline double box_gap(const bounds& a, const glm::dvec3& lo, const glm::dvec3& hi) {
  double s = 0;
  for (int k = 0; k < 3; ++k) {
    const double e = std::max({double(a.lo[k]) - hi[k], lo[k] - double(a.hi[k]), 0.0});
    s += e * e;
  }
  return std::sqrt(s);
}

// Slab test; true when [t0, t1] overlaps the box. NaN-safe: 0 * inf lanes are dropped by
// the operand order of min/max (std::min returns its first argument on NaN comparisons).
inline bool hit_bounds(const vec3& lo, const vec3& hi, const ray& r, float tmax, float& tnear) {
  float tx0 = (lo.x - r.o.x) * r.inv_d.x, tx1 = (hi.x - r.o.x) * r.inv_d.x;
  float ty0 = (lo.y - r.o.y) * r.inv_d.y, ty1 = (hi.y - r.o.y) * r.inv_d.y;
  float tz0 = (lo.z - r.o.z) * r.inv_d.z, tz1 = (hi.z - r.o.z) * r.inv_d.z;
  float t0 = std::max(std::max(std::min(tx0, tx1), std::min(ty0, ty1)), std::max(std::min(tz0, tz1), 0.0f));
  float t1 = std::min(std::min(std::max(tx0, tx1), std::max(ty0, ty1)), std::min(std::max(tz0, tz1), tmax));
  // Grow the exit by a few ulps so rays grazing a flat box (a polygon's) are not lost.
  tnear = t0;
  return t0 <= t1 * 1.00000024f;
}

}  // namespace epsray
