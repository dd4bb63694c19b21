#include "geom/shape_build.h"

#include <algorithm>
#include <cmath>

namespace epsray {

namespace {
bounds disk_bounds(vec3 c, vec3 n, float r) {
  vec3 e = r * glm::sqrt(glm::max(vec3(0), vec3(1) - n * n));
  return bounds{c - e, c + e};
}
}  // namespace

vec3 perpendicular(vec3 n) {
  vec3 a = std::fabs(n.x) < 0.9f ? vec3(1, 0, 0) : vec3(0, 1, 0);
  return glm::normalize(glm::cross(n, a));
}

uv_frame fixed_uv_frame(const scene& s, const primitive& p) {
  uv_frame f;
  switch (p.kind) {
    case prim_kind::polygon:
    case prim_kind::patch: {
      const vec3* v = &s.vertices[size_t(p.first)];
      f.o = v[0];
      f.eu = glm::normalize(v[1] - v[0]);
      f.ev = glm::cross(polygon_normal(s, p), f.eu);
      break;
    }
    case prim_kind::disk:
      f.o = p.a;
      f.eu = perpendicular(p.b);
      f.ev = glm::cross(p.b, f.eu);
      break;
    default: break;
  }
  return f;
}

vec3 polygon_normal(const scene& s, const primitive& p) {
  const vec3* v = &s.vertices[size_t(p.first)];
  glm::dvec3 n = glm::cross(glm::dvec3(v[1]) - glm::dvec3(v[0]), glm::dvec3(v[2]) - glm::dvec3(v[1]));
  return vec3(glm::normalize(n));
}

bounds primitive_bounds(const scene& s, const primitive& p) {
  switch (p.kind) {
    case prim_kind::sphere: return bounds{p.a - std::fabs(p.r0), p.a + std::fabs(p.r0)};
    case prim_kind::cone: {
      vec3 n = glm::normalize(p.b - p.a);
      bounds b = disk_bounds(p.a, n, std::fabs(p.r0));
      b.grow(disk_bounds(p.b, n, std::fabs(p.r1)));
      return b;
    }
    case prim_kind::polygon:
    case prim_kind::patch: {
      bounds b;
      for (int i = 0; i < p.count; ++i) b.grow(s.vertices[size_t(p.first + i)]);
      return b;
    }
    case prim_kind::disk: return disk_bounds(p.a, p.b, p.r0);
    case prim_kind::box: {
      vec3 e = glm::abs(p.frame[0]) * p.b.x + glm::abs(p.frame[1]) * p.b.y + glm::abs(p.frame[2]) * p.b.z;
      return bounds{p.a - e, p.a + e};
    }
  }
  return {};
}

namespace {

// Buckets edges by the band range of their v interval, using the query's own band
// function, so every v an edge straddles finds the edge in its band.
void make_bands(polygon_geom& g, polygon_data& pd) {
  g.bands = 0, g.band_first = 0, g.v0 = 0, g.inv_band = 0;
  if (g.count < 12) return;  // walking a dozen edges is as fast as a band lookup
  const vec2* v = pd.verts.data() + g.first;
  float lo = v[0].y, hi = v[0].y;
  for (int i = 1; i < g.count; ++i) lo = std::min(lo, v[i].y), hi = std::max(hi, v[i].y);
  if (!(hi > lo)) return;
  g.bands = std::min(64, g.count / 2);
  g.v0 = lo;
  g.inv_band = float(g.bands) / (hi - lo);
  g.band_first = std::int32_t(pd.band_begin.size());
  std::vector<std::vector<std::int32_t>> lists(size_t(g.bands));
  for (int i = 0; i < g.count; ++i) {
    vec2 a = v[i == 0 ? g.count - 1 : i - 1], b = v[i];
    int b0 = polygon_band(g, std::min(a.y, b.y)), b1 = polygon_band(g, std::max(a.y, b.y));
    for (int k = b0; k <= b1; ++k) lists[size_t(k)].push_back(i);
  }
  for (const auto& l : lists) {
    pd.band_begin.push_back(std::int32_t(pd.band_edges.size()));
    pd.band_edges.insert(pd.band_edges.end(), l.begin(), l.end());
  }
  pd.band_begin.push_back(std::int32_t(pd.band_edges.size()));
}

}  // namespace

shape make_shape(const scene& s, const primitive& p, polygon_data& pd) {
  shape out;
  switch (p.kind) {
    case prim_kind::sphere:
      out.kind = shape_kind::sphere;
      out.sphere = {p.a, p.r0};
      break;
    case prim_kind::cone: {
      out.kind = shape_kind::cone;
      vec3 axis = p.b - p.a;
      float h = glm::length(axis);
      float r0 = std::fabs(p.r0), r1 = std::fabs(p.r1);
      out.cone = {p.a, axis / h, h, r0, (r1 - r0) / h};
      break;
    }
    case prim_kind::polygon:
    case prim_kind::patch: {
      const vec3* v = &s.vertices[size_t(p.first)];
      if (p.count == 3) {
        out.kind = shape_kind::triangle;
        out.tri = {v[0], v[1] - v[0], v[2] - v[0], polygon_normal(s, p)};
        break;
      }
      out.kind = shape_kind::polygon;
      vec3 n = polygon_normal(s, p);
      vec3 an = glm::abs(n);
      int drop = an.x > an.y ? (an.x > an.z ? 0 : 2) : (an.y > an.z ? 1 : 2);
      int u = (drop + 1) % 3, w = (drop + 2) % 3;
      out.poly = {n, glm::dot(n, v[0]), std::int32_t(pd.verts.size()), p.count, u, w, 0, 0, 0, 0};
      for (int i = 0; i < p.count; ++i) pd.verts.push_back({v[i][u], v[i][w]});
      make_bands(out.poly, pd);
      break;
    }
    case prim_kind::disk:
      out.kind = shape_kind::disk;
      out.disk = {p.a, p.b, p.r0};
      break;
    case prim_kind::box:
      out.kind = shape_kind::box;
      out.box = {p.a, p.frame[0], p.frame[1], p.frame[2], p.b};
      break;
  }
  return out;
}

}  // namespace epsray
