// A binary BVH built by binned SAH over primitive bounds: flat 32-byte nodes in depth-first
// order, walked with a fixed stack. Knows nothing of shapes; leaves call back.
#pragma once
#include <cstdint>
#include <vector>

#include "geom/bounds.h"

namespace epsray {

struct bvh_node {
  vec3 lo;
  std::uint32_t index;  // leaf: first primitive; interior: second child (first is this + 1)
  vec3 hi;
  std::uint16_t count;  // primitives in a leaf, 0 for an interior node
  std::uint8_t axis;    // split axis: visit the child on the ray's side first
  std::uint8_t pad;
};
static_assert(sizeof(bvh_node) == 32);

struct bvh {
  std::vector<bvh_node> nodes;
  std::vector<int> order;  // order[i]: the input index of the i-th primitive in leaf order
};

struct bvh_params {
  int max_leaf = 4;        // SAH may stop earlier; never more than this many per leaf...
  int bins = 16;
  float traversal_cost = 1.0f;  // relative to one primitive test
};

bvh build_bvh(const std::vector<bounds>& prims, const bvh_params& params = {});

constexpr int bvh_stack_size = 64;

// Visits leaves front to back. `leaf(first, count, tmax)` tests the primitives and may
// shrink tmax; `any` stops at the first leaf that returns true (shadow rays).
template <bool any, class Leaf>
inline bool traverse_bvh(const bvh& b, const ray& r, float& tmax, Leaf&& leaf) {
  if (b.nodes.empty()) return false;
  std::uint32_t stack[bvh_stack_size];
  int top = 0;
  std::uint32_t node = 0;
  bool found = false;
  const bool neg[3] = {r.d.x < 0, r.d.y < 0, r.d.z < 0};
  const bvh_node* nodes = b.nodes.data();
  for (;;) {
    const bvh_node& n = nodes[node];
    float tn;
    if (hit_bounds(n.lo, n.hi, r, tmax, tn)) {
      if (n.count) {
        if (leaf(n.index, n.count, tmax)) {
          found = true;
          if constexpr (any) return true;
        }
      } else {
        std::uint32_t near = node + 1, far = n.index;
        if (neg[n.axis]) std::swap(near, far);
        stack[top++] = far;
        node = near;
        continue;
      }
    }
    if (top == 0) break;
    node = stack[--top];
  }
  return found;
}

}  // namespace epsray
