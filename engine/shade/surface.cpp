#include "shade/surface.h"

#include <algorithm>
#include <cmath>

#include "geom/shape_build.h"

namespace epsray {

namespace {

constexpr float pi = 3.14159265358979323846f;

// Barycentric coordinates of p in triangle (a, b, c), p assumed in its plane.
vec3 barycentric(vec3 p, vec3 a, vec3 b, vec3 c) {
  vec3 v0 = b - a, v1 = c - a, v2 = p - a;
  float d00 = glm::dot(v0, v0), d01 = glm::dot(v0, v1), d11 = glm::dot(v1, v1);
  float d20 = glm::dot(v2, v0), d21 = glm::dot(v2, v1);
  float den = d00 * d11 - d01 * d01;
  if (den == 0) return {1, 0, 0};
  float v = (d11 * d20 - d01 * d21) / den, u = (d00 * d21 - d01 * d20) / den;
  return {1 - v - u, v, u};
}

// whitted.md 2: triangles barycentrically; n-gons through the fan triangle holding p.
vec3 patch_normal(const scene& s, const primitive& pr, vec3 p) {
  const vec3* v = &s.vertices[size_t(pr.first)];
  const vec3* n = &s.normals[size_t(pr.first)];
  int best = 1;
  float best_min = -INFINITY;
  vec3 best_b{1, 0, 0};
  for (int i = 1; i + 1 < pr.count; ++i) {
    vec3 b = barycentric(p, v[0], v[i], v[i + 1]);
    float m = std::min({b.x, b.y, b.z});
    if (m > best_min) best_min = m, best = i, best_b = b;
    if (m >= 0) break;
  }
  vec3 ns = best_b.x * n[0] + best_b.y * n[best] + best_b.z * n[best + 1];
  float len = glm::length(ns);
  return len > 0 ? ns / len : polygon_normal(s, pr);
}

}  // namespace

surface surface_at(const world& w, int prim, const ray& r, float t) {
  // Normals come from the 64-byte shape record the hit test just read (hot in cache);
  // only patches and negative-radius cones need the scene's primitive.
  const shape& sh = w.shapes[size_t(prim)];
  surface out;
  out.p = r.o + t * r.d;
  switch (sh.kind) {
    case shape_kind::sphere: out.ng = (out.p - sh.sphere.c) / sh.sphere.r; break;  // negative r flips
    case shape_kind::triangle: out.ng = sh.tri.n; break;
    case shape_kind::polygon: out.ng = sh.poly.n; break;
    case shape_kind::disk: out.ng = sh.disk.n; break;
    case shape_kind::cone: {
      vec3 q = out.p - sh.cone.base;
      vec3 radial = q - glm::dot(q, sh.cone.axis) * sh.cone.axis;
      float rl = safe_length(radial);
      vec3 ru = rl > 0 ? radial / rl : perpendicular(sh.cone.axis);
      out.ng = ru - sh.cone.k * sh.cone.axis;  // gradient of distance-to-axis minus radius
      const primitive& pr = w.sc.prims[size_t(w.info[size_t(prim)].source)];
      if (pr.r0 < 0 || pr.r1 < 0) out.ng = -out.ng;
      break;
    }
    case shape_kind::box: out.ng = box_face_normal(sh.box, r); break;
  }
  out.ng = glm::normalize(out.ng);
  out.ns = out.ng;
  if (w.info[size_t(prim)].patch) {
    const primitive& pr = w.sc.prims[size_t(w.info[size_t(prim)].source)];
    out.ns = patch_normal(w.sc, pr, out.p);
  }
  return out;
}

vec2 surface_uv(const world& w, int prim, vec3 p) {
  const scene& s = w.sc;
  const primitive& pr = s.prims[size_t(w.info[size_t(prim)].source)];
  switch (pr.kind) {
    case prim_kind::sphere: {
      vec3 d = safe_normalize(p - pr.a);
      float r = std::fabs(pr.r0);
      return {(std::atan2(d.y, d.x) + pi) * r, std::acos(std::clamp(d.z, -1.0f, 1.0f)) * r};
    }
    case prim_kind::cone: {
      vec3 axis = safe_normalize(pr.b - pr.a);
      vec3 e1 = perpendicular(axis), e2 = glm::cross(axis, e1);
      vec3 q = p - pr.a;
      float ang = std::atan2(glm::dot(q, e2), glm::dot(q, e1)) + pi;
      return {ang * 0.5f * (std::fabs(pr.r0) + std::fabs(pr.r1)), glm::dot(q, axis)};
    }
    default: {  // planar: polygons, patches, disks, box faces
      vec3 o, eu, ev;
      planar_uv_frame(w, prim, p, o, eu, ev);
      return {glm::dot(p - o, eu), glm::dot(p - o, ev)};
    }
  }
  return {0, 0};
}

bool planar_uv_frame(const world& w, int prim, vec3 p, vec3& o, vec3& eu, vec3& ev) {
  const scene& s = w.sc;
  const primitive& pr = s.prims[size_t(w.info[size_t(prim)].source)];
  switch (pr.kind) {
    case prim_kind::polygon:
    case prim_kind::patch:
    case prim_kind::disk: {
      const uv_frame& f = w.uv_frames[size_t(prim)];
      o = f.o, eu = f.eu, ev = f.ev;
      return true;
    }
    case prim_kind::box: {
      vec3 q = p - pr.a;
      vec3 l{glm::dot(q, pr.frame[0]), glm::dot(q, pr.frame[1]), glm::dot(q, pr.frame[2])};
      vec3 n = glm::abs(l / pr.b);
      int i = n.x > n.y ? (n.x > n.z ? 0 : 2) : (n.y > n.z ? 1 : 2);
      int j = (i + 1) % 3, k = (i + 2) % 3;
      o = pr.a - pr.b[j] * pr.frame[j] - pr.b[k] * pr.frame[k];
      eu = pr.frame[j];
      ev = pr.frame[k];
      return true;
    }
    default: return false;
  }
}

}  // namespace epsray
