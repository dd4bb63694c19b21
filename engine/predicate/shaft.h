// Shaft culling (Haines & Wallace, "Shaft Culling for Efficient Ray-Traced Radiosity", 1994):
// which primitives may meet some segment from a point of box A to a point of box B?
// The shaft is the convex hull of A and B, kept as their union box cut by the planes of the
// hull's faces that join A to B. Each such plane holds an edge of A and the parallel edge of
// B, where of the two face directions d1, d2 meeting at that edge A reaches farther along d1
// and B farther along d2; at most 8 planes exist (3 + 3 mixed directions less 1 same-axis
// pair, or 4 + 2). B may be a point (a point light), A may be flat (a polygon's patch).
//
// Everything here is CONSERVATIVE: a box that meets the hull is never culled; a box within
// about shaft_rel_tol * (largest coordinate of the union box) of the hull may be kept too.
#pragma once
#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#if defined(__AVX__)
#include <immintrin.h>
#endif

#include "accel/bvh.h"
#include "geom/bounds.h"

namespace epsray {

// Slack, relative to the largest absolute coordinate of the union box, by which the union
// box is grown and every plane pushed outwards (by at least that distance). Float
// evaluation of a plane over the (grown) union box errs by < 2e-7 of that size, so this
// leaves ample room for the caller's rounding too (a segment end computed as a + t (b - a)
// may stray a few ulps outside A or B). Offsets from a box of size delta around a point
// are the caller's to add: grow A or B first.
constexpr float shaft_rel_tol = 1e-5f;

constexpr int shaft_max_planes = 8;
constexpr int shaft_stack_size = 64;

// Plain data, no allocation. Planes are n . p <= d (n not normalised; two components of n
// are nonzero), SoA for one 8-wide test; unused slots hold n = 0, d = +inf (never reject).
// A default shaft, like the shaft of two empty boxes, is empty: it culls every finite box.
struct alignas(32) shaft {
  static constexpr float inf = std::numeric_limits<float>::infinity();
  float nx[shaft_max_planes] = {}, ny[shaft_max_planes] = {}, nz[shaft_max_planes] = {};
  float d[shaft_max_planes] = {inf, inf, inf, inf, inf, inf, inf, inf};
  bounds box;  // union box of A and B, grown by the slack
  int planes = 0;
};
static_assert(shaft_max_planes == 8);

// The shaft of A and B (either may be flat or a point; an empty one is ignored).
shaft make_shaft(const bounds& a, const bounds& b);

// False only when `box` certainly does not meet the convex hull of A and B.
// Conservative because (1) every half-space kept contains both A and B whole, hence the
// hull and every A-to-B segment, and each is widened by the slack against rounding, and
// (2) a box is culled only if it misses the (grown) union box, or if even its point most
// inside a plane, taken over the box clipped to the union box (the hull lies within it, so
// clipping drops no part of the hull), is still outside that plane. NaN never culls.
// Monotone: a box inside a culled box is culled too (min/max/+/* round monotonically),
// so the BVH walk below culls exactly what a test of every primitive box would.
inline bool shaft_may_overlap(const shaft& s, const bounds& box) {
  // Written as "cull if ...": comparisons with NaN are false, so NaN boxes are kept.
  if (box.lo.x > s.box.hi.x || box.lo.y > s.box.hi.y || box.lo.z > s.box.hi.z || box.hi.x < s.box.lo.x ||
      box.hi.y < s.box.lo.y || box.hi.z < s.box.lo.z)
    return false;
  if (s.planes == 0) return true;
  const float lx = std::max(box.lo.x, s.box.lo.x), ly = std::max(box.lo.y, s.box.lo.y),
              lz = std::max(box.lo.z, s.box.lo.z);
  const float hx = std::min(box.hi.x, s.box.hi.x), hy = std::min(box.hi.y, s.box.hi.y),
              hz = std::min(box.hi.z, s.box.hi.z);
#if defined(__AVX__)
  // Per plane, the box's least n . p: per axis the smaller of n*lo and n*hi.
  const __m256 nx = _mm256_load_ps(s.nx), ny = _mm256_load_ps(s.ny), nz = _mm256_load_ps(s.nz);
  __m256 px = _mm256_min_ps(_mm256_mul_ps(nx, _mm256_set1_ps(lx)), _mm256_mul_ps(nx, _mm256_set1_ps(hx)));
  __m256 py = _mm256_min_ps(_mm256_mul_ps(ny, _mm256_set1_ps(ly)), _mm256_mul_ps(ny, _mm256_set1_ps(hy)));
  __m256 pz = _mm256_min_ps(_mm256_mul_ps(nz, _mm256_set1_ps(lz)), _mm256_mul_ps(nz, _mm256_set1_ps(hz)));
  __m256 least = _mm256_add_ps(_mm256_add_ps(px, py), pz);
  return _mm256_movemask_ps(_mm256_cmp_ps(least, _mm256_load_ps(s.d), _CMP_GT_OQ)) == 0;
#else
  for (int k = 0; k < s.planes; ++k) {
    float least = std::min(s.nx[k] * lx, s.nx[k] * hx) + std::min(s.ny[k] * ly, s.ny[k] * hy) +
                  std::min(s.nz[k] * lz, s.nz[k] * hz);
    if (least > s.d[k]) return false;
  }
  return true;
#endif
}

namespace detail {

// Depth-first walk of the binary nodes from `root`. Should the fixed stack ever fill (the
// builder keeps depth far below 64), the subtree is walked by a nested call instead.
template <class Visit>
bool shaft_walk(const bvh2_node* nodes, const bounds* prim_bounds, const std::uint32_t* slot_prim, const shaft& s,
                std::uint32_t root, Visit& visit) {
  std::uint32_t stack[shaft_stack_size];
  int top = 0;
  std::uint32_t at = root;
  for (;;) {
    const bvh2_node& n = nodes[at];
    if (shaft_may_overlap(s, bounds{n.lo, n.hi})) {
      if (n.count) {
        for (std::uint32_t i = n.index, e = n.index + n.count; i < e; ++i)
          if (shaft_may_overlap(s, prim_bounds[i]) && visit(int(slot_prim ? slot_prim[i] : i))) return true;
      } else {
        if (top < shaft_stack_size)
          stack[top++] = n.index;
        else if (shaft_walk(nodes, prim_bounds, slot_prim, s, n.index, visit))
          return true;
        at = at + 1;
        continue;
      }
    }
    if (top == 0) return false;
    at = stack[--top];
  }
}

}  // namespace detail

// Calls visit(prim_id) for every primitive whose own box may meet the shaft (ids as in
// world::prim_bounds / world::shapes, i.e. BVH leaf order), until visit returns true.
// Returns true when visit stopped it, false when every candidate was visited.
// Conservative because a node is skipped only when its box is culled, and the node's box
// holds every primitive box below it, so (culling being monotone) each of those is culled.
template <class Visit>
bool for_each_in_shaft(const bvh& tree, const std::vector<bounds>& prim_bounds, const shaft& s, Visit&& visit) {
  if (tree.nodes2.empty()) return false;
  return detail::shaft_walk(tree.nodes2.data(), prim_bounds.data(), nullptr, s, 0, visit);
}

// The same over leaf slots that name primitives through slot_prim (world::slot_prim and
// world::slot_bounds, where a split primitive has several slots): a primitive may be
// visited once per slot of it that the shaft may meet.
template <class Visit>
bool for_each_in_shaft(const bvh& tree, const std::vector<bounds>& slot_bounds,
                       const std::vector<std::uint32_t>& slot_prim, const shaft& s, Visit&& visit) {
  if (tree.nodes2.empty()) return false;
  return detail::shaft_walk(tree.nodes2.data(), slot_bounds.data(), slot_prim.data(), s, 0, visit);
}

}  // namespace epsray
