#include "accel/prim_list.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace epsray {

void make_prim_list(const world& w, const bounds& origins, const std::uint32_t* slots, int n, prim_list& l) {
  std::uint32_t order[prim_list::max_prims];
  l.count = std::min(n, prim_list::max_prims);
  for (int i = 0; i < l.count; ++i) {
    l.near[i] = float(box_gap(w.slot_bounds[slots[i]], glm::dvec3(origins.lo), glm::dvec3(origins.hi)) * (1 - 1e-5));
    order[i] = slots[i];
  }
  for (int i = 1; i < l.count; ++i)  // insertion sort: a few entries, and ties keep their order
    for (int j = i; j > 0 && l.near[j] < l.near[j - 1]; --j)
      std::swap(l.near[j], l.near[j - 1]), std::swap(order[j], order[j - 1]);
  for (int i = 0; i < prim_list::max_prims; ++i) {
    // Unused lanes hold an empty box; closest_listed_hit masks them off besides.
    const bounds b = i < l.count ? w.slot_bounds[order[i]] : bounds{glm::vec3(INFINITY), glm::vec3(-INFINITY)};
    l.prims[i] = i < l.count ? std::int32_t(w.slot_prim[order[i]]) : -1;
    for (int k = 0; k < 3; ++k) l.lo[k][i] = b.lo[k], l.hi[k][i] = b.hi[k];
  }
}

}  // namespace epsray
