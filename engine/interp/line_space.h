// The 4D line parameterization of section 4.1: a line crossing an object's facepair is
// named by its intercepts (a, b) with the front plane and (c, d) with the back plane.
// Six facepairs per object, chosen by the ray's dominant axis and its sign, cover every
// line through the object's box; a flat object (below) holds most of its lines in the
// facepair of its normal axis instead.
#pragma once
#include <glm/glm.hpp>

#include <cmath>

#include "geom/bounds.h"

namespace epsray {

struct facepair {
  int index = 4;            // 2 * axis + (rays travel towards -axis)
  int axis = 2;             // dominant axis of the rays it holds
  int u = 0, v = 1;         // the two other axes: a, c along u; b, d along v
  float front = 0, back = 0;  // axis coordinates of the planes (rays travel front -> back)
  float lo[4] = {0, 0, 0, 0}, hi[4] = {0, 0, 0, 0};  // root cell: a, b, c, d ranges
  int flat = -1;            // the object's flat axis (flat_axis), -1 when it has none
};

// A flat object lies in a plane normal to an axis (an axis-aligned polygon or disk: its
// box has no extent along that axis and some along the others); -1 for any other.
// Such an object's lines are held by the facepair of its normal axis whenever they are
// no flatter than flat_slope (|d_u|, |d_v| <= flat_slope |d_axis|), and that facepair's
// back plane hugs the surface: a line's hit point is then almost its (c, d), so a cell's
// corner lines meet the object where its pixels do. With the planes of the dominant
// axis, an eye inside the room (inside a floor's or a wall's slab) saw cells whose
// corners met the floor over several times the pixels' footprint, and disagreed on
// shadows the pixels did not straddle.
constexpr float flat_slope = 16;
inline int flat_axis(const bounds& box) {
  const glm::vec3 e = box.extent();
  for (int k = 0; k < 3; ++k)
    if (e[k] == 0 && e[(k + 1) % 3] > 0 && e[(k + 2) % 3] > 0) return k;
  return -1;
}

// Index 0..5 of the facepair holding direction d: 2 * axis + (d[axis] < 0).
inline int facepair_of(glm::vec3 d) {
  glm::vec3 a = glm::abs(d);
  int axis = a.x >= a.y ? (a.x >= a.z ? 0 : 2) : (a.y >= a.z ? 1 : 2);
  return 2 * axis + (d[axis] < 0 ? 1 : 0);
}

// Index of the facepair of an object with flat axis `flat` (-1: none) that holds direction d.
inline int facepair_for(int flat, glm::vec3 d) {
  if (flat >= 0) {
    const float lim = flat_slope * std::fabs(d[flat]);
    if (std::fabs(d[(flat + 1) % 3]) <= lim && std::fabs(d[(flat + 2) % 3]) <= lim) return 2 * flat + (d[flat] < 0 ? 1 : 0);
  }
  return facepair_of(d);
}

// The facepair `index` of an object with bounds `box`: the box is pushed out along the
// axis by a margin (so flat objects get two distinct planes) and widened sideways by the
// slab's depth, so every line whose dominant axis is `axis` and which meets the box
// crosses both faces inside the root cell. A flat object's normal-axis facepair has its
// front plane 0.3 of the object's size before the surface and its back plane just
// behind it, widened by flat_slope times each plane's distance from the surface.
facepair make_facepair(const bounds& box, int index);

// Intercepts of the line o + t d with the facepair's planes. In double, rounded once: a
// pixel's coordinates are then within half an ulp of its float ray's exact line, however far
// the eye stands from the object (in float, o's rounding entered at the eye's magnitude),
// which the predicate's widening of each cell by 16 ulps covers (bound_cell).
// Where the line o + t d meets the plane at axis coordinate `at`: its u and v, in double.
inline glm::dvec2 plane_intercept(const facepair& f, glm::vec3 o, glm::vec3 d, double at) {
  const double t = (at - double(o[f.axis])) / double(d[f.axis]);
  return {double(o[f.u]) + t * double(d[f.u]), double(o[f.v]) + t * double(d[f.v])};
}

inline void line_coords(const facepair& f, glm::vec3 o, glm::vec3 d, float abcd[4]) {
  const glm::dvec2 front = plane_intercept(f, o, d, f.front), back = plane_intercept(f, o, d, f.back);
  abcd[0] = float(front.x), abcd[1] = float(front.y), abcd[2] = float(back.x), abcd[3] = float(back.y);
}

// The point (a, b) of the plane at axis coordinate `at`, in the facepair's u and v.
inline glm::vec3 plane_point(const facepair& f, float at, float a, float b) {
  glm::vec3 p;
  p[f.axis] = at, p[f.u] = a, p[f.v] = b;
  return p;
}

// The line through (a, b) on the front plane and (c, d) on the back plane.
inline glm::vec3 front_point(const facepair& f, float a, float b) { return plane_point(f, f.front, a, b); }
inline glm::vec3 back_point(const facepair& f, float c, float d) { return plane_point(f, f.back, c, d); }

// Is the eye strictly in front of the front plane? Only then is an eye ray's first hit on
// the object the same as its line's first hit after the front plane.
inline bool in_front(const facepair& f, glm::vec3 eye) {
  return f.back > f.front ? eye[f.axis] < f.front : eye[f.axis] > f.front;
}

}  // namespace epsray
