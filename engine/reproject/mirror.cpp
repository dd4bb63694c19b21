#include "reproject/mirror.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "interp/cell_screen.h"
#include "predicate/shaft_shape.h"
#include "shade/surface.h"
#include "shade/texture.h"

namespace epsray {

namespace {

glm::vec3 mirrored(glm::vec3 v, glm::vec3 n) { return v - 2 * glm::dot(v, n) * n; }

// The interpolant of cell n at line x4 and, for a textured cell, its texture at the ray's
// own hit, and the lights it leaves to per-pixel shadow rays; ks times all. The pixel's
// radiance so far is at least `known`, with proven error `err`.
void cell_value(const world& w, int prim, const lt_node& n, const interpolant& ip, const float x4[4], const ray& r,
                float t_hit, float ks, glm::vec3 known, glm::vec3 err, float eps, trace_state& st, glm::vec3& L,
                glm::vec3& E) {
  float t[4];
  cell_fractions(n, x4, t);
  L = quadrilinear(ip.rad, t), E = ip.err;
  if (ip.textured() || ip.deferred) {
    const material& m = w.sc.materials[size_t(w.info[size_t(prim)].material)];
    const surface sf = surface_at(w, prim, r, t_hit);
    glm::vec3 T{1};
    if (ip.textured()) {
      T = sample_texture(w.sc.textures[size_t(m.texture)], surface_uv(w, prim, sf.p));
      L += T * quadrilinear(ip.tx->tex, t), E += T * ip.tx->err_tex;
    }
    // Lights only: a depth-2 cell's deferred rays would be traced at the eye's depth. They
    // skip shadow rays under the pixel's allowance, as a traced reflection's hit does
    // (mirror_term): in units of this term, the pixel's radiance and error are divided by
    // ks, so a light skipped at half its term costs ks times that half of the pixel's room.
    // The cell's own error is reserved first; the pixel's test decides with all of it.
    if (ip.deferred) {
      error_allowance allow{known / ks, err / ks + E, eps};
      L += deferred_terms(w, r, hit{t_hit, prim}, sf, T, ip.deferred, 0, &ip.shadow, st, &allow);
      E += allow.spent;
    }
  }
  L *= ks, E *= ks;
}

}  // namespace

mirror_view choose_mirror(const world& w, const camera& cam, float min_share) {
  mirror_view out;
  float best = min_share * float(cam.width) * float(cam.height);
  for (size_t i = 0; i < w.scene_prims; ++i) {
    const shape& s = w.shapes[i];
    if (s.kind != shape_kind::polygon && s.kind != shape_kind::disk) continue;
    const material& m = w.sc.materials[size_t(w.info[i].material)];
    if (!(m.ks > 0)) continue;
    const float px = box_pixels(cam, w.prim_bounds[i]);
    if (!(px > best)) continue;
    best = px;
    out.reflector = int(i);
    out.ks = m.ks;
    if (s.kind == shape_kind::polygon) out.n = s.poly.n, out.d = s.poly.d;
    else out.n = s.disk.n, out.d = glm::dot(s.disk.n, s.disk.c);
    if (std::isinf(px)) break;  // a box reaching behind the eye: as large as any
  }
  if (out.reflector < 0) return out;
  // Seen from its front: the eye's side. An eye on the plane sees no reflection.
  float h = glm::dot(out.n, cam.origin) - out.d;
  if (h < 0) out.n = -out.n, out.d = -out.d, h = -h;
  if (!(h > 0)) {
    out.reflector = -1;
    return out;
  }
  out.cam = cam;
  out.cam.origin = cam.origin - 2 * h * out.n;
  out.cam.w = mirrored(cam.w, out.n), out.cam.r = mirrored(cam.r, out.n), out.cam.u = mirrored(cam.u, out.n);
  // A pixel's reflected ray leaves P + delta n; run back, its line passes E' + delta n, up
  // to the rounding of P and of the reflected direction over the eye's distance.
  const glm::vec3 e = out.cam.origin, lifted = e + w.delta * out.n;
  const float pad = 1e-4f * (1 + glm::length(e) + 2 * h) + 1e-5f * w.delta;
  out.eye_box.lo = glm::min(e, lifted) - pad, out.eye_box.hi = glm::max(e, lifted) + pad;
  return out;
}

float mirror_eps(float eps, float ks) { return std::min(0.5f, 0.5f * eps / std::max(ks, 1e-6f)); }

bool behind_mirror(const mirror_view& m, const bounds& b) {
  float top = 0;  // the box's greatest n.x
  for (int i = 0; i < 3; ++i) top += std::max(m.n[i] * b.lo[i], m.n[i] * b.hi[i]);
  return top <= m.d;
}

cell_trust trust_from_mirror(const world& w, const cell_ref& c, const mirror_view& m) {
  cell_trust out;
  const interpolant& ip = *c.ip;
  if (ip.reason != cell_reason::valid || ip.hit_box.empty() || ip.deferred_rays) return out;
  const facepair& fp = c.lt->fp;
  const bounds& eb = m.eye_box;
  const bool ahead = fp.back > fp.front ? eb.hi[fp.axis] < ip.hit_box.lo[fp.axis] : eb.lo[fp.axis] > ip.hit_box.hi[fp.axis];
  if (!ahead) return out;
  const int self = scene_prim_of(w, c.prim);
  if (self != c.prim) {  // a box face's cell: only where every line meets the face itself
    const int k = flat_axis(w.prim_bounds[size_t(c.prim)]);
    const bounds& f = w.prim_bounds[size_t(c.prim)];
    const bounds hb = with_rounding_margin(ip.hit_box, m.cam.origin);
    for (int i = 0; i < 3; ++i)
      if (i != k && !(hb.lo[i] > f.lo[i] && hb.hi[i] < f.hi[i])) return out;
  }
  const bounds to = with_rounding_margin(ip.hit_box, m.cam.origin);
  list_candidates(
      w, eb, to,
      [&](int id) { return id == self || id == m.reflector || behind_mirror(m, w.prim_bounds[size_t(id)]); }, out);
  return out;
}

bool mirror_term(mirror_use& mu, const world& w, int x, int y, const surface& sf, const ray& r, glm::vec3 known,
                 glm::vec3 err, float eps, trace_state& st, glm::vec3& L, glm::vec3& E, bool* noted) {
  const mirror_frame& m = *mu.m;
  const float ks = m.view.ks;
  *noted = false;
  // The reflected ray exactly as the reference casts it (whitted.cpp, reflected_term).
  const bool entering = glm::dot(sf.ng, r.d) < 0;
  const glm::vec3 nf = entering ? sf.ns : -sf.ns;
  const ray rr = make_ray(sf.p + w.delta * nf, r.d - 2 * glm::dot(r.d, nf) * nf);
  float x4[4];
  // A reprojected mirror cell that holds the ray's line, hit first from its origin, with
  // no candidate in front.
  const std::int32_t own = m.owner ? m.owner[size_t(y) * size_t(m.view.cam.width) + size_t(x)] : -1;
  if (own >= 0) {
    const cell_ref& c = (*m.cells)[size_t(own)];
    const cell_trust& tr = (*m.trust)[size_t(own)];
    const facepair& fp = c.lt->fp;
    const int self = scene_prim_of(w, c.prim);
    float t2 = 0;
    bool ok = facepair_for(fp.flat, rr.d) == fp.index;
    if (ok) line_coords(fp, rr.o, rr.d, x4);
    ok = ok && holds(*c.node, x4) && same_first_hit(w.shapes[size_t(self)], fp, rr.o) &&
         hit_shape(w.shapes[size_t(self)], w.polys, rr, std::numeric_limits<float>::infinity(), t2) &&
         (self == c.prim || face_prim_of(w, self, rr) == c.prim);
    for (int i = 0; ok && i < tr.count; ++i) {
      float tc;
      if (hit_shape(w.shapes[size_t(tr.candidates[i])], w.polys, rr, t2 * (1 + 1e-5f), tc)) ok = false;
    }
    if (ok) {
      cell_value(w, c.prim, *c.node, *c.ip, x4, rr, t2, ks, known, err, eps, st, L, E);
      if (note_cell(mu.cells, c)) *noted = true;
      ++mu.filled;
      return false;
    }
  }
  // Its first hit, then that object's mirror linetree.
  ++st.counts.reflect;
  hit h;
  if (!closest_hit(w, rr, std::numeric_limits<float>::infinity(), h)) {
    L = ks * w.background, E = glm::vec3(0);
    ++mu.traced;
    return true;
  }
  if (h.prim != m.view.reflector && !(m.f.small && m.f.small[h.prim])) {
    const int face = face_prim_of(w, h.prim, rr);
    const int lp = face >= 0 ? face : h.prim;
    linetree& lt = m.f.trees->tree_for(lp, rr.d);
    line_coords(lt.fp, rr.o, rr.d, x4);
    if (same_first_hit(w.shapes[size_t(h.prim)], lt.fp, rr.o) && holds(lt.root, x4)) {
      const interpolant* ip = nullptr;
      lt_node* node = find_cell(m.f, lt, lp, x4, st, mu.scratch, ip);
      if (ip->reason == cell_reason::valid && !ip->deferred_rays) {
        cell_value(w, lp, *node, *ip, x4, rr, h.t, ks, known, err, eps, st, L, E);
        if (note_cell(mu.cells, cell_ref{&lt, node, ip, lp})) *noted = true;
        ++mu.looked_up;
        return false;
      }
    }
  }
  // What reflected_term computes, from the hit already found.
  glm::vec3 left = error_room(known, err, eps);
  const glm::vec3 offered = left;
  st.error_left = &left, st.path_weight = ks;
  L = ks * shade_hit(w, rr, h, 2, st);
  st.error_left = nullptr, st.path_weight = 1;
  E = offered - left;
  ++mu.traced;
  return true;
}

}  // namespace epsray
