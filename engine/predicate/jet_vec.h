// The predicate's arithmetic on whole families of lines: diagonal second-order jets of
// affine forms over a linetree cell (djet), 3-vectors of them (jv), and the boxes and
// signs read off them. Shared by the error predicate and its hit tests.
#pragma once
#include <algorithm>
#include <cmath>

#include "geom/bounds.h"
#include "predicate/djet.h"

namespace epsray::family {

// Affine forms: interval bounds of these expressions over wide cells were 1000x too loose.
using djet = djet_t<affine>;

inline djet djet_variable(int i, double l, double h) {
  djet j(affine_variable(i, l, h));
  j.d[i] = affine(1.0);
  return j;
}

// 3-vectors of jets: points and directions of a whole family of rays at once.
struct jv {
  djet x, y, z;
  djet& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  const djet& operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
};
inline jv operator+(const jv& a, const jv& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline jv operator-(const jv& a, const jv& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline jv operator-(const jv& a) { return {-a.x, -a.y, -a.z}; }
inline jv operator*(const jv& a, const djet& s) { return {a.x * s, a.y * s, a.z * s}; }
inline jv operator*(const jv& a, double s) { return {a.x * s, a.y * s, a.z * s}; }
inline jv operator/(const jv& a, const djet& s) { return {a.x / s, a.y / s, a.z / s}; }
inline djet dot(const jv& a, const jv& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline djet dot(const jv& a, glm::dvec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
// |a|^2, its value also bounded below through each component's own range: the affine
// product of a form that straddles 0 with itself dips below 0, and over a wide cell that
// left sqrt, and every direction normalized from it, unbounded (teapot-s6's floor cells
// could not prove a highlight's N.H positive, though one component never nears 0).
inline djet norm2(const jv& a) {
  djet s = dot(a, a);
  if (lo(s.v) > 0) return s;
  double least = 0;  // sum of each component's least square over its range
  for (int i = 0; i < 3; ++i) {
    const double l = lo(a[i].v), h = hi(a[i].v);
    const double m = l > 0 ? l : (h < 0 ? -h : 0.0);
    least += m * m;
  }
  least *= 1 - 1e-12;  // the squares' and the sum's rounding
  if (!(least > 0) || !std::isfinite(hi(s.v))) return s;
  s.v = affine_range(least, hi(s.v));
  return s;
}
inline jv normalize(const jv& a) { return a / sqrt(norm2(a)); }
inline jv constant(glm::dvec3 p) { return {djet(p.x), djet(p.y), djet(p.z)}; }
inline jv operator-(const jv& a, glm::dvec3 b) { return a - constant(b); }

inline glm::dvec3 dv(glm::vec3 v) { return glm::dvec3(v); }

// The float box holding a family of points, rounded outwards.
inline bounds box_of(const jv& p) {
  bounds b;
  for (int i = 0; i < 3; ++i) {
    b.lo[i] = std::nextafter(float(lo(p[i].v)), -INFINITY);
    b.hi[i] = std::nextafter(float(hi(p[i].v)), INFINITY);
  }
  return b;
}

// The box of points that lie on the plane n.p = c, tightened by the plane: each coordinate
// is also bounded through the others. Affine forms of o + t d leave a flat family's box
// centimetres thick, touching whatever stands just behind the surface (a canvas' frame).
inline bounds box_on_plane(const jv& p, glm::dvec3 n, double c) {
  bounds b = box_of(p);
  for (int i = 0; i < 3; ++i) {
    if (std::fabs(n[i]) < 1e-9) continue;
    double lo_s = c, hi_s = c;  // c - sum_{j != i} n_j p_j
    for (int j = 0; j < 3; ++j) {
      if (j == i) continue;
      double a = n[j] * double(b.lo[j]), z = n[j] * double(b.hi[j]);
      lo_s -= std::max(a, z), hi_s -= std::min(a, z);
    }
    double v0 = lo_s / n[i], v1 = hi_s / n[i];
    if (v0 > v1) std::swap(v0, v1);
    const double pad = 1e-6 * (std::fabs(v0) + std::fabs(v1)) + 1e-9;
    b.lo[i] = std::max(b.lo[i], std::nextafter(float(v0 - pad), -INFINITY));
    b.hi[i] = std::min(b.hi[i], std::nextafter(float(v1 + pad), INFINITY));
  }
  return b;
}

inline bool finite_box(const bounds& b) {
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(b.lo[i]) || !std::isfinite(b.hi[i])) return false;
  return true;
}

inline bool positive(const djet& x) { return lo(x.v) > 0; }
inline bool negative(const djet& x) { return hi(x.v) < 0; }

}  // namespace epsray::family
