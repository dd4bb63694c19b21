#include "interp/line_space.h"

#include <algorithm>

namespace epsray {

facepair make_facepair(const bounds& box, int index) {
  facepair f;
  f.index = index;
  f.axis = index / 2;
  f.u = (f.axis + 1) % 3;
  f.v = (f.axis + 2) % 3;
  glm::vec3 ext = box.extent();
  float size = std::max({ext.x, ext.y, ext.z});
  // The planes stay at least half the object's size apart, so lines are well conditioned
  // (a flat object would otherwise give two planes at one place), and clear of the object
  // by a twentieth of its size, so no line starts on its surface (a box face or a sphere's
  // pole on the plane would put every entry at t = 0, which the predicate cannot order).
  // Less slab means smaller root cells. The absolute term covers points.
  float margin = std::max(0.05f * size, 0.25f * size - 0.5f * ext[f.axis]) + 1e-6f * (1 + glm::length(box.centre()));
  float lo = box.lo[f.axis] - margin, hi = box.hi[f.axis] + margin;
  bool positive = index % 2 == 0;
  f.front = positive ? lo : hi;
  f.back = positive ? hi : lo;
  // A line with |d_u| <= |d_axis| moves at most (hi - lo) sideways between the planes.
  float depth = hi - lo;
  for (int k = 0; k < 2; ++k) {
    int ax = k == 0 ? f.u : f.v;
    f.lo[k] = f.lo[k + 2] = box.lo[ax] - depth;
    f.hi[k] = f.hi[k + 2] = box.hi[ax] + depth;
  }
  return f;
}

}  // namespace epsray
