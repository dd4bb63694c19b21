#include "predicate/error_predicate.h"

#include <algorithm>
#include <cmath>

#include "geom/shape_build.h"
#include "predicate/djet.h"
#include "predicate/shaft_shape.h"
#include "shade/surface.h"
#include "shade/whitted.h"

namespace epsray {

namespace {

// Affine forms: interval bounds of these expressions over wide cells were 1000x too loose.
using djet = djet_t<affine>;

// A deferrable light whose own bound exceeds this share of the cell's least radiance is
// deferred (evaluator::defer_loose_lights).
constexpr double loose_light_share = 0.05;

djet djet_variable(int i, double l, double h) {
  djet j(affine_variable(i, l, h));
  j.d[i] = affine(1.0);
  return j;
}

// 3-vectors of jets: points and directions of a whole family of rays at once.
struct jv {
  djet x, y, z;
  djet& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  const djet& operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
};
jv operator+(const jv& a, const jv& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
jv operator-(const jv& a, const jv& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
jv operator-(const jv& a) { return {-a.x, -a.y, -a.z}; }
jv operator*(const jv& a, const djet& s) { return {a.x * s, a.y * s, a.z * s}; }
jv operator*(const jv& a, double s) { return {a.x * s, a.y * s, a.z * s}; }
jv operator/(const jv& a, const djet& s) { return {a.x / s, a.y / s, a.z / s}; }
djet dot(const jv& a, const jv& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
djet dot(const jv& a, glm::dvec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
// |a|^2, its value also bounded below through each component's own range: the affine
// product of a form that straddles 0 with itself dips below 0, and over a wide cell that
// left sqrt, and every direction normalized from it, unbounded (teapot-s6's floor cells
// could not prove a highlight's N.H positive, though one component never nears 0).
djet norm2(const jv& a) {
  djet s = dot(a, a);
  if (lo(s.v) > 0) return s;
  double least = 0;  // sum of each component's least square over its range
  for (int i = 0; i < 3; ++i) {
    const double l = lo(a[i].v), h = hi(a[i].v);
    const double m = l > 0 ? l : (h < 0 ? -h : 0.0);
    least += m * m;
  }
  least *= 1 - 1e-12;  // the squares' and the sum's rounding
  if (!(least > 0) || !std::isfinite(hi(s.v))) return s;
  s.v = affine_range(least, hi(s.v));
  return s;
}
jv normalize(const jv& a) { return a / sqrt(norm2(a)); }
jv constant(glm::dvec3 p) { return {djet(p.x), djet(p.y), djet(p.z)}; }
jv operator-(const jv& a, glm::dvec3 b) { return a - constant(b); }

glm::dvec3 dv(glm::vec3 v) { return glm::dvec3(v); }

// The float box holding a family of points, rounded outwards.
bounds box_of(const jv& p) {
  bounds b;
  for (int i = 0; i < 3; ++i) {
    b.lo[i] = std::nextafter(float(lo(p[i].v)), -INFINITY);
    b.hi[i] = std::nextafter(float(hi(p[i].v)), INFINITY);
  }
  return b;
}

// The box of points that lie on the plane n.p = c, tightened by the plane: each coordinate
// is also bounded through the others. Affine forms of o + t d leave a flat family's box
// centimetres thick, touching whatever stands just behind the surface (a canvas' frame).
bounds box_on_plane(const jv& p, glm::dvec3 n, double c) {
  bounds b = box_of(p);
  for (int i = 0; i < 3; ++i) {
    if (std::fabs(n[i]) < 1e-9) continue;
    double lo_s = c, hi_s = c;  // c - sum_{j != i} n_j p_j
    for (int j = 0; j < 3; ++j) {
      if (j == i) continue;
      double a = n[j] * double(b.lo[j]), z = n[j] * double(b.hi[j]);
      lo_s -= std::max(a, z), hi_s -= std::min(a, z);
    }
    double v0 = lo_s / n[i], v1 = hi_s / n[i];
    if (v0 > v1) std::swap(v0, v1);
    const double pad = 1e-6 * (std::fabs(v0) + std::fabs(v1)) + 1e-9;
    b.lo[i] = std::max(b.lo[i], std::nextafter(float(v0 - pad), -INFINITY));
    b.hi[i] = std::min(b.hi[i], std::nextafter(float(v1 + pad), INFINITY));
  }
  return b;
}

bool finite_box(const bounds& b) {
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(b.lo[i]) || !std::isfinite(b.hi[i])) return false;
  return true;
}

bool positive(const djet& x) { return lo(x.v) > 0; }
bool negative(const djet& x) { return hi(x.v) < 0; }

// Can a segment leaving primitive q's surface (towards its facing side) meet q again?
// Never for a plane; never for a convex solid left from the outside. An open cone is the
// side of a convex frustum, so the same holds for it.
// A patch is not: its rays leave along the interpolated shading normal, which may point
// through its own plane, so a shadow or reflected ray may meet the patch itself (the base
// tracer then finds it blocked by its own surface).
bool cannot_reenter(shape_kind k, bool from_outside, bool patch) {
  if (patch) return false;
  if (k == shape_kind::triangle || k == shape_kind::polygon || k == shape_kind::disk) return true;
  return (k == shape_kind::sphere || k == shape_kind::box || k == shape_kind::cone) && from_outside;
}

struct surface_family {
  djet t;
  jv p, ng;            // hit points; outward geometric normals
  bounds box;          // holds every hit point (tighter than p's range on planes)
  bool from_outside = true;  // spheres, boxes, cones: every ray arrives from outside the solid
};

struct evaluator {
  const world& w;
  const ray_tree& tree;
  cell_reason fail = cell_reason::valid;
  double far = 0;  // farther than any scene point from any ray origin we see
  const jv* root_span = nullptr;  // the cell's lines, front point to back point (unnormalized)
  bounds root_hits{};  // where the cell's lines meet the object
  std::uint32_t deferred = 0;  // the root's lights left to per-pixel shadow rays
  std::uint32_t deferred_rays = 0;  // ... and its subtrees left to per-pixel rays
  // The reference's own float noise that no smooth interpolant follows (per channel, in
  // the pixel's units): a highlight max(0, N.H)^shine moves by shine * spec per ulp of
  // N.H, and a float N.H is a few ulps off (bound_cell adds this to the error).
  glm::dvec3 noise{0};
  double path_weight = 1;  // product of ks and t down to the node being bounded
  bool allow_defer = false;         // may more lights and subtrees be deferred
  shadow_candidates shadow{};       // the deferred lights' possible blockers, where few
  double cell_width[4] = {0, 0, 0, 0};  // the cell's extent along each coordinate

  bool reject(cell_reason r) {
    if (fail == cell_reason::valid) fail = r;
    return false;
  }

  // A light's terms at one surface family, before they join its radiance.
  struct light_terms {
    size_t j = 0;
    djet diffuse[3], spec[3];  // diffuse: times the texel on a textured root
    double noise[3] = {0, 0, 0};
  };
  light_terms root_lights[max_deferred_lights]{};  // the root's deferrable lights, bounded
  size_t n_root_lights = 0;

  void add_light(const light_terms& lt, djet* acc, djet* tf) {
    for (int c = 0; c < 3; ++c) {
      if (tf) tf[c] = tf[c] + lt.diffuse[c];
      else acc[c] = acc[c] + lt.diffuse[c];
      acc[c] = acc[c] + lt.spec[c];
      noise[c] += lt.noise[c];
    }
  }

  // A deferrable light of the root whose own interpolation bound exceeds loose_light_share
  // of the cell's least radiance is deferred: its per-pixel shadow ray costs less than the
  // cell's pixels traced, or its children built, for want of a bound only this light
  // spoils (a highlight over a wide cell). The rule depends on the cell alone, not on eps.
  void defer_loose_lights(const djet* acc, const djet* tf, const material& m) {
    glm::dvec3 tlo(1), thi(1);
    if (tf && m.texture >= 0) {
      const texture_range& tr = w.texture_ranges[size_t(m.texture)];
      tlo = glm::dvec3(tr.lo), thi = glm::dvec3(tr.hi);
    }
    double least[3];
    for (int c = 0; c < 3; ++c) {
      least[c] = lo(acc[c].v) + (tf ? tlo[c] * lo(tf[c].v) : 0.0);
      for (size_t k = 0; k < n_root_lights; ++k)
        least[c] += lo(root_lights[k].spec[c].v) + tlo[c] * lo(root_lights[k].diffuse[c].v);
    }
    for (size_t k = 0; k < n_root_lights; ++k) {
      for (int c = 0; c < 3; ++c) {
        const double e = interpolation_error(root_lights[k].spec[c], cell_width) +
                         thi[c] * interpolation_error(root_lights[k].diffuse[c], cell_width);
        if (!(e <= loose_light_share * std::max(least[c], 1.0 / 255))) {
          deferred |= 1u << root_lights[k].j;
          break;
        }
      }
    }
  }

  // For each deferred light, the primitives (but `self`, when a shadow ray cannot meet it
  // again) in the shaft from the box of the shadow rays' origins to the light, while they
  // fit in `shadow`. Both ends take a margin of ~100 ulps: a pixel's origin is computed in
  // floats from its own eye ray.
  void list_shadow_candidates(bounds from, int self) {
    if (!finite_box(from)) return;
    from = with_rounding_margin(from);
    for (size_t j = 0; j < w.light_pos.size() && j < size_t(max_deferred_lights); ++j) {
      if (!(deferred >> j & 1)) continue;
      shadow_candidates next = shadow;
      const bounds light = with_rounding_margin(bounds{w.light_pos[j], w.light_pos[j]});
      const shaft s = make_shaft(from, light);
      const bool over = for_each_shape_in_shaft(w, s, from, light, [&](int id) {
        if (id == self || std::find(next.prims, next.prims + next.count, id) != next.prims + next.count) return false;
        if (next.count == shadow_candidates::max_prims) return true;
        next.prims[next.count++] = id;
        return false;
      });
      if (over) continue;  // light j keeps the BVH walk
      next.lights |= 1u << j;
      shadow = next;
    }
  }

  // No primitive other than skip_a / skip_b may meet a segment from box a to box b.
  bool shaft_empty(const bounds& a, const bounds& b, int skip_a, int skip_b) const {
    if (!finite_box(a) || !finite_box(b)) return false;
    shaft s = make_shaft(a, b);
    return !for_each_shape_in_shaft(w, s, a, b, [&](int id) { return id != skip_a && id != skip_b; });
  }
  bool shaft_clear(const bounds& a, const bounds& b, int skip_a, int skip_b) {
    return shaft_empty(a, b, skip_a, skip_b) ? true : reject(cell_reason::blocked);
  }

  // The family o + t d hits primitive `prim` at its first surface with t > 0, for every ray
  // of the cell (else the cell has a gap or changes sheet).
  // span, when given, is the family's unnormalized direction (d = span / |span|).
  bool intersect(int prim, const jv& o, const jv& d, const jv* span, surface_family& s) {
    const shape& sh = w.shapes[size_t(prim)];
    switch (sh.kind) {
      case shape_kind::sphere: return hit_sphere(sh.sphere, o, span ? *span : d, s);
      case shape_kind::triangle: return hit_plane(prim, o, span ? *span : d, s);
      case shape_kind::polygon: return hit_plane(prim, o, span ? *span : d, s);
      case shape_kind::disk: return hit_plane(prim, o, span ? *span : d, s);
      case shape_kind::cone: return hit_cone(sh.cone, o, span ? *span : d, s);
      case shape_kind::box: return hit_box(sh.box, o, span ? *span : d, s);
    }
    return reject(cell_reason::missed);
  }

  // d need not be unit. b^2 - |d|^2 c is written by Lagrange's identity as
  // r^2 |d|^2 - |oc x d|^2, as for cones: the difference of two small squares.
  bool hit_sphere(const sphere_geom& g, const jv& o, const jv& d, surface_family& s) {
    jv oc = o - dv(g.c);
    djet b = dot(oc, d);
    djet a = norm2(d);
    jv cr = {oc.y * d.z - oc.z * d.y, oc.z * d.x - oc.x * d.z, oc.x * d.y - oc.y * d.x};
    djet disc = a * (double(g.r) * double(g.r)) - dot(cr, cr);
    if (!positive(disc)) return reject(cell_reason::missed);
    djet sq = sqrt(disc);
    djet t0 = (-b - sq) / a, t1 = (-b + sq) / a;
    if (positive(t0)) s.t = t0, s.from_outside = true;
    else if (hi(t0.v) <= 0 && positive(t1)) s.t = t1, s.from_outside = false;
    else return reject(cell_reason::discontinuity);
    s.p = o + d * s.t;
    s.ng = (s.p - dv(g.c)) * (1.0 / double(g.r));
    return true;
  }

  // d need not be unit: the point o + d t does not depend on its length, and the cell's
  // own lines, given by the unnormalized front-to-back span, meet a plane parallel to the
  // facepair's at points affine in (a, b, c, d), with no normalization's range to widen.
  bool hit_plane(int prim, const jv& o, const jv& d, surface_family& s) {
    const primitive& pr = w.sc.prims[size_t(w.info[size_t(prim)].source)];
    glm::dvec3 n, anchor;
    if (pr.kind == prim_kind::disk) n = dv(pr.b), anchor = dv(pr.a);
    else n = dv(polygon_normal(w.sc, pr)), anchor = dv(w.sc.vertices[size_t(pr.first)]);
    djet dn = dot(d, n);
    if (!(lo(dn.v) > 0 || hi(dn.v) < 0)) return reject(cell_reason::missed);
    s.t = (glm::dot(n, anchor) - dot(o, n)) / dn;
    if (!positive(s.t)) return reject(cell_reason::missed);
    s.p = o + d * s.t;
    s.ng = constant(n);
    s.box = box_on_plane(s.p, n, glm::dot(n, anchor));
    if (!inside_planar(pr, s.box, n)) return reject(cell_reason::missed);
    return true;
  }

  // Is every point of the box (which lies around the primitive's plane) inside it?
  bool inside_planar(const primitive& pr, const bounds& b, glm::dvec3 n) {
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

  static bool segment_meets_rect(double au, double av, double bu, double bv, double u0, double u1, double v0,
                                 double v1) {
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

  bool hit_cone(const cone_geom& g, const jv& o, const jv& d, surface_family& s) {
    glm::dvec3 axis = dv(g.axis);
    double k = g.k, r0 = g.r0, h = g.h;
    jv q = o - dv(g.base);
    djet qa = dot(q, axis), da = dot(d, axis);
    jv qp = q - constant(axis) * qa, dp = d - constant(axis) * da;
    djet R = qa * k + r0, S = da * k;
    djet A = dot(dp, dp) - sqr(S);
    djet B = 2.0 * (dot(qp, dp) - R * S);
    if (!(lo(A.v) > 0 || hi(A.v) < 0)) return reject(cell_reason::discontinuity);
    // B^2 - 4AC rewritten by Lagrange's identity as 4 (|R dp - S qp|^2 - |qp x dp|^2): the
    // same value, but as the difference of two small squares instead of large correlated
    // products, so its enclosure is tight enough to prove that a line through the middle
    // of a column meets it (B^2 - 4AC's went negative on 5-pixel cells).
    jv rs = dp * R - qp * S;
    jv cr = {qp.y * dp.z - qp.z * dp.y, qp.z * dp.x - qp.x * dp.z, qp.x * dp.y - qp.y * dp.x};
    djet disc = 4.0 * (dot(rs, rs) - dot(cr, cr));
    if (!positive(disc)) return reject(cell_reason::missed);
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
    else return reject(cell_reason::missed);
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
    return true;
  }

  bool hit_box(const box_geom& g, const jv& o, const jv& d, surface_family& s) {
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
    if (k == 3 && n_definite < 3) return reject(cell_reason::discontinuity);
    double max_near_hi = std::max({hi(nearv[0].v), hi(nearv[1].v), hi(nearv[2].v)});
    double min_far_lo = std::min({lo(farv[0].v), lo(farv[1].v), lo(farv[2].v)});
    if (k == 3) {  // else the slabs' ranges: a unique entry face, or the eye inside the box
      if (!(max_near_hi < min_far_lo)) return reject(cell_reason::missed);
      if (!unique_max(nearv, k) || !positive(nearv[k]) || !within_face(k, nearv[k])) k = 3;
    }
    if (k < 3) {
      s.t = nearv[k], s.from_outside = true;
      s.ng = constant(dv(*ax[k]) * (lo(dl[k].v) > 0 ? -1.0 : 1.0));
    } else if (max_near_hi < 0 && unique_min(farv, k) && positive(farv[k]) && within_face(k, farv[k])) {
      s.t = farv[k], s.from_outside = false;
      s.ng = constant(dv(*ax[k]) * (lo(dl[k].v) > 0 ? 1.0 : -1.0));
    } else {
      return reject(cell_reason::discontinuity);
    }
    s.p = o + d * s.t;
    glm::dvec3 nk{mid(s.ng.x.v), mid(s.ng.y.v), mid(s.ng.z.v)};  // the face's outward normal, exact
    s.box = box_on_plane(s.p, nk, glm::dot(nk, dv(g.c)) + double(g.half[k]));
    return true;
  }

  // Interpolated patch normals: the point family must stay inside one fan triangle.
  bool patch_normal(const primitive& pr, const jv& p, jv& ns) {
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
        return true;
      }
      bool outside = hi(u.v) < 0 || hi(vv.v) < 0 || hi(w0.v) < 0;
      if (!outside) return reject(cell_reason::discontinuity);  // straddles a fan edge: a kink
    }
    return reject(cell_reason::discontinuity);
  }

  // Proves that every shadow segment from the box `from` to light point `lp` meets the
  // primitive `blocker`: the shadow volume of a convex solid seen from a point is convex, so
  // its containing the 8 corners of `from` suffices.
  bool blocked_everywhere(int blocker, const bounds& from, glm::vec3 lp) {
    const shape& sh = w.shapes[size_t(blocker)];
    if (sh.kind == shape_kind::triangle || sh.kind == shape_kind::polygon || sh.kind == shape_kind::disk)
      return planar_blocked_everywhere(blocker, from, dv(lp));
    if (sh.kind == shape_kind::cone && !cone_entered_by_side(sh.cone, from, w.prim_bounds[size_t(blocker)], dv(lp)))
      return false;
    for (int c = 0; c < 8; ++c) {
      glm::dvec3 o{(c & 1) ? from.hi.x : from.lo.x, (c & 2) ? from.hi.y : from.lo.y, (c & 4) ? from.hi.z : from.lo.z};
      glm::dvec3 seg = dv(lp) - o;
      if (!segment_blocked(sh, o, seg)) return false;
    }
    return true;
  }

  // A planar blocker, convex or not: seen from the light, the box projects onto the plane
  // as the convex hull of its corners' projections, so that hull's bounding rectangle lying
  // inside the polygon (or disk) proves every segment crosses it.
  bool planar_blocked_everywhere(int blocker, const bounds& from, glm::dvec3 L) {
    const double m = 1e-5;
    const primitive& pr = w.sc.prims[size_t(w.info[size_t(blocker)].source)];
    glm::dvec3 n, anchor;
    if (pr.kind == prim_kind::disk) n = dv(pr.b), anchor = dv(pr.a);
    else n = dv(polygon_normal(w.sc, pr)), anchor = dv(w.sc.vertices[size_t(pr.first)]);
    double dl = glm::dot(n, L - anchor);
    bounds cross;
    for (int c = 0; c < 8; ++c) {
      glm::dvec3 o{(c & 1) ? from.hi.x : from.lo.x, (c & 2) ? from.hi.y : from.lo.y, (c & 4) ? from.hi.z : from.lo.z};
      double d0 = glm::dot(n, o - anchor);
      if (!(d0 * dl < 0)) return false;  // every corner strictly on the far side from the light
      double t = d0 / (d0 - dl);
      if (!(t > m && t < 1 - m)) return false;
      glm::dvec3 p = o + t * (L - o);
      for (int i = 0; i < 3; ++i) {
        cross.lo[i] = std::min(cross.lo[i], std::nextafter(float(p[i]), -INFINITY));
        cross.hi[i] = std::max(cross.hi[i], std::nextafter(float(p[i]), INFINITY));
      }
    }
    return inside_planar(pr, cross, n);
  }

  // An open cone blocks a segment that meets its solid frustum C when the segment can only
  // enter C through the side. From a light beside C (axial coordinate inside (0, h)) that
  // always holds: entering through a cap plane would take a second crossing of that plane.
  // From a light beyond a cap, a segment entering through that cap leaves C by the side
  // unless it also passes the other cap, which no line from the light does when the cap's
  // shadow misses the other cap; the box must then lie outside C.
  static bool cone_entered_by_side(const cone_geom& g, const bounds& from, const bounds& cone_box, glm::dvec3 L) {
    const double m = 1e-5, h = double(g.h);
    glm::dvec3 rel = L - dv(g.base), axis = dv(g.axis);
    double zl = glm::dot(rel, axis);
    if (zl > m * h && zl < (1 - m) * h) return true;
    bool separated = false;
    for (int i = 0; i < 3; ++i) separated |= from.hi[i] < cone_box.lo[i] || from.lo[i] > cone_box.hi[i];
    if (!separated) return false;
    double rho = glm::length(rel - axis * zl);
    double r0 = double(g.r0), r1 = double(g.r0) + double(g.k) * h;
    double near_r, far_r, s;
    if (zl > h * (1 + m)) near_r = r1, far_r = r0, s = zl / (zl - h);       // the top cap faces the light
    else if (zl < -m * h) near_r = r0, far_r = r1, s = (h - zl) / (-zl);  // the bottom cap does
    else return false;
    // The near cap's shadow on the far cap's plane: a disk of radius s near_r whose centre is
    // rho (s - 1) off the axis.
    return rho * (s - 1) > (s * near_r + far_r) * (1 + 1e-4) + m * h;
  }

  static bool segment_blocked(const shape& sh, glm::dvec3 o, glm::dvec3 seg) {
    const double m = 1e-5;  // margin: the float tracer must agree on the corners too
    switch (sh.kind) {
      case shape_kind::sphere: {
        glm::dvec3 c = dv(sh.sphere.c);
        double r = std::fabs(double(sh.sphere.r)) * (1 - m);
        double t = std::clamp(glm::dot(c - o, seg) / glm::dot(seg, seg), 0.0, 1.0);
        glm::dvec3 q = o + t * seg - c;
        // The segment must cross the surface: one end outside (the light), the closest
        // point well inside.
        return glm::dot(q, q) < r * r && glm::dot(o - c, o - c) > r * r * (1 + 4 * m) &&
               glm::dot(o + seg - c, o + seg - c) > r * r * (1 + 4 * m);
      }
      case shape_kind::box: {
        double t0 = 0, t1 = 1;
        const glm::vec3* ax[3] = {&sh.box.ax0, &sh.box.ax1, &sh.box.ax2};
        for (int i = 0; i < 3; ++i) {
          double ol = glm::dot(o - dv(sh.box.c), dv(*ax[i])), dl = glm::dot(seg, dv(*ax[i]));
          double hh = double(sh.box.half[i]) * (1 - m);
          if (dl == 0) {
            if (std::fabs(ol) >= hh) return false;
            continue;
          }
          double a = (-hh - ol) / dl, b = (hh - ol) / dl;
          if (a > b) std::swap(a, b);
          t0 = std::max(t0, a), t1 = std::min(t1, b);
        }
        return t0 < t1 && t0 > 0 && t1 < 1;  // enters and leaves strictly inside the segment
      }
      case shape_kind::triangle: {
        glm::dvec3 v0 = dv(sh.tri.v0), e1 = dv(sh.tri.e1), e2 = dv(sh.tri.e2);
        glm::dvec3 p = glm::cross(seg, e2);
        double det = glm::dot(e1, p);
        if (det == 0) return false;
        glm::dvec3 s = o - v0;
        double u = glm::dot(s, p) / det;
        glm::dvec3 q = glm::cross(s, e1);
        double v = glm::dot(seg, q) / det, t = glm::dot(e2, q) / det;
        return u > m && v > m && u + v < 1 - m && t > m && t < 1 - m;
      }
      case shape_kind::disk: {
        glm::dvec3 n = dv(sh.disk.n), c = dv(sh.disk.c);
        double dn = glm::dot(n, seg);
        if (dn == 0) return false;
        double t = glm::dot(c - o, n) / dn;
        glm::dvec3 q = o + t * seg - c;
        return t > m && t < 1 - m && glm::dot(q, q) < double(sh.disk.r2) * (1 - 2 * m);
      }
      case shape_kind::cone: {
        // Does the segment meet the (convex) solid frustum, shrunken by the margin? Whether
        // that means meeting the open side is cone_entered_by_side's business.
        const cone_geom& g = sh.cone;
        glm::dvec3 axis = dv(g.axis), base = dv(g.base);
        double h = double(g.h), k = double(g.k), r0 = double(g.r0);
        double zlo = m * h, zhi = (1 - m) * h;
        glm::dvec3 q = o - base;
        double qa = glm::dot(q, axis), da = glm::dot(seg, axis);
        double t0 = 0, t1 = 1;
        if (da == 0) {
          if (qa <= zlo || qa >= zhi) return false;
        } else {
          double a = (zlo - qa) / da, b = (zhi - qa) / da;
          if (a > b) std::swap(a, b);
          t0 = std::max(t0, a), t1 = std::min(t1, b);
        }
        if (!(t0 < t1)) return false;
        // g(t) = |radial|^2 - (shrunken radius)^2 = A t^2 + B t + C; negative inside.
        glm::dvec3 qp = q - axis * qa, dp = seg - axis * da;
        double R0 = (r0 + k * qa) * (1 - m), S = k * da * (1 - m);
        double A = glm::dot(dp, dp) - S * S, B = 2 * (glm::dot(qp, dp) - R0 * S), C = glm::dot(qp, qp) - R0 * R0;
        auto gf = [&](double t) { return (A * t + B) * t + C; };
        double best = std::min(gf(t0), gf(t1));
        if (A > 0) {
          double tv = -B / (2 * A);
          if (tv > t0 && tv < t1) best = std::min(best, gf(tv));
        }
        return best < 0;
      }
      default: return false;  // concave polygons: no convexity argument
    }
  }

  // Radiance of the family of rays o + t d (t > 0) whose ray-tree node is `node`; `from` is
  // the primitive they leave (-1 for the lines of the cell) and whether it may be ignored
  // in their shaft. Root extra: the texture factor of a textured root.
  bool radiance(int node, const jv& o, const jv& d, int depth, int from, bool from_ignorable, djet L[3],
                djet* tex_factor) {
    const ray_tree_node& n = tree.nodes[size_t(node)];
    if (n.prim < 0) {  // a miss: nothing may lie anywhere along any ray of the family
      bounds a = box_of(o);
      jv end = o + d * djet(far);
      if (!shaft_clear(a, box_of(end), from_ignorable ? from : -1, -1)) return false;
      for (int c = 0; c < 3; ++c) L[c] = djet(double(w.background[c]));
      return true;
    }
    const int prim = w.shape_of[size_t(n.prim)];
    surface_family sf;
    if (!intersect(prim, o, d, from < 0 ? root_span : nullptr, sf)) return false;
    if (sf.box.empty()) sf.box = box_of(sf.p);
    if (from < 0) root_hits = sf.box;
    if (from >= 0) {  // a secondary segment: nothing but its ends in its shaft
      if (!shaft_clear(box_of(o), sf.box, prim, from_ignorable ? from : -1)) return false;
    }
    const shape_kind kind = w.shapes[size_t(prim)].kind;
    const primitive& pr = w.sc.prims[size_t(n.prim)];
    if (kind == shape_kind::cone && (pr.r0 < 0 || pr.r1 < 0)) sf.ng = -sf.ng;
    jv ns = sf.ng;
    if (pr.kind == prim_kind::patch && !patch_normal(pr, sf.p, ns)) return false;
    // The sign of d . n is that of span . n, which is exact for a plane's flat facepair
    // (a constant) where the normalized d spreads.
    djet dng = dot(sf.ng, from < 0 && root_span ? *root_span : d);
    bool entering = n.entering != 0;
    if (entering ? !negative(dng) : !positive(dng)) return reject(cell_reason::discontinuity);
    jv nf = entering ? ns : -ns;

    const material& m = w.sc.materials[size_t(w.info[size_t(prim)].material)];
    const bool split = tex_factor != nullptr;
    if (m.texture >= 0 && !split) return reject(cell_reason::nonlinear);  // textures seen in reflections
    // A textured root's texture is looked up per pixel at the pixel's own hit point, so its
    // uv needs no bound (any primitive, any texture).
    glm::dvec3 kdc = dv(m.kd * m.color);
    djet acc[3], tf[3];
    for (int c = 0; c < 3; ++c) {
      acc[c] = djet(split ? 0.0 : double(w.ambient[c]) * kdc[c]);
      tf[c] = djet(double(w.ambient[c]) * kdc[c]);
    }
    const double delta = w.delta;
    jv above = sf.p + nf * delta;
    bounds above_box = box_of(above);
    {  // the hit points' box moved off the surface: tighter than above's own range on planes
      const bounds off = box_of(nf * delta);
      for (int i = 0; i < 3; ++i) {
        above_box.lo[i] = std::max(above_box.lo[i], std::nextafter(sf.box.lo[i] + off.lo[i], -INFINITY));
        above_box.hi[i] = std::min(above_box.hi[i], std::nextafter(sf.box.hi[i] + off.hi[i], INFINITY));
      }
    }
    jv view = -d;
    for (size_t j = 0; j < w.light_pos.size(); ++j) {
      // The eye ray's own lights may be left to per-pixel shadow rays: those the corners
      // disagree on are, and so is any whose visibility or shading this cell cannot prove.
      const bool deferrable = from < 0 && allow_defer && j < size_t(max_deferred_lights);
      if (from < 0 && (deferred >> j & 1)) continue;
      auto defer_or = [&](cell_reason r) {
        if (!deferrable) return reject(r);
        deferred |= 1u << j;
        return true;
      };
      std::int32_t status = tree.lights[n.lights + j];
      jv to_light = constant(dv(w.light_pos[j])) - sf.p;
      jv lj = normalize(to_light);
      djet ndl = dot(nf, lj);
      if (status == light_behind) {
        if (!(hi(ndl.v) <= 0) && !defer_or(cell_reason::discontinuity)) return false;
        continue;
      }
      if (status >= 0) {  // blocked at every corner: prove it for every ray
        if (!blocked_everywhere(w.shape_of[size_t(status)], above_box, w.light_pos[j]) &&
            !defer_or(cell_reason::blocked))
          return false;
        continue;
      }
      if (!positive(ndl)) {
        if (!defer_or(cell_reason::discontinuity)) return false;
        continue;
      }
      bounds lbox{w.light_pos[j], w.light_pos[j]};
      const int skip = cannot_reenter(kind, sf.from_outside, pr.kind == prim_kind::patch) ? prim : -1;
      if (deferrable ? !shaft_empty(above_box, lbox, skip, -1) : !shaft_clear(above_box, lbox, skip, -1)) {
        if (!defer_or(cell_reason::blocked)) return false;
        continue;
      }
      djet spec(0.0);
      if (m.shine > 0 && m.ks > 0) {
        djet nh = dot(nf, normalize(lj + view));
        if (!positive(nh)) {
          if (!defer_or(cell_reason::nonlinear)) return false;
          continue;
        }
        spec = pow(nh, double(m.shine));
      }
      glm::dvec3 I = dv(w.light_power[j]);
      light_terms lt;
      lt.j = j;
      for (int c = 0; c < 3; ++c) {
        lt.diffuse[c] = ndl * (I[c] * kdc[c]);
        lt.spec[c] = spec * (I[c] * double(m.ks));
        // 16 ulps of N.H (2^-20): the shiny stress scene's reference stepped by one ulp's
        // worth (shine 50000: 2e-4 in 0.13) between neighbouring rays.
        lt.noise[c] = m.shine > 0 && m.ks > 0 ? path_weight * I[c] * double(m.ks) * double(m.shine) * hi(spec.v) * 0x1p-20 : 0;
      }
      // The root's deferrable lights wait until all are bounded (defer_loose_lights).
      if (deferrable) root_lights[n_root_lights++] = lt;
      else add_light(lt, acc, split ? tf : nullptr);
    }
    if (from < 0 && n_root_lights) {
      defer_loose_lights(acc, split ? tf : nullptr, m);
      for (size_t k = 0; k < n_root_lights; ++k)
        if (!(deferred >> root_lights[k].j & 1)) add_light(root_lights[k], acc, split ? tf : nullptr);
    }
    const bool leave_ok = cannot_reenter(kind, sf.from_outside, pr.kind == prim_kind::patch);
    if (from < 0 && deferred) list_shadow_candidates(above_box, leave_ok ? prim : -1);
    // The eye ray's reflected and transmitted subtrees may be left to per-pixel rays (where
    // allowed): those the corners disagree on are, and so is any this cell cannot bound.
    const bool root = from < 0;
    // weight: the child's radiance enters this one times it (ks or t), and so does the
    // noise bounded below it.
    auto child_or_defer = [&](std::uint32_t bit, double weight, auto&& bound_child) {
      if (root && (deferred_rays & bit)) return true;
      const double above_weight = path_weight;
      path_weight *= weight;
      const bool bounded = bound_child();
      path_weight = above_weight;
      if (bounded) return true;
      if (!(root && allow_defer)) return false;
      fail = cell_reason::valid, deferred_rays |= bit;
      return true;
    };
    // Reflected and refracted directions of unit vectors are unit (whitted.md 4); normalizing
    // intervals would only lose that.
    if (n.reflect >= 0) {
      const bool ok = child_or_defer(deferred_reflect, double(m.ks), [&] {
        jv rd = d - nf * (2.0 * dot(d, nf));
        djet Lr[3];
        if (!radiance(n.reflect, above, rd, depth + 1, prim, leave_ok, Lr, nullptr)) return false;
        for (int c = 0; c < 3; ++c) acc[c] = acc[c] + Lr[c] * double(m.ks);
        return true;
      });
      if (!ok) return false;
    }
    if (n.refract >= 0) {
      const bool ok = child_or_defer(deferred_refract, double(m.t), [&] {
        double eta = entering ? 1.0 / double(m.ior) : double(m.ior);
        djet ci = dot(view, nf);
        djet k = 1.0 - eta * eta * (1.0 - sqr(ci));
        djet Lt[3];
        if (n.tir) {
          if (!(hi(k.v) < 0)) return reject(cell_reason::discontinuity);
          jv rd = d - nf * (2.0 * dot(d, nf));
          if (!radiance(n.refract, above, rd, depth + 1, prim, leave_ok, Lt, nullptr)) return false;
        } else {
          if (!positive(k)) return reject(cell_reason::discontinuity);
          jv td = d * eta + nf * (ci * eta - sqrt(k));
          jv below = sf.p - nf * delta;
          // A refracted segment passes through a plane; inside a sphere or box it meets the
          // solid again only at its target, the exit point.
          const ray_tree_node& child = tree.nodes[size_t(n.refract)];
          bool planar = kind == shape_kind::triangle || kind == shape_kind::polygon || kind == shape_kind::disk;
          bool exits_self = child.prim >= 0 && w.shape_of[size_t(child.prim)] == prim &&
                            (kind == shape_kind::sphere || kind == shape_kind::box);
          bool through_ok = planar || exits_self;
          if (!radiance(n.refract, below, td, depth + 1, prim, through_ok, Lt, nullptr)) return false;
        }
        for (int c = 0; c < 3; ++c) acc[c] = acc[c] + Lt[c] * double(m.t);
        return true;
      });
      if (!ok) return false;
    }
    for (int c = 0; c < 3; ++c) {
      L[c] = acc[c];
      if (split) tex_factor[c] = tf[c];
    }
    return true;
  }
};

}  // namespace

cell_bound bound_cell(const cell_query& q) {
  const world& w = *q.w;
  const facepair& fp = *q.fp;
  evaluator ev{w, *q.tree};  // the rest by name: a positional list silently shifts when members move
  ev.deferred = q.deferred, ev.deferred_rays = q.deferred_rays, ev.allow_defer = q.allow_defer;
  for (int i = 0; i < 4; ++i) ev.cell_width[i] = double(q.hi[i]) - double(q.lo[i]);
  // A pixel's line is found in the cell by float coordinates (line_coords: o + t d rounded
  // at the magnitudes of the eye and the coordinates), a few ulps from its exact line's, so
  // the jets range over the cell widened by 16 ulps of those magnitudes, the scene's
  // standing for the eye's (as in the hit tests' rounding margins). Loose enclosures once
  // covered this by accident; tight ones need it said (a box's edge within rounding).
  const double magnitude = 2 * std::max(glm::length(dv(w.box.lo)), glm::length(dv(w.box.hi)));
  double lo4[4], hi4[4];
  for (int i = 0; i < 4; ++i) {
    const double pad = 0x1p-20 * (magnitude + std::max(std::fabs(double(q.lo[i])), std::fabs(double(q.hi[i]))));
    lo4[i] = double(q.lo[i]) - pad, hi4[i] = double(q.hi[i]) + pad;
  }
  glm::dvec3 ext = dv(w.box.extent());
  double scene = glm::length(ext);
  // Lines start on the facepair's front plane, within a few object sizes of the scene.
  double reach = 0;
  for (int i = 0; i < 4; ++i) reach = std::max({reach, std::fabs(double(fp.lo[i])), std::fabs(double(fp.hi[i]))});
  ev.far = 4 * (scene + reach + glm::length(dv(w.box.centre())) + std::fabs(double(fp.front)) + 1);

  jv o, p1;
  djet a = djet_variable(0, lo4[0], hi4[0]), b = djet_variable(1, lo4[1], hi4[1]);
  djet c = djet_variable(2, lo4[2], hi4[2]), d = djet_variable(3, lo4[3], hi4[3]);
  o[fp.axis] = djet(double(fp.front)), o[fp.u] = a, o[fp.v] = b;
  p1[fp.axis] = djet(double(fp.back)), p1[fp.u] = c, p1[fp.v] = d;
  const jv span = p1 - o;
  ev.root_span = &span;
  jv dir = normalize(span);

  djet L[3], tf[3];
  cell_bound out;
  if (!ev.radiance(0, o, dir, 1, -1, false, L, q.textured ? tf : nullptr)) {
    out.reason = ev.fail == cell_reason::valid ? cell_reason::nonlinear : ev.fail;
    return out;
  }
  out.hit_box = ev.root_hits;
  out.deferred = ev.deferred;
  out.deferred_rays = ev.deferred_rays;
  out.shadow = ev.shadow;
  double h[4];
  for (int i = 0; i < 4; ++i) h[i] = double(q.hi[i]) - double(q.lo[i]);
  double axis[4] = {0, 0, 0, 0};
  for (int ch = 0; ch < 3; ++ch) {
    out.err[ch] = float((interpolation_error(L[ch], h, axis) + ev.noise[ch]) * (1 + 1e-6));
    if (q.textured) out.err_tex[ch] = float(interpolation_error(tf[ch], h, axis));
  }
  // The pair whose second-order terms dominate is the one worth halving.
  const double ac = axis[0] + axis[2], bd = axis[1] + axis[3];
  out.split = ac > 3 * bd ? split_ac : (bd > 3 * ac ? split_bd : split_all);
  auto finite3 = [](glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  if (!finite3(out.err) || !finite3(out.err_tex)) out.reason = cell_reason::nonlinear;
  return out;
}

}  // namespace epsray
