// BVH over primitive bounds: built binary by binned SAH, then collapsed to 4 children per
// node so one SSE slab test checks four boxes at once. Flat node arrays, a fixed stack,
// children visited nearest first and skipped once the closest hit is nearer.
// Knows nothing of shapes: leaves call back.
#pragma once
#include <immintrin.h>

#include <cstdint>
#include <vector>

#include "geom/bounds.h"

namespace epsray {

// The binary tree as built (kept for tests and statistics).
struct bvh2_node {
  vec3 lo;
  std::uint32_t index;  // leaf: first primitive; interior: second child (first is this + 1)
  vec3 hi;
  std::uint16_t count;  // primitives in a leaf, 0 for an interior node
  std::uint8_t axis;
  std::uint8_t pad;
};
static_assert(sizeof(bvh2_node) == 32);

// Four child boxes in SoA for SSE. child[k] is a node index when count[k] == 0, else the
// first primitive of a leaf of count[k] primitives. Only the first `size` slots are used.
struct alignas(16) bvh4_node {
  float lo[3][4], hi[3][4];
  std::uint32_t child[4];
  std::uint16_t count[4];
  std::uint32_t size;
  std::uint32_t pad[3];
};
static_assert(sizeof(bvh4_node) == 144);

struct bvh {
  std::vector<bvh2_node> nodes2;
  std::vector<bvh4_node> nodes;
  std::vector<int> order;  // order[i]: the input index of the i-th primitive in leaf order
  bounds box;
};

struct bvh_params {
  int max_leaf = 4;
  int bins = 16;
  float traversal_cost = 1.0f;  // relative to one primitive test
};

bvh build_bvh(const std::vector<bounds>& prims, const bvh_params& params = {});

constexpr int bvh_stack_size = 128;

// Visits leaves front to back. `leaf(first, count, tmax)` tests primitives and may shrink
// tmax; with `any`, traversal stops at the first leaf that returns true (shadow rays).
template <bool any, class Leaf>
inline bool traverse_bvh(const bvh& b, const ray& r, float& tmax, Leaf&& leaf) {
  if (b.nodes.empty()) return false;
  float root_near;
  if (!hit_bounds(b.box.lo, b.box.hi, r, tmax, root_near)) return false;
  struct entry {
    std::uint32_t index;
    std::uint32_t count;  // 0: interior node
    float tnear;
  };
  entry stack[bvh_stack_size];
  int top = 0;
  // Slab planes as (lo - o) * inv_d, not the FMA form lo * inv_d - o * inv_d: with a tiny
  // direction component o * inv_d is huge and the difference loses every digit.
  const __m128 ox = _mm_set1_ps(r.o.x), oy = _mm_set1_ps(r.o.y), oz = _mm_set1_ps(r.o.z);
  const __m128 ix = _mm_set1_ps(r.inv_d.x), iy = _mm_set1_ps(r.inv_d.y), iz = _mm_set1_ps(r.inv_d.z);
  const __m128 zero = _mm_setzero_ps();
  const bvh4_node* nodes = b.nodes.data();
  bool found = false;
  entry cur{0, 0, root_near};  // the entry in hand: the nearest child is never pushed
  for (;;) {
    if (cur.count) {
      if (leaf(cur.index, cur.count, tmax)) {
        found = true;
        if constexpr (any) return true;
      }
    } else {
      const bvh4_node& n = nodes[cur.index];
      __m128 t0x = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.lo[0]), ox), ix);
      __m128 t1x = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.hi[0]), ox), ix);
      __m128 t0y = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.lo[1]), oy), iy);
      __m128 t1y = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.hi[1]), oy), iy);
      __m128 t0z = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.lo[2]), oz), iz);
      __m128 t1z = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.hi[2]), oz), iz);
      // Operand order keeps NaN lanes (0 * inf) from widening the interval.
      __m128 tn = _mm_max_ps(_mm_max_ps(_mm_min_ps(t0x, t1x), _mm_min_ps(t0y, t1y)), _mm_max_ps(_mm_min_ps(t0z, t1z), zero));
      __m128 tf = _mm_min_ps(_mm_min_ps(_mm_max_ps(t0x, t1x), _mm_max_ps(t0y, t1y)),
                             _mm_min_ps(_mm_max_ps(t0z, t1z), _mm_set1_ps(tmax)));
      // A few ulps of slack so rays grazing flat boxes (polygons) are kept.
      int mask = _mm_movemask_ps(_mm_cmple_ps(tn, _mm_mul_ps(tf, _mm_set1_ps(1.00000024f)))) & ((1 << n.size) - 1);
      if (mask) {
        alignas(16) float tnear[4];
        _mm_store_ps(tnear, tn);
        if (!(mask & (mask - 1))) {  // one child hit: take it, no stack traffic
          int k = __builtin_ctz(unsigned(mask));
          cur = {n.child[k], n.count[k], tnear[k]};
          continue;
        }
        entry hits[4];
        int nh = 0;
        for (int k = 0; k < 4; ++k) {
          if (!(mask >> k & 1)) continue;
          entry c{n.child[k], n.count[k], tnear[k]};
          int j = nh++;
          if constexpr (!any) {  // farthest first; any hit ends the walk, so order is moot
            while (j > 0 && hits[j - 1].tnear < c.tnear) hits[j] = hits[j - 1], --j;
          }
          hits[j] = c;
        }
        for (int k = 0; k + 1 < nh; ++k) stack[top++] = hits[k];
        cur = hits[nh - 1];  // the nearest (closest hit) or any (shadows)
        continue;
      }
    }
    // Next entry from the stack, skipping those a nearer hit has made pointless.
    do {
      if (top == 0) return found;
      cur = stack[--top];
    } while (cur.tnear > tmax);
  }
}

}  // namespace epsray
