// A short list of primitives that stands in for the BVH for the rays of one known beam:
// when the list holds every primitive such a ray can meet, its nearest hit among them is
// closest_hit's. Kept nearest first, with the primitives' hit boxes in SoA so that one SSE
// slab test, the BVH's own, checks four at once; the scan stops at the first primitive
// that lies farther from every origin of the beam than the nearest hit found.
#pragma once
#include <immintrin.h>

#include <bit>
#include <cstdint>
#include <limits>

#include "accel/world.h"

namespace epsray {

// Entries are BVH slots (world::slot_bounds), as the BVH's leaves hold them: a large
// primitive split into pieces is tested only when a ray enters one of its pieces' boxes.
struct alignas(16) prim_list {
  static constexpr int max_prims = 24;  // a multiple of 4
  int count = 0;
  std::int32_t prims[max_prims] = {};  // the slot's primitive (world::slot_prim)
  // near[i]: at most the distance from any ray's origin to the slot's box; ascending.
  float near[max_prims] = {};
  alignas(16) float lo[3][max_prims] = {}, hi[3][max_prims] = {};  // the slots' boxes
};

// The list of `n` (at most max_prims) slots, nearest first by their boxes' distance from
// the box `origins` (which must hold every ray's origin), rounded down.
void make_prim_list(const world& w, const bounds& origins, const std::uint32_t* slots, int n, prim_list& l);

// closest_hit's answer for a ray from the list's beam (r.d a unit vector, so t is at least
// the distance to any point of a box it meets there). Two hits at the same t are the BVH's
// to order (it visits nearer boxes first), so a tie walks the BVH after all.
inline bool closest_listed_hit(const world& w, const ray& r, const prim_list& l, hit& h) {
  constexpr float inf = std::numeric_limits<float>::infinity();
  // Bounded by the float just past the best so far, so that a hit at exactly the same t is
  // seen: hits lie at t > 0, where the next float up is one more in the bits.
  float best = inf, reach = inf;
  bool tie = false;
  h.prim = -1;
  const __m128 ox = _mm_set1_ps(r.o.x), oy = _mm_set1_ps(r.o.y), oz = _mm_set1_ps(r.o.z);
  const __m128 ix = _mm_set1_ps(r.inv_d.x), iy = _mm_set1_ps(r.inv_d.y), iz = _mm_set1_ps(r.inv_d.z);
  const __m128 zero = _mm_setzero_ps();
  for (int g = 0; g < l.count && !(l.near[g] > best); g += 4) {
    // The slab test of traverse_bvh, term for term.
    const __m128 t0x = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(&l.lo[0][g]), ox), ix);
    const __m128 t1x = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(&l.hi[0][g]), ox), ix);
    const __m128 t0y = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(&l.lo[1][g]), oy), iy);
    const __m128 t1y = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(&l.hi[1][g]), oy), iy);
    const __m128 t0z = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(&l.lo[2][g]), oz), iz);
    const __m128 t1z = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(&l.hi[2][g]), oz), iz);
    const __m128 tn =
        _mm_max_ps(_mm_max_ps(_mm_min_ps(t0x, t1x), _mm_min_ps(t0y, t1y)), _mm_max_ps(_mm_min_ps(t0z, t1z), zero));
    const __m128 tf = _mm_min_ps(_mm_min_ps(_mm_max_ps(t0x, t1x), _mm_max_ps(t0y, t1y)),
                                 _mm_min_ps(_mm_max_ps(t0z, t1z), _mm_set1_ps(reach)));
    const int lanes = l.count - g < 4 ? (1 << (l.count - g)) - 1 : 15;
    int mask = _mm_movemask_ps(_mm_cmple_ps(tn, _mm_mul_ps(tf, _mm_set1_ps(1.00000024f)))) & lanes;
    for (; mask; mask &= mask - 1) {
      const int i = g + __builtin_ctz(unsigned(mask));
      if (l.near[i] > best) break;
      const int id = l.prims[i];
      float t;
      if (!hit_shape(w.shapes[size_t(id)], w.polys, r, reach, t)) continue;
      if (t == best) {
        tie |= id != h.prim;  // a primitive met again through another of its slots is no tie
      } else {
        best = t, h.t = t, h.prim = id, tie = false;
        reach = std::bit_cast<float>(std::bit_cast<std::uint32_t>(t) + 1);
      }
    }
  }
  if (tie) return closest_hit(w, r, inf, h);
  return h.prim >= 0;
}

}  // namespace epsray
