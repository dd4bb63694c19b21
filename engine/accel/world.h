// Everything the tracer needs, built once from a parsed scene: shapes in BVH leaf order,
// their materials, the lights with the SPD convention applied, and the spec's delta.
#pragma once
#include <cmath>
#include <vector>

#include "accel/bvh.h"
#include "geom/shape_build.h"
#include "geom/shapes.h"
#include "scene/camera.h"
#include "scene/scene.h"
#include "shade/radiance_bound.h"
#include "shade/texture.h"

namespace epsray {

struct shape_info {
  int material = 0;
  int source = 0;      // index into scene::prims
  bool patch = false;  // shading normals interpolated from the vertices
};

struct world {
  scene sc;
  std::vector<shape> shapes;  // indexed by primitive id (BVH leaf order)
  std::vector<shape_info> info;
  std::vector<bounds> prim_bounds;  // per primitive id
  // prim_bounds grown by the rounding margin, as the BVH's slot boxes are: every hit a
  // primitive's own test finds lies inside, so a list of candidates may test it first.
  std::vector<bounds> hit_boxes;
  // BVH leaves hold slots: a primitive split into pieces has one slot per piece.
  std::vector<std::uint32_t> slot_prim;  // slot -> primitive id
  std::vector<bounds> slot_bounds;       // slot -> box of that piece
  std::vector<int> shape_of;        // scene::prims index -> primitive id
  polygon_data polys;
  bvh tree;
  std::vector<vec3> light_pos, light_power;
  std::vector<texture_range> texture_ranges;  // per scene texture
  std::vector<uv_frame> uv_frames;  // per primitive id: polygons, patches and disks (surface_uv)
  vec3 ambient{0}, background{0};
  // Box faces' own linetree objects (add_face_prims in world.cpp): primitive ids from
  // scene_prims on are rectangles in the planes of axis-aligned, opaque, untextured boxes'
  // faces, larger than the faces and in no BVH: no ray ever meets them, only linetrees are
  // keyed by them.
  size_t scene_prims = 0;            // primitives in the BVH: ids [0, scene_prims)
  std::vector<std::int32_t> face_prims;  // 6 per scene primitive (2 axis + (outward normal < 0)), -1: none
  std::vector<std::int32_t> face_owner;  // per primitive id: the box of a face rectangle, else -1
  bounds box;        // tight bounds of the primitives
  float delta = 0;   // 1e-4 of the box diagonal: origin offset of secondary rays
  radiance_range rad;  // what a ray of each depth can carry (error allowances, whitted.h)
};

world make_world(scene s);

struct hit {
  float t = 0;
  int prim = -1;
};

// The eye ray with direction d. An eye far outside the scene (beyond 16 box diagonals)
// starts it instead where the line comes within two diagonals of the box's centre, found in
// double: no primitive lies before that point, and a float hit found from the far eye
// rounds at the eye's distance, past the spec's secondary-ray offset delta (the reference
// itself showed shadow acne 10^4 scene sizes away). Elsewhere the ray is the eye's own.
inline ray eye_ray(const world& w, const camera& cam, vec3 d) {
  const glm::dvec3 o(cam.origin), dd(d), oc = glm::dvec3(w.box.centre()) - o, ext(w.box.extent());
  const double diag2 = glm::dot(ext, ext);  // squared: no square root on every pixel's way
  if (!(glm::dot(oc, oc) > 256.0 * diag2)) return make_ray(cam.origin, d);
  const double t0 = glm::dot(oc, dd) - 2.0 * std::sqrt(diag2);
  if (!(t0 > 0)) return make_ray(cam.origin, d);
  return make_ray(vec3(o + t0 * dd), d);
}

// The face rectangle (world::face_prims) whose linetree holds the eye ray r that hits
// primitive prim, or -1: the face box_face_normal gives, as the reference shades it.
inline int face_prim_of(const world& w, int prim, const ray& r) {
  if (size_t(prim) >= w.scene_prims || w.shapes[size_t(prim)].kind != shape_kind::box) return -1;
  const std::int32_t* f = &w.face_prims[6 * size_t(prim)];
  if (f[0] < 0 && f[2] < 0 && f[4] < 0) return -1;
  const vec3 n = box_face_normal(w.shapes[size_t(prim)].box, r);  // +-e_k: the box is axis-aligned
  const int k = n.x != 0 ? 0 : (n.y != 0 ? 1 : 2);
  return f[2 * k + (n[k] < 0 ? 1 : 0)];
}

// The primitive in the BVH that primitive id stands for: a face rectangle's box, else id.
inline int scene_prim_of(const world& w, int id) {
  return size_t(id) < w.scene_prims ? id : w.face_owner[size_t(id)];
}

// Nearest hit with 0 < t < tmax.
inline bool closest_hit(const world& w, const ray& r, float tmax, hit& h) {
  const shape* shapes = w.shapes.data();
  const std::uint32_t* slot = w.slot_prim.data();
  const polygon_data& pd = w.polys;
  return traverse_bvh<false>(w.tree, r, tmax, [&](std::uint32_t first, std::uint32_t count, float& tm) {
    bool any = false;
    for (std::uint32_t i = first; i < first + count; ++i) {
      float t;
      std::uint32_t id = slot[i];
      if (hit_shape(shapes[id], pd, r, tm, t)) tm = t, h.t = t, h.prim = int(id), any = true;
    }
    return any;
  });
}

// Some primitive with 0 < t < tmax, or -1: the shadow test (any hit, early exit).
inline int first_blocker(const world& w, const ray& r, float tmax) {
  const shape* shapes = w.shapes.data();
  const std::uint32_t* slot = w.slot_prim.data();
  const polygon_data& pd = w.polys;
  int blocker = -1;
  traverse_bvh<true>(w.tree, r, tmax, [&](std::uint32_t first, std::uint32_t count, float& tm) {
    for (std::uint32_t i = first; i < first + count; ++i) {
      float t;
      if (hit_shape(shapes[slot[i]], pd, r, tm, t)) return blocker = int(slot[i]), true;
    }
    return false;
  });
  return blocker;
}

}  // namespace epsray
