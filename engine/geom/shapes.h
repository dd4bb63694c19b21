// Traceable primitives: one 64-byte record per primitive (one cache line), a tag switch
// instead of virtual calls, and the closest-hit routines that the BVH leaves call.
// Every routine is two-sided and accepts hits with 0 < t < tmax (whitted.md 2, 4).
#pragma once
#include <cmath>
#include <cstdint>
#include <vector>

#include "geom/bounds.h"
#include "geom/ray.h"

namespace epsray {

using glm::vec2;

enum class shape_kind : std::uint8_t { sphere, triangle, polygon, cone, disk, box };

struct sphere_geom { vec3 c; float r; };              // r may be negative (flipped normal)
struct triangle_geom { vec3 v0, e1, e2, n; };         // v1 = v0 + e1, v2 = v0 + e2; n unit
struct polygon_geom {                                  // n-gon, even-odd rule in 2D
  vec3 n; float d;                                     // plane dot(n, p) = d
  std::int32_t first, count;                           // into polygon_data::verts
  std::int32_t ax_u, ax_v;                             // projection axes
  // Large polygons bucket their edges into horizontal bands of the projected v range so
  // the crossing test walks only edges that can straddle the hit (0 bands: walk all).
  std::int32_t bands, band_first;                      // into polygon_data::band_begin
  float v0, inv_band;                                  // band of v: (v - v0) * inv_band
};
struct cone_geom { vec3 base, axis; float h, r0, k; };  // radius r0 + k z, z in [0, h], r >= 0
struct disk_geom { vec3 c, n; float r; };             // r, not r^2: r^2 leaves float range for r > 1.8e19
struct box_geom { vec3 c, ax0, ax1, ax2, half; };      // oriented box

struct shape {
  union {
    sphere_geom sphere;
    triangle_geom tri;
    polygon_geom poly;
    cone_geom cone;
    disk_geom disk;
    box_geom box;
  };
  shape_kind kind;
  shape() : box{} {}
};
static_assert(sizeof(shape) <= 64, "one cache line per primitive");

inline bool hit_sphere(const sphere_geom& s, const ray& r, float tmax, float& t) {
  // Distance from the centre to the line, computed directly: far more accurate than b^2 - c
  // for small spheres seen from afar (Ray Tracing Gems, ch. 7). In double: r^2 of a sky
  // dome of radius 1e20, or of a sphere of radius 1e-30, is beyond float's range.
  using d3 = glm::dvec3;
  const d3 oc = d3(r.o) - d3(s.c), dir(r.d);
  const double b = glm::dot(oc, dir);
  const d3 f = oc - b * dir;
  const double r2 = double(s.r) * double(s.r);
  const double disc = r2 - glm::dot(f, f);
  if (disc < 0) return false;
  const double sq = std::sqrt(disc);
  const double c = glm::dot(oc, oc) - r2;
  const double q = -b - std::copysign(sq, b);
  double t0 = q != 0 ? c / q : 0, t1 = q;
  if (t0 > t1) std::swap(t0, t1);
  if (t0 > 0 && t0 < double(tmax) && float(t0) > 0) return t = float(t0), true;
  if (t1 > 0 && t1 < double(tmax) && float(t1) > 0) return t = float(t1), true;
  return false;
}

inline bool hit_triangle(const triangle_geom& g, const ray& r, float tmax, float& t) {
  vec3 p = glm::cross(r.d, g.e2);
  float det = glm::dot(g.e1, p);
  if (det == 0) return false;
  float inv = 1.0f / det;
  vec3 s = r.o - g.v0;
  float u = glm::dot(s, p) * inv;
  if (u < 0 || u > 1) return false;
  vec3 q = glm::cross(s, g.e1);
  float v = glm::dot(r.d, q) * inv;
  if (v < 0 || u + v > 1) return false;
  float tt = glm::dot(g.e2, q) * inv;
  if (!(tt > 0 && tt < tmax)) return false;
  t = tt;
  return true;
}

// Projected vertices of the n-gons (n > 3) and their edge bands.
struct polygon_data {
  std::vector<vec2> verts;
  std::vector<std::int32_t> band_begin;  // per band: first entry in band_edges; one extra at the end
  std::vector<std::int32_t> band_edges;  // edge i joins verts i-1 and i (cyclically)
};

// Does edge (a, b) flip the even-odd parity of (u, w)? One formula for every caller, so a
// point is classified the same whether edges are walked all or by band.
inline bool crosses(vec2 a, vec2 b, float u, float w) {
  if ((b.y > w) == (a.y > w)) return false;
  float x = a.x + (w - a.y) * (b.x - a.x) / (b.y - a.y);
  return u < x;
}

inline int polygon_band(const polygon_geom& g, float w) {
  float f = (w - g.v0) * g.inv_band;
  return f <= 0 ? 0 : (f >= float(g.bands - 1) ? g.bands - 1 : int(f));
}

inline bool inside_polygon(const polygon_geom& g, const polygon_data& pd, float u, float w) {
  const vec2* v = pd.verts.data() + g.first;
  const int n = g.count;
  bool in = false;
  if (g.bands == 0) {
    for (int i = 0, j = n - 1; i < n; j = i++) in ^= crosses(v[j], v[i], u, w);
    return in;
  }
  const std::int32_t* bb = pd.band_begin.data() + g.band_first;
  int b = polygon_band(g, w);
  for (std::int32_t k = bb[b]; k < bb[b + 1]; ++k) {
    int i = pd.band_edges[size_t(k)];
    in ^= crosses(v[i == 0 ? n - 1 : i - 1], v[i], u, w);
  }
  return in;
}

// Where the ray meets the polygon's plane, in (0, tmax): hit_polygon's t before its outline
// test, and the whole test where the outline is proven (reproject.cpp, hit_proven).
inline bool hit_polygon_plane(const polygon_geom& g, const ray& r, float tmax, float& t) {
  float dn = glm::dot(g.n, r.d);
  if (dn == 0) return false;
  float tt = (g.d - glm::dot(g.n, r.o)) / dn;
  if (!(tt > 0 && tt < tmax)) return false;
  t = tt;
  return true;
}

inline bool hit_polygon(const polygon_geom& g, const polygon_data& pd, const ray& r, float tmax, float& t) {
  float tt;
  if (!hit_polygon_plane(g, r, tmax, tt)) return false;
  vec3 p = r.o + tt * r.d;
  if (!inside_polygon(g, pd, p[g.ax_u], p[g.ax_v])) return false;
  t = tt;
  return true;
}

inline bool hit_cone(const cone_geom& g, const ray& r, float tmax, float& t) {
  // In double, with the discriminant by Lagrange's identity (b^2/4 - ac = |R dp - S qp|^2 -
  // |qp x dp|^2): in float, |qp|^2 - R^2 cancelled so badly for an eye metres away that a
  // one-ulp turn of a ray near a cone's apex moved its hit by 2e-4 m, and the normal and
  // shading with it (by 1-8% of the radiance), noise no error bound can cover.
  using d3 = glm::dvec3;
  const d3 axis(g.axis), q = d3(r.o) - d3(g.base), dir(r.d);
  const double qa = glm::dot(q, axis), da = glm::dot(dir, axis);
  const d3 qp = q - qa * axis, dp = dir - da * axis;
  const double R = double(g.r0) + double(g.k) * qa, S = double(g.k) * da;  // radius along the ray: R + S t
  const double a = glm::dot(dp, dp) - S * S;
  const double hb = glm::dot(qp, dp) - R * S;  // half of b
  const double c = glm::dot(qp, qp) - R * R;
  const d3 rs = R * dp - S * qp, cr = glm::cross(qp, dp);
  const double disc = glm::dot(rs, rs) - glm::dot(cr, cr);
  if (disc < 0) return false;
  double t0, t1;
  if (a == 0) {
    if (hb == 0) return false;
    t0 = t1 = -c / (2 * hb);
  } else {
    const double qq = -(hb + std::copysign(std::sqrt(disc), hb));
    t0 = qq / a;
    t1 = qq != 0 ? c / qq : t0;
    if (t0 > t1) std::swap(t0, t1);
  }
  for (double tt : {t0, t1}) {
    if (!(tt > 0 && tt < double(tmax))) continue;
    const double z = qa + tt * da;
    if (z >= 0 && z <= double(g.h) && double(g.r0) + double(g.k) * z >= 0) return t = float(tt), true;
  }
  return false;
}

// Where the ray meets the disk's plane, in (0, tmax): hit_disk's t before its rim test.
inline bool hit_disk_plane(const disk_geom& g, const ray& r, float tmax, float& t) {
  float dn = glm::dot(g.n, r.d);
  if (dn == 0) return false;
  float tt = glm::dot(g.c - r.o, g.n) / dn;
  if (!(tt > 0 && tt < tmax)) return false;
  t = tt;
  return true;
}

inline bool hit_disk(const disk_geom& g, const ray& r, float tmax, float& t) {
  float tt;
  if (!hit_disk_plane(g, r, tmax, tt)) return false;
  // The rim test in double: |p|^2 of a disk of radius 1e20 overflows float.
  const glm::dvec3 p = glm::dvec3(r.o) + double(tt) * glm::dvec3(r.d) - glm::dvec3(g.c);
  if (glm::dot(p, p) > double(g.r) * double(g.r)) return false;
  t = tt;
  return true;
}

inline bool hit_box(const box_geom& g, const ray& r, float tmax, float& t) {
  vec3 q = r.o - g.c;
  float t0 = -INFINITY, t1 = INFINITY;
  const vec3* ax[3] = {&g.ax0, &g.ax1, &g.ax2};
  for (int i = 0; i < 3; ++i) {
    float o = glm::dot(q, *ax[i]), d = glm::dot(r.d, *ax[i]);
    if (d == 0) {
      if (std::fabs(o) > g.half[i]) return false;
      continue;
    }
    float inv = 1.0f / d;
    float a = (-g.half[i] - o) * inv, b = (g.half[i] - o) * inv;
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
  }
  if (t0 > t1) return false;
  if (t0 > 0 && t0 < tmax) return t = t0, true;  // from outside
  if (t1 > 0 && t1 < tmax) return t = t1, true;  // from inside
  return false;
}

// The outward normal of the face a ray enters a box by (or, from inside, leaves it by),
// decided by the slabs in double: in float, a hit within rounding of an edge (ulps of the
// eye's distance) took either face's normal, so the reference's radiance there was noise
// that a cell proven on one face could not follow (docs/radiance.md).
inline vec3 box_face_normal(const box_geom& g, const ray& r) {
  const glm::dvec3 q = glm::dvec3(r.o) - glm::dvec3(g.c), d = glm::dvec3(r.d);
  const vec3* ax[3] = {&g.ax0, &g.ax1, &g.ax2};
  double t_in = -INFINITY, t_out = INFINITY;
  int k_in = 0, k_out = 0;
  for (int i = 0; i < 3; ++i) {
    const glm::dvec3 a = glm::dvec3(*ax[i]);
    const double o = glm::dot(q, a), di = glm::dot(d, a);
    if (di == 0) continue;  // parallel to the slab: neither enters nor leaves by it
    const double lo = (-double(g.half[i]) - o) / di, hi = (double(g.half[i]) - o) / di;
    const double enter = std::min(lo, hi), leave = std::max(lo, hi);
    if (enter > t_in) t_in = enter, k_in = di > 0 ? -(i + 1) : i + 1;
    if (leave < t_out) t_out = leave, k_out = di > 0 ? i + 1 : -(i + 1);
  }
  const int k = t_in > 0 ? k_in : k_out;  // +-(axis + 1): the face's outward side
  return k > 0 ? *ax[k - 1] : -*ax[-k - 1];
}

// Can a segment leaving primitive q's surface (towards its facing side) meet q again?
// Never for a plane; never for a convex solid left from the outside. An open cone is the
// side of a convex frustum, so the same holds for it.
// A patch is not: its rays leave along the interpolated shading normal, which may point
// through its own plane, so a shadow or reflected ray may meet the patch itself (the base
// tracer then finds it blocked by its own surface).
inline bool cannot_reenter(shape_kind k, bool from_outside, bool patch) {
  if (patch) return false;
  if (k == shape_kind::triangle || k == shape_kind::polygon || k == shape_kind::disk) return true;
  return (k == shape_kind::sphere || k == shape_kind::box || k == shape_kind::cone) && from_outside;
}

inline bool hit_shape(const shape& s, const polygon_data& pd, const ray& r, float tmax, float& t) {
  switch (s.kind) {
    case shape_kind::sphere: return hit_sphere(s.sphere, r, tmax, t);
    case shape_kind::triangle: return hit_triangle(s.tri, r, tmax, t);
    case shape_kind::polygon: return hit_polygon(s.poly, pd, r, tmax, t);
    case shape_kind::cone: return hit_cone(s.cone, r, tmax, t);
    case shape_kind::disk: return hit_disk(s.disk, r, tmax, t);
    case shape_kind::box: return hit_box(s.box, r, tmax, t);
  }
  return false;
}

}  // namespace epsray
