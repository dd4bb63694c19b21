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
// Same topology, or, where `defer`, the same but for what an interpolant may leave to
// per-pixel rays: the eye ray's statuses of its first 8 lights, and its reflected and
// transmitted subtrees (whether a transmission is a total internal reflection included).
// The bits of what differs are or-ed into *lights (bit j: light j) and *rays
// (deferred_reflect = 1, deferred_refract = 2). nlights: the scene's lights (each hit
// records that many).
bool same_topology_deferring(const ray_tree& a, const ray_tree& b, std::size_t nlights, bool defer,
                             std::uint32_t* lights, std::uint32_t* rays);
std::uint64_t topology_hash(const ray_tree& t);

}  // namespace epsray
