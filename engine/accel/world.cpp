#include "accel/world.h"

#include <algorithm>
#include <cmath>

#include "geom/shape_build.h"

namespace epsray {

namespace {

// Early split clipping (Ernst & Greiner 2007): a long thin cone or cylinder at an angle to
// the axes has a bounding box mostly empty, which every ray near it must open. It enters
// the BVH as several references (slots), one per length of about two diameters, each boxed
// by the two end circles of its piece.
void add_references(const scene& s, int src, std::vector<bounds>& boxes, std::vector<int>& owner) {
  const primitive& p = s.prims[size_t(src)];
  if (p.kind == prim_kind::cone) {
    vec3 axis = p.b - p.a;
    float len = glm::length(axis);
    float r = std::max(std::fabs(p.r0), std::fabs(p.r1));
    vec3 n = axis / len;
    // Along a coordinate axis the box is tight already; pieces would only add slots.
    bool diagonal = std::max({std::fabs(n.x), std::fabs(n.y), std::fabs(n.z)}) < 0.95f;
    // Clamped before the conversion: len / 4r of a cone 3e38 long is no int.
    int pieces = diagonal ? int(std::clamp(len / (4 * r), 1.0f, 8.0f)) : 1;
    if (pieces > 1) {
      vec3 side = r * glm::sqrt(glm::max(vec3(0), vec3(1) - n * n));  // end circle extent
      for (int k = 0; k < pieces; ++k) {
        vec3 p0 = p.a + axis * (float(k) / float(pieces)), p1 = p.a + axis * (float(k + 1) / float(pieces));
        bounds b{glm::min(p0, p1) - side, glm::max(p0, p1) + side};
        boxes.push_back(b);
        owner.push_back(src);
      }
      return;
    }
  }
  boxes.push_back(primitive_bounds(s, p));
  owner.push_back(src);
}

// Each face of an axis-aligned, opaque, untextured box gets a rectangle of its own, in its
// plane and wider than it on every side (face_prims): pixels that meet the face look it up
// in that rectangle's linetree, whose cells may straddle the box's edges. A point of the
// face's plane off the face shades as a point of the face would (the same normal and
// material; the box lies behind that plane, so it blocks none of the point's shadow or
// reflected rays), so cells along an edge interpolate one smooth function where the box's
// own cells met two faces or missed. Rectangles are appended after the scene's primitives.
void add_face_prims(scene& s, world& w) {
  const size_t n = w.shapes.size();
  w.face_prims.assign(6 * n, -1);
  w.face_owner.assign(n, -1);
  for (size_t id = 0; id < n; ++id) {
    const primitive box = s.prims[size_t(w.info[id].source)];  // a copy: s.prims grows below
    if (box.kind != prim_kind::box || box.frame != glm::mat3(1.0f)) continue;
    const material& m = s.materials[size_t(box.material)];
    if (m.texture >= 0 || m.t > 0) continue;
    const vec3 half = box.b;
    for (int k = 0; k < 3; ++k) {
      const int u = (k + 1) % 3, v = (k + 2) % 3;
      if (!(half[u] > 0 && half[v] > 0)) continue;
      // Wide enough that a cell along an edge, a dozen pixels across, stays on the rectangle.
      const float grow = std::max(std::min(half[u], half[v]), 0.2f * std::max(half[u], half[v]));
      for (int side = 0; side < 2; ++side) {
        const float sgn = side ? -1.0f : 1.0f;
        primitive r;
        r.kind = prim_kind::polygon, r.material = box.material, r.line = box.line;
        r.first = int(s.vertices.size()), r.count = 4;
        // Counter-clockwise about the outward normal sgn e_k (e_u x e_v = e_k).
        const float cu[4] = {-1, 1, 1, -1}, cv[4] = {-1, -1, 1, 1};
        for (int i = 0; i < 4; ++i) {
          const int j = side ? 3 - i : i;
          vec3 p = box.a;
          p[k] += sgn * half[k];
          p[u] += cu[j] * (half[u] + grow), p[v] += cv[j] * (half[v] + grow);
          s.vertices.push_back(p);
        }
        const int src = int(s.prims.size());
        s.prims.push_back(r);
        w.face_prims[6 * id + size_t(2 * k + side)] = int(w.shapes.size());
        w.face_owner.push_back(int(id));
        w.shapes.push_back(make_shape(s, r, w.polys));
        w.info.push_back({r.material, src, false});
        w.prim_bounds.push_back(primitive_bounds(s, r));
      }
    }
  }
}

}  // namespace

world make_world(scene s) {
  world w;
  std::vector<bounds> boxes;
  std::vector<int> owner;  // reference -> scene primitive
  boxes.reserve(s.prims.size());
  for (int i = 0; i < int(s.prims.size()); ++i) add_references(s, i, boxes, owner);
  for (const bounds& b : boxes) w.box.grow(b);  // the scene's own bounds (whitted.md's delta)
  // The BVH must never cull a primitive its own hit test would hit: a box's bounds, c +-
  // half rounded to the nearest float, may lie an ulp inside its faces, and a shadow ray
  // grazing such an edge was then "lit" through the BVH but "blocked" when the last
  // blocker was tried first (trace_state::last_blocker), so a pixel's reference radiance
  // depended on the pixel traced before it. Grown by ~100 ulps, every shape's bounds hold
  // it whatever its test rounds.
  for (bounds& b : boxes) b = with_rounding_margin(b);
  w.tree = build_bvh(boxes);
  // Primitive ids follow the first leaf that references each primitive, for locality.
  std::vector<int> id_of(s.prims.size(), -1);
  w.shapes.reserve(s.prims.size());
  for (int ref : w.tree.order) {
    int src = owner[size_t(ref)];
    if (id_of[size_t(src)] < 0) {
      id_of[size_t(src)] = int(w.shapes.size());
      w.shapes.push_back(make_shape(s, s.prims[size_t(src)], w.polys));
      w.info.push_back({s.prims[size_t(src)].material, src, s.prims[size_t(src)].kind == prim_kind::patch});
      w.prim_bounds.push_back(primitive_bounds(s, s.prims[size_t(src)]));
    }
    w.slot_prim.push_back(std::uint32_t(id_of[size_t(src)]));
    w.slot_bounds.push_back(boxes[size_t(ref)]);
  }
  w.scene_prims = w.shapes.size();
  add_face_prims(s, w);
  w.hit_boxes.reserve(w.prim_bounds.size());
  for (const bounds& b : w.prim_bounds) w.hit_boxes.push_back(with_rounding_margin(b));
  w.shape_of.resize(s.prims.size());
  for (size_t i = 0; i < w.info.size(); ++i) w.shape_of[size_t(w.info[i].source)] = int(i);
  for (const light& l : s.lights) {
    w.light_pos.push_back(l.position);
    w.light_power.push_back(light_intensity(s, l));
  }
  for (const texture& t : s.textures) w.texture_ranges.push_back(range_of(t));
  // Textured pixels ask for these at every hit: computed once (a polygon's normal is a
  // cross product in double and two normalisations).
  w.uv_frames.resize(w.info.size());
  for (size_t i = 0; i < w.info.size(); ++i) w.uv_frames[i] = fixed_uv_frame(s, s.prims[size_t(w.info[i].source)]);
  w.ambient = scene_ambient(s);
  w.background = s.background;
  // The diagonal in double: a sky dome's (2e20 a side) squares past float's range.
  w.delta = w.box.empty() ? 0.0f : float(1e-4 * glm::length(glm::dvec3(w.box.hi) - glm::dvec3(w.box.lo)));
  w.sc = std::move(s);
  w.rad = bound_radiance(w);
  return w;
}

}  // namespace epsray
