// The ray tree of an eye ray (whitted.md 5): which primitive each ray of the recursion hit,
// how each light reached the point, and the reflected / transmitted children. Two rays
// whose trees have the same topology see no radiance discontinuity between them.
// Storage is reused across rays (clear() keeps capacity): no allocation per ray.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace epsray {

// Per light at a hit: lit, behind the surface, or the scene index (>= 0) of a blocker.
// Primitives are named by their index in scene::prims, which does not depend on the BVH.
enum : std::int32_t { light_lit = -1, light_behind = -2 };

struct ray_tree_node {
  std::int32_t prim = -1;        // index into scene::prims; -1: the ray missed everything
  std::int16_t reflect = -1;     // child node indices, -1 when not traced
  std::int16_t refract = -1;
  std::uint32_t lights = 0;      // first of world::light_pos.size() entries in ray_tree::lights
  std::uint8_t entering = 0;     // dot(Ng, D) < 0
  std::uint8_t tir = 0;          // the transmitted child is a total internal reflection
};

struct ray_tree {
  std::vector<ray_tree_node> nodes;  // nodes[0] is the eye ray
  std::vector<std::int32_t> lights;
  void clear() { nodes.clear(), lights.clear(); }
};

bool same_topology(const ray_tree& a, const ray_tree& b);
std::uint64_t topology_hash(const ray_tree& t);

}  // namespace epsray
