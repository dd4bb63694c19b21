#include "interp/line_space.h"

#include <algorithm>

namespace epsray {

facepair make_facepair(const bounds& box, int index) {
  facepair f;
  f.index = index;
  f.axis = index / 2;
  f.u = (f.axis + 1) % 3;
  f.v = (f.axis + 2) % 3;
  f.flat = flat_axis(box);
  glm::vec3 ext = box.extent();
  const float tiny = 1e-6f * (1 + glm::length(box.centre()));
  const bool positive = index % 2 == 0;
  float wide_front, wide_back;  // how far the root's front and back ranges reach past the box
  if (f.flat == f.axis) {
    // Lines no flatter than flat_slope move at most flat_slope times a plane's distance
    // from the surface sideways between the plane and the hit (a little more for rounding).
    const float size = std::max(ext[f.u], ext[f.v]);
    const float near = 0.3f * size + tiny, beyond = 0.005f * size + tiny;
    const float s = box.lo[f.axis];
    f.front = positive ? s - near : s + near;
    f.back = positive ? s + beyond : s - beyond;
    wide_front = 1.001f * flat_slope * near + tiny, wide_back = 1.001f * flat_slope * beyond + tiny;
  } else {
    float size = std::max({ext.x, ext.y, ext.z});
    // The planes stay at least half the object's size apart, so lines are well conditioned
    // (a flat object would otherwise give two planes at one place), and clear of the object
    // by a twentieth of its size, so no line starts on its surface (a box face or a sphere's
    // pole on the plane would put every entry at t = 0, which the predicate cannot order).
    // Less slab means smaller root cells. The absolute term covers points.
    float margin = std::max(0.05f * size, 0.25f * size - 0.5f * ext[f.axis]) + tiny;
    float lo = box.lo[f.axis] - margin, hi = box.hi[f.axis] + margin;
    f.front = positive ? lo : hi;
    f.back = positive ? hi : lo;
    // A line with |d_u| <= |d_axis| moves at most (hi - lo) sideways between the planes.
    wide_front = wide_back = hi - lo;
  }
  for (int k = 0; k < 2; ++k) {
    int ax = k == 0 ? f.u : f.v;
    f.lo[k] = box.lo[ax] - wide_front, f.hi[k] = box.hi[ax] + wide_front;
    f.lo[k + 2] = box.lo[ax] - wide_back, f.hi[k + 2] = box.hi[ax] + wide_back;
  }
  return f;
}

}  // namespace epsray
