#include "predicate/reflect_shaft.h"

#include <algorithm>
#include <cmath>

#include "interp/interval.h"
#include "predicate/jet_vec.h"
#include "predicate/shaft.h"

namespace epsray {

namespace {

// Where the cell's lines (coordinates widened to lo4..hi4) cross the plane at front-plane
// fraction s: their u and v ranges, rounded outwards.
void lines_at(const double lo4[4], const double hi4[4], double s, interval& u, interval& v) {
  u = (1 - s) * interval(lo4[0], hi4[0]) + s * interval(lo4[2], hi4[2]);
  v = (1 - s) * interval(lo4[1], hi4[1]) + s * interval(lo4[3], hi4[3]);
}

// The float box holding [lo, hi] on each axis, rounded outwards.
bounds outward(const double lo[3], const double hi[3]) {
  bounds b;
  for (int i = 0; i < 3; ++i) {
    b.lo[i] = std::nextafter(float(lo[i]), -INFINITY);
    b.hi[i] = std::nextafter(float(hi[i]), INFINITY);
  }
  return b;
}

}  // namespace

bool reflect_beam(const world& w, int prim, const facepair& fp, const float lo[4], const float hi[4], bounds& from,
                  bounds& to) {
  if (fp.flat < 0 || fp.axis != fp.flat || size_t(prim) >= w.shapes.size()) return false;
  const shape_kind k = w.shapes[size_t(prim)].kind;
  if (k != shape_kind::triangle && k != shape_kind::polygon && k != shape_kind::disk) return false;
  // A scene primitive's shading normal may be interpolated; a box face's is the box's.
  if (size_t(prim) < w.scene_prims && w.info[size_t(prim)].patch) return false;
  const bounds& pb = w.prim_bounds[size_t(prim)];
  const int ax = fp.axis;
  if (!(pb.lo[ax] == pb.hi[ax])) return false;
  const double y0 = pb.lo[ax], front = fp.front, back = fp.back;
  if (!(std::fabs(front - back) > 0)) return false;
  // The scene's far side from the plane, on the eye lines' side (the front plane's).
  const bool up = front > y0;  // reflected rays run towards +axis
  const double far = up ? double(w.box.hi[ax]) : double(w.box.lo[ax]);
  // The cell widened as bound_cell widens it: a pixel's float coordinates are within half
  // an ulp of its exact line's.
  const double magnitude = 2 * std::max(glm::length(glm::dvec3(w.box.lo)), glm::length(glm::dvec3(w.box.hi)));
  double lo4[4], hi4[4];
  for (int i = 0; i < 4; ++i) {
    const double pad = 0x1p-20 * (magnitude + std::max(std::fabs(double(lo[i])), std::fabs(double(hi[i]))));
    lo4[i] = double(lo[i]) - pad, hi4[i] = double(hi[i]) + pad;
  }
  // The eye lines past the plane, from y0 to the far side's mirror image 2 y0 - far.
  const double reach = up ? std::max(far - y0, 0.0) : std::max(y0 - far, 0.0);
  const double y_end = up ? y0 - reach : y0 + reach;
  const double s0 = (front - y0) / (front - back), s1 = (front - y_end) / (front - back);
  interval u0, v0, u1, v1;
  lines_at(lo4, hi4, s0, u0, v0);
  lines_at(lo4, hi4, s1, u1, v1);
  // Mirrored: the first box lies in the plane, the second on the scene's far side.
  double alo[3], ahi[3], blo[3], bhi[3];
  alo[ax] = ahi[ax] = y0;
  blo[ax] = bhi[ax] = up ? y0 + reach : y0 - reach;
  alo[fp.u] = u0.lo, ahi[fp.u] = u0.hi, alo[fp.v] = v0.lo, ahi[fp.v] = v0.hi;
  blo[fp.u] = u1.lo, bhi[fp.u] = u1.hi, blo[fp.v] = v1.lo, bhi[fp.v] = v1.hi;
  // Each ray leaves from delta off the plane, from a hit point rounded in float.
  const glm::vec3 grow(w.delta);
  from = with_rounding_margin(outward(alo, ahi));
  to = with_rounding_margin(outward(blo, bhi));
  from.lo -= grow, from.hi += grow, to.lo -= grow, to.hi += grow;
  return family::finite_box(from) && family::finite_box(to);
}

bool list_reflect_candidates(const world& w, int prim, const facepair& fp, const float lo[4], const float hi[4],
                             reflect_candidates& out) {
  out.count = 0;
  bounds from, to;
  if (!reflect_beam(w, prim, fp, lo, hi, from, to)) return false;
  const shaft s = make_shaft(from, to);
  // The BVH's slots whose boxes meet the beam, as its walk would test them, but the
  // mirror's own: a ray leaving a plane from delta off it, away from it, cannot meet it
  // (nor the box a face belongs to, which it leaves outwards).
  const int self = scene_prim_of(w, prim);
  std::uint32_t slots[reflect_candidates::max_prims];
  int n = 0;
  auto visit = [&](int slot) {
    if (int(w.slot_prim[size_t(slot)]) == self) return false;
    if (n == reflect_candidates::max_prims) return true;
    slots[n++] = std::uint32_t(slot);
    return false;
  };
  const bool over =
      !w.tree.nodes2.empty() && detail::shaft_walk(w.tree.nodes2.data(), w.slot_bounds.data(), nullptr, s, 0, visit);
  if (over) return false;
  make_prim_list(w, from, slots, n, out);
  // A ray of the beam meets one of these or nothing (the background); its depth is 2.
  glm::vec3 rlo = w.background, rhi = w.background;
  for (int i = 0; i < out.count; ++i) {
    glm::vec3 mlo, mhi;
    material_radiance(w, w.sc.materials[size_t(w.info[size_t(out.prims[i])].material)], 2, w.rad.lo[3], w.rad.hi[3],
                      mlo, mhi);
    rlo = glm::min(rlo, mlo), rhi = glm::max(rhi, mhi);
  }
  widen_radiance(rlo, rhi);
  out.rad_lo = glm::max(rlo, w.rad.lo[2]), out.rad_hi = glm::min(rhi, w.rad.hi[2]);
  return true;
}

}  // namespace epsray
