#include "predicate/error_predicate.h"

#include <algorithm>
#include <cmath>

#include "geom/shape_build.h"
#include "predicate/hit_family.h"
#include "predicate/jet_vec.h"
#include "predicate/shaft_shape.h"
#include "shade/surface.h"
#include "shade/whitted.h"

namespace epsray {

namespace {

// The jets and their 3-vectors (predicate/jet_vec.h); where the lines meet the primitives
// (predicate/hit_family.cpp). This file bounds the radiance they carry.
using namespace family;

// A deferrable light whose own bound exceeds this share of the cell's least radiance is
// deferred (evaluator::defer_loose_lights).
constexpr double loose_light_share = 0.05;


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
      bool met = false;
      const bool over = for_each_shape_in_shaft(w, s, from, light, [&](int id) {
        if (id == self) return false;
        met = true;
        if (std::find(next.prims, next.prims + next.count, id) != next.prims + next.count) return false;
        if (next.count == shadow_candidates::max_prims) return true;
        next.prims[next.count++] = id;
        return false;
      });
      if (over) continue;  // light j keeps the BVH walk
      if (!met) {  // nothing to test: every pixel's shadow ray reaches the light
        shadow.lit |= 1u << j;
        continue;
      }
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
    return inside_planar(w, pr, cross, n);
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
        return t > m && t < 1 - m && glm::dot(q, q) < double(sh.disk.r) * double(sh.disk.r) * (1 - 2 * m);
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
    if (const cell_reason r = hit_family(w, prim, o, d, from < 0 ? root_span : nullptr, sf); r != cell_reason::valid)
      return reject(r);
    if (sf.box.empty()) sf.box = box_of(sf.p);
    if (from < 0) root_hits = sf.box;
    if (from >= 0) {  // a secondary segment: nothing but its ends in its shaft
      if (!shaft_clear(box_of(o), sf.box, prim, from_ignorable ? from : -1)) return false;
    }
    const shape_kind kind = w.shapes[size_t(prim)].kind;
    const primitive& pr = w.sc.prims[size_t(n.prim)];
    if (kind == shape_kind::cone && (pr.r0 < 0 || pr.r1 < 0)) sf.ng = -sf.ng;
    jv ns = sf.ng;
    if (pr.kind == prim_kind::patch) {
      if (const cell_reason r = patch_normal(w, pr, sf.p, ns); r != cell_reason::valid) return reject(r);
    }
    // The sign of d . n is that of span . n, which is exact for a plane's flat facepair
    // (a constant) where the normalized d spreads.
    djet dng = dot(sf.ng, from < 0 && root_span ? *root_span : d);
    bool entering = n.entering != 0;
    if (entering ? !negative(dng) : !positive(dng)) return reject(cell_reason::discontinuity);
    // What rays leaving the surface may skip in their shafts: a box face's rectangle
    // (world::face_prims) met from outside is left away from the box behind its plane, so
    // they may skip the box itself. (Lines from the inside never hold a pixel: its eye ray
    // enters the box by the face.)
    const int self = entering ? scene_prim_of(w, prim) : prim;
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
      const int skip = cannot_reenter(kind, sf.from_outside, pr.kind == prim_kind::patch) ? self : -1;
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
    if (from < 0 && deferred) list_shadow_candidates(above_box, leave_ok ? self : -1);
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
        if (!radiance(n.reflect, above, rd, depth + 1, self, leave_ok, Lr, nullptr)) return false;
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
          if (!radiance(n.refract, above, rd, depth + 1, self, leave_ok, Lt, nullptr)) return false;
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
          if (!radiance(n.refract, below, td, depth + 1, self, through_ok, Lt, nullptr)) return false;
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
  // A pixel's line is found in the cell by float coordinates (line_coords: computed in
  // double, rounded once), half an ulp from its exact line's, so the jets range over the
  // cell widened by 16 ulps of the scene's and the coordinates' magnitudes. Loose enclosures
  // once covered this by accident; tight ones need it said (a box's edge within rounding).
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
