#include "predicate/hit_family.h"

#include <algorithm>
#include <cmath>

#include "geom/shape_build.h"

namespace epsray::family {

namespace {

bool segment_meets_rect(double au, double av, double bu, double bv, double u0, double u1, double v0, double v1) {
  // Liang-Barsky clip of the segment against the rectangle.
  double t0 = 0, t1 = 1, du = bu - au, dvv = bv - av;
  auto clip = [&](double p, double q) {
    if (p == 0) return q >= 0;
    double r = q / p;
    if (p < 0) {
      if (r > t1) return false;
      t0 = std::max(t0, r);
    } else {
      if (r < t0) return false;
      t1 = std::min(t1, r);
    }
    return true;
  };
  return clip(-du, au - u0) && clip(du, u1 - au) && clip(-dvv, av - v0) && clip(dvv, v1 - av) && t0 <= t1;
}

}  // namespace

// Is every point of the box (which lies around the primitive's plane) inside it?
bool inside_planar(const world& w, const primitive& pr, const bounds& b, glm::dvec3 n) {
  if (pr.kind == prim_kind::disk) {
    // The farthest corner from the centre must be inside the rim.
    glm::dvec3 far_pt;
    for (int i = 0; i < 3; ++i)
      far_pt[i] = std::fabs(double(b.lo[i]) - pr.a[i]) > std::fabs(double(b.hi[i]) - pr.a[i]) ? b.lo[i] : b.hi[i];
    glm::dvec3 q = far_pt - dv(pr.a);
    q -= glm::dot(q, n) * n;
    return glm::dot(q, q) < double(pr.r0) * double(pr.r0) * (1 - 1e-6);
  }
  // Polygons: project on the plane's dominant axes; the projected box must lie inside,
  // with no edge crossing it (even-odd rule at its centre decides in or out).
  glm::dvec3 an = glm::abs(n);
  int drop = an.x > an.y ? (an.x > an.z ? 0 : 2) : (an.y > an.z ? 1 : 2);
  int u = (drop + 1) % 3, v = (drop + 2) % 3;
  double u0 = b.lo[u], u1 = b.hi[u], v0 = b.lo[v], v1 = b.hi[v];
  double pad = 1e-6 * (std::fabs(u0) + std::fabs(u1) + std::fabs(v0) + std::fabs(v1) + 1e-30);
  u0 -= pad, u1 += pad, v0 -= pad, v1 += pad;
  const vec3* vt = &w.sc.vertices[size_t(pr.first)];
  bool in = false;
  double cu = 0.5 * (u0 + u1), cv = 0.5 * (v0 + v1);
  for (int i = 0, j = pr.count - 1; i < pr.count; j = i++) {
    double au = vt[j][u], av = vt[j][v], bu = vt[i][u], bv = vt[i][v];
    if (segment_meets_rect(au, av, bu, bv, u0, u1, v0, v1)) return false;
    if ((bv > cv) != (av > cv) && cu < au + (cv - av) * (bu - au) / (bv - av)) in = !in;
  }
  return in;
}

namespace {

// Every point of the family p inside a convex polygon (normal n): each edge's half-plane,
// tested on the points themselves. The box around them (inside_planar) pokes out past an
// edge that runs across the axes, which refused most cells of a tessellated surface's
// slanted triangles. False for a concave polygon, or one whose points come within a
// rounding margin of an edge.
bool points_inside_convex(const world& w, const primitive& pr, const jv& p, glm::dvec3 n) {
  if (pr.kind == prim_kind::disk || pr.count < 3) return false;
  const vec3* vt = &w.sc.vertices[size_t(pr.first)];
  const int nv = pr.count;
  double turn = 0;  // the sign of every corner's turn about n: convex when they agree
  for (int i = 0; i < nv; ++i) {
    const glm::dvec3 a = dv(vt[i]), b = dv(vt[(i + 1) % nv]), c = dv(vt[(i + 2) % nv]);
    const double t = glm::dot(glm::cross(b - a, c - b), n);
    if (t == 0) continue;
    if (turn == 0) turn = t;
    else if ((t > 0) != (turn > 0)) return false;
  }
  if (turn == 0) return false;
  for (int i = 0; i < nv; ++i) {
    const glm::dvec3 a = dv(vt[i]), b = dv(vt[(i + 1) % nv]);
    const glm::dvec3 inward = glm::cross(n, b - a) * (turn > 0 ? 1.0 : -1.0);
    const double margin = 2e-6 * glm::length(inward) * (glm::length(a) + glm::length(b) + 1e-30);
    if (!(lo(dot(p - a, inward).v) > margin)) return false;
  }
  return true;
}

// d need not be unit. b^2 - |d|^2 c is written by Lagrange's identity as
// r^2 |d|^2 - |oc x d|^2, as for cones: the difference of two small squares.
cell_reason hit_sphere(const sphere_geom& g, const jv& o, const jv& d, surface_family& s) {
  jv oc = o - dv(g.c);
  djet b = dot(oc, d);
  djet a = norm2(d);
  jv cr = {oc.y * d.z - oc.z * d.y, oc.z * d.x - oc.x * d.z, oc.x * d.y - oc.y * d.x};
  djet disc = a * (double(g.r) * double(g.r)) - dot(cr, cr);
  if (!positive(disc)) return cell_reason::missed;
  djet sq = sqrt(disc);
  djet t0 = (-b - sq) / a, t1 = (-b + sq) / a;
  if (positive(t0)) s.t = t0, s.from_outside = true;
  else if (hi(t0.v) <= 0 && positive(t1)) s.t = t1, s.from_outside = false;
  else return cell_reason::discontinuity;
  s.p = o + d * s.t;
  s.ng = (s.p - dv(g.c)) * (1.0 / double(g.r));
  return cell_reason::valid;
}

// d need not be unit: the point o + d t does not depend on its length, and the cell's
// own lines, given by the unnormalized front-to-back span, meet a plane parallel to the
// facepair's at points affine in (a, b, c, d), with no normalization's range to widen.
cell_reason hit_plane(const world& w, int prim, const jv& o, const jv& d, surface_family& s) {
  const primitive& pr = w.sc.prims[size_t(w.info[size_t(prim)].source)];
  glm::dvec3 n, anchor;
  if (pr.kind == prim_kind::disk) n = dv(pr.b), anchor = dv(pr.a);
  else n = dv(polygon_normal(w.sc, pr)), anchor = dv(w.sc.vertices[size_t(pr.first)]);
  djet dn = dot(d, n);
  if (!(lo(dn.v) > 0 || hi(dn.v) < 0)) return cell_reason::missed;
  s.t = (glm::dot(n, anchor) - dot(o, n)) / dn;
  if (!positive(s.t)) return cell_reason::missed;
  s.p = o + d * s.t;
  s.ng = constant(n);
  s.box = box_on_plane(s.p, n, glm::dot(n, anchor));
  if (!points_inside_convex(w, pr, s.p, n) && !inside_planar(w, pr, s.box, n)) return cell_reason::missed;
  return cell_reason::valid;
}

cell_reason hit_cone(const cone_geom& g, const jv& o, const jv& d, surface_family& s) {
  glm::dvec3 axis = dv(g.axis);
  double k = g.k, r0 = g.r0, h = g.h;
  jv q = o - dv(g.base);
  djet qa = dot(q, axis), da = dot(d, axis);
  jv qp = q - constant(axis) * qa, dp = d - constant(axis) * da;
  djet R = qa * k + r0, S = da * k;
  djet A = dot(dp, dp) - sqr(S);
  djet B = 2.0 * (dot(qp, dp) - R * S);
  if (!(lo(A.v) > 0 || hi(A.v) < 0)) return cell_reason::discontinuity;
  // B^2 - 4AC rewritten by Lagrange's identity as 4 (|R dp - S qp|^2 - |qp x dp|^2): the
  // same value, but as the difference of two small squares instead of large correlated
  // products, so its enclosure is tight enough to prove that a line through the middle
  // of a column meets it (B^2 - 4AC's went negative on 5-pixel cells).
  jv rs = dp * R - qp * S;
  jv cr = {qp.y * dp.z - qp.z * dp.y, qp.z * dp.x - qp.x * dp.z, qp.x * dp.y - qp.y * dp.x};
  djet disc = 4.0 * (dot(rs, rs) - dot(cr, cr));
  if (!positive(disc)) return cell_reason::missed;
  djet sq = sqrt(disc);
  djet ta = (-B - sq) / (2.0 * A), tb = (-B + sq) / (2.0 * A);
  if (hi(A.v) < 0) std::swap(ta, tb);  // ta is the nearer root
  // A root counts only a rounding margin inside or outside the end circles: a pixel whose
  // float line lies a few ulps outside its cell may pass the rim there, and meet the same
  // cone on its far side.
  const double margin = rounding_margin(std::max({std::fabs(g.base.x), std::fabs(g.base.y), std::fabs(g.base.z)}) +
                                        g.h + std::max(std::fabs(g.r0), std::fabs(g.r0 + g.k * g.h)));
  auto valid = [&](const djet& t) {
    djet z = qa + t * da;
    return positive(t) && lo(z.v) > margin && hi(z.v) < h - margin;
  };
  auto invalid = [&](const djet& t) {
    djet z = qa + t * da;
    return hi(t.v) <= 0 || hi(z.v) < -margin || lo(z.v) > h + margin;
  };
  if (valid(ta)) s.t = ta;
  else if (invalid(ta) && valid(tb)) s.t = tb;
  else return cell_reason::missed;
  s.p = o + d * s.t;
  // On the surface the radial vector's length is the radius r0 + k z, and the unit radial
  // minus k * axis has length sqrt(1 + k^2): exact identities, no interval normalize
  // (which would lose |n| = 1 over a wide cell).
  jv rel = s.p - dv(g.base);
  djet z = dot(rel, axis);
  jv radial = rel - constant(axis) * z;
  jv n = radial / (z * k + r0) - constant(axis) * k;
  s.ng = n * (1.0 / std::sqrt(1.0 + k * k));  // the caller flips it for negative radii
  s.from_outside = negative(dot(d, s.ng));       // proven for every ray, or not claimed
  return cell_reason::valid;
}

cell_reason hit_box(const box_geom& g, const jv& o, const jv& d, surface_family& s) {
  const glm::vec3* ax[3] = {&g.ax0, &g.ax1, &g.ax2};
  djet nearv[3], farv[3], dl[3];
  jv q = o - dv(g.c);
  // Lines that may run parallel to a slab (a face seen head-on has two) can enter only
  // through another face, whose rectangle test below bounds them along that slab's axis.
  bool definite[3];
  int n_definite = 0;
  for (int i = 0; i < 3; ++i) {
    djet ol = dot(q, dv(*ax[i]));
    dl[i] = dot(d, dv(*ax[i]));
    definite[i] = lo(dl[i].v) > 0 || hi(dl[i].v) < 0;
    if (!definite[i]) continue;
    ++n_definite;
    djet ta = (-double(g.half[i]) - ol) / dl[i], tb = (double(g.half[i]) - ol) / dl[i];
    if (lo(dl[i].v) > 0) nearv[i] = ta, farv[i] = tb;
    else nearv[i] = tb, farv[i] = ta;
  }
  auto unique_max = [](const djet* t, int& k) {
    for (k = 0; k < 3; ++k) {
      bool ok = true;
      for (int j = 0; j < 3; ++j)
        if (j != k && !(lo(t[k].v) > hi(t[j].v))) ok = false;
      if (ok) return true;
    }
    return false;
  };
  auto unique_min = [](const djet* t, int& k) {
    for (k = 0; k < 3; ++k) {
      bool ok = true;
      for (int j = 0; j < 3; ++j)
        if (j != k && !(hi(t[k].v) < lo(t[j].v))) ok = false;
      if (ok) return true;
    }
    return false;
  };
  // Every line meets face k at a point inside the face's rectangle, kept a rounding margin
  // off its edges: the pixel's line is found in the cell by float coordinates, and across
  // an edge the normal jumps (box_face_normal).
  const double margin = rounding_margin(std::max({std::fabs(g.c.x), std::fabs(g.c.y), std::fabs(g.c.z)}) +
                                        std::max({g.half.x, g.half.y, g.half.z}));
  auto within_face = [&](int k, const djet& t) {
    const jv pk = q + d * t;
    for (int j = 0; j < 3; ++j) {
      if (j == k) continue;
      const djet u = dot(pk, dv(*ax[j]));
      if (!(hi(u.v) < double(g.half[j]) - margin && lo(u.v) > -double(g.half[j]) + margin)) return false;
    }
    return true;
  };
  // From outside: every line enters through face k when its point there lies inside the
  // face's rectangle. Testing the point's own face coordinates keeps the correlation
  // between the slabs' entry and exit times that comparing their separate ranges loses
  // (which failed most cells of a box seen at a slant).
  int k;
  for (k = 0; k < 3; ++k)
    if (definite[k] && positive(nearv[k]) && within_face(k, nearv[k])) break;
  if (k == 3 && n_definite < 3) return cell_reason::discontinuity;
  double max_near_hi = std::max({hi(nearv[0].v), hi(nearv[1].v), hi(nearv[2].v)});
  double min_far_lo = std::min({lo(farv[0].v), lo(farv[1].v), lo(farv[2].v)});
  if (k == 3) {  // else the slabs' ranges: a unique entry face, or the eye inside the box
    if (!(max_near_hi < min_far_lo)) return cell_reason::missed;
    if (!unique_max(nearv, k) || !positive(nearv[k]) || !within_face(k, nearv[k])) k = 3;
  }
  if (k < 3) {
    s.t = nearv[k], s.from_outside = true;
    s.ng = constant(dv(*ax[k]) * (lo(dl[k].v) > 0 ? -1.0 : 1.0));
  } else if (max_near_hi < 0 && unique_min(farv, k) && positive(farv[k]) && within_face(k, farv[k])) {
    s.t = farv[k], s.from_outside = false;
    s.ng = constant(dv(*ax[k]) * (lo(dl[k].v) > 0 ? 1.0 : -1.0));
  } else {
    return cell_reason::discontinuity;
  }
  s.p = o + d * s.t;
  glm::dvec3 nk{mid(s.ng.x.v), mid(s.ng.y.v), mid(s.ng.z.v)};  // the face's outward normal, exact
  s.box = box_on_plane(s.p, nk, glm::dot(nk, dv(g.c)) + double(g.half[k]));
  return cell_reason::valid;
}

}  // namespace

// The family o + t d hits primitive `prim` at its first surface with t > 0, for every ray
// of the cell (else the cell has a gap or changes sheet).
// span, when given, is the family's unnormalized direction (d = span / |span|).
cell_reason hit_family(const world& w, int prim, const jv& o, const jv& d, const jv* span, surface_family& s) {
  const shape& sh = w.shapes[size_t(prim)];
  switch (sh.kind) {
    case shape_kind::sphere: return hit_sphere(sh.sphere, o, span ? *span : d, s);
    case shape_kind::triangle: return hit_plane(w, prim, o, span ? *span : d, s);
    case shape_kind::polygon: return hit_plane(w, prim, o, span ? *span : d, s);
    case shape_kind::disk: return hit_plane(w, prim, o, span ? *span : d, s);
    case shape_kind::cone: return hit_cone(sh.cone, o, span ? *span : d, s);
    case shape_kind::box: return hit_box(sh.box, o, span ? *span : d, s);
  }
  return cell_reason::missed;
}

// Interpolated patch normals: the point family must stay inside one fan triangle.
cell_reason patch_normal(const world& w, const primitive& pr, const jv& p, jv& ns) {
  const vec3* v = &w.sc.vertices[size_t(pr.first)];
  const vec3* n = &w.sc.normals[size_t(pr.first)];
  glm::dvec3 pn = dv(polygon_normal(w.sc, pr));
  for (int i = 1; i + 1 < pr.count; ++i) {
    glm::dvec3 a = dv(v[0]), e1 = dv(v[i]) - a, e2 = dv(v[i + 1]) - a;
    glm::dvec3 c1 = glm::cross(e2, pn), c2 = glm::cross(pn, e1);
    glm::dvec3 b1 = c1 / glm::dot(e1, c1), b2 = c2 / glm::dot(e2, c2);
    jv rel = p - a;
    djet u = dot(rel, b1), vv = dot(rel, b2);
    djet w0 = 1.0 - u - vv;
    if (lo(u.v) >= 0 && lo(vv.v) >= 0 && lo(w0.v) >= 0) {
      jv m = constant(dv(n[0])) * w0 + constant(dv(n[i])) * u + constant(dv(n[i + 1])) * vv;
      ns = normalize(m);
      return cell_reason::valid;
    }
    bool outside = hi(u.v) < 0 || hi(vv.v) < 0 || hi(w0.v) < 0;
    if (!outside) return cell_reason::discontinuity;  // straddles a fan edge: a kink
  }
  return cell_reason::discontinuity;
}

}  // namespace epsray::family
