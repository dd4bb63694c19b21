#include "predicate/shaft_shape.h"

#include <algorithm>
#include <cmath>

namespace epsray {

namespace {

using dvec3 = glm::dvec3;

struct span {
  double lo = INFINITY, hi = -INFINITY;
  void add(double v) { lo = std::min(lo, v), hi = std::max(hi, v); }
  void add(double centre, double radius) { lo = std::min(lo, centre - radius), hi = std::max(hi, centre + radius); }
};

dvec3 dv(vec3 v) { return dvec3(v); }

// A disk's reach along n: its radius times the part of n across its normal m.
double rim_reach(dvec3 n, dvec3 m, double r) {
  const double mm = glm::dot(m, m), nm = glm::dot(n, m);
  return r * std::sqrt(std::max(0.0, glm::dot(n, n) - (mm > 0 ? nm * nm / mm : 0.0)));
}

// The primitive's extent along n (a convex set holding it: see the header).
span extent(const world& w, int prim, dvec3 n) {
  const shape& sh = w.shapes[size_t(prim)];
  span out;
  switch (sh.kind) {
    case shape_kind::sphere:
      out.add(glm::dot(n, dv(sh.sphere.c)), std::fabs(double(sh.sphere.r)) * glm::length(n));
      break;
    case shape_kind::triangle: {
      const dvec3 v0 = dv(sh.tri.v0);
      out.add(glm::dot(n, v0)), out.add(glm::dot(n, v0 + dv(sh.tri.e1))), out.add(glm::dot(n, v0 + dv(sh.tri.e2)));
      break;
    }
    case shape_kind::polygon: {
      const primitive& pr = w.sc.prims[size_t(w.info[size_t(prim)].source)];
      for (int i = 0; i < pr.count; ++i) out.add(glm::dot(n, dv(w.sc.vertices[size_t(pr.first + i)])));
      break;
    }
    case shape_kind::cone: {
      // The hull of the two caps (radius clamped at 0) holds the cone, an apex inside
      // [0, h] included: there the surface narrows faster than the hull does.
      const cone_geom& g = sh.cone;
      const dvec3 axis = dv(g.axis), c0 = dv(g.base), c1 = c0 + axis * double(g.h);
      const double r0 = std::max(0.0, double(g.r0)), r1 = std::max(0.0, double(g.r0) + double(g.k) * double(g.h));
      out.add(glm::dot(n, c0), rim_reach(n, axis, r0));
      out.add(glm::dot(n, c1), rim_reach(n, axis, r1));
      break;
    }
    case shape_kind::disk:
      out.add(glm::dot(n, dv(sh.disk.c)), rim_reach(n, dv(sh.disk.n), double(sh.disk.r)));
      break;
    case shape_kind::box: {
      const box_geom& g = sh.box;
      const double r = double(g.half.x) * std::fabs(glm::dot(n, dv(g.ax0))) +
                       double(g.half.y) * std::fabs(glm::dot(n, dv(g.ax1))) +
                       double(g.half.z) * std::fabs(glm::dot(n, dv(g.ax2)));
      out.add(glm::dot(n, dv(g.c)), r);
      break;
    }
  }
  return out;
}

bool empty_box(const bounds& b) { return !(b.lo.x <= b.hi.x && b.lo.y <= b.hi.y && b.lo.z <= b.hi.z); }

// The corners of A and B (the hull's vertices are among them) along u.
span hull_extent(const bounds& a, const bounds& b, dvec3 u) {
  span out;
  for (const bounds* box : {&a, &b}) {
    if (empty_box(*box)) continue;
    for (int c = 0; c < 8; ++c)
      out.add(glm::dot(u, dvec3((c & 1) ? box->hi.x : box->lo.x, (c & 2) ? box->hi.y : box->lo.y,
                                (c & 4) ? box->hi.z : box->lo.z)));
  }
  return out;
}

// The directions a primitive's own faces give: a box's axes, a cone's axis, a normal.
int own_axes(const shape& sh, dvec3 (&out)[3]) {
  switch (sh.kind) {
    case shape_kind::box: out[0] = dv(sh.box.ax0), out[1] = dv(sh.box.ax1), out[2] = dv(sh.box.ax2); return 3;
    case shape_kind::cone: out[0] = dv(sh.cone.axis); return 1;
    case shape_kind::triangle: out[0] = dv(sh.tri.n); return 1;
    case shape_kind::polygon: out[0] = dv(sh.poly.n); return 1;
    case shape_kind::disk: out[0] = dv(sh.disk.n); return 1;
    case shape_kind::sphere: return 0;
  }
  return 0;
}

dvec3 centre(const bounds& b) { return 0.5 * (dv(b.lo) + dv(b.hi)); }

}  // namespace

bool shape_may_meet_shaft(const world& w, int prim, const shaft& s, const bounds& a, const bounds& b) {
  if (empty_box(a) && empty_box(b)) return false;  // as make_shaft: an empty shaft meets nothing
  const bounds& pb = w.prim_bounds[size_t(prim)];
  double scale = 1;
  for (int i = 0; i < 3; ++i)
    scale = std::max({scale, std::fabs(double(s.box.lo[i])), std::fabs(double(s.box.hi[i])),
                      std::fabs(double(pb.lo[i])), std::fabs(double(pb.hi[i]))});
  if (!std::isfinite(scale)) return true;
  const double margin = 2e-5 * scale;
  for (int k = 0; k < s.planes; ++k) {
    const dvec3 n(s.nx[k], s.ny[k], s.nz[k]);
    // Written as "cull if ...": NaN never culls.
    if (extent(w, prim, n).lo > double(s.d[k]) + margin * glm::length(n)) return false;
  }
  // Candidate separating directions besides the shaft's faces: the primitive's own axes;
  // across each of them and the shaft's run from A to B (a pillar beside a diagonal shaft
  // is separated only along the direction across both); and from the primitive's centre
  // straight across to the shaft's middle line (a sphere beside a thin shaft).
  const shape& sh = w.shapes[size_t(prim)];
  dvec3 own[3];
  const int n_own = own_axes(sh, own);
  const dvec3 ca = empty_box(a) ? centre(b) : centre(a), cb = empty_box(b) ? centre(a) : centre(b), run = cb - ca;
  dvec3 axes[8];
  int count = 0;
  for (int i = 0; i < n_own; ++i) axes[count++] = own[i], axes[count++] = glm::cross(own[i], run);
  const dvec3 off = centre(pb) - ca;
  const double rr = glm::dot(run, run);
  axes[count++] = rr > 0 ? off - run * (glm::dot(off, run) / rr) : off;
  for (int i = 0; i < count; ++i) {
    const double len = glm::length(axes[i]);
    if (!(len > 1e-12 * scale)) continue;  // no direction (a run along the axis, a centre on the line)
    const span h = hull_extent(a, b, axes[i]), p = extent(w, prim, axes[i]);
    if (p.lo > h.hi + margin * len || p.hi < h.lo - margin * len) return false;
  }
  return true;
}

}  // namespace epsray
