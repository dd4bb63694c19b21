#include "interp/interp_shade.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "interp/cell_screen.h"
#include "predicate/error_predicate.h"
#include "predicate/reflect_shaft.h"
#include "reproject/mirror.h"
#include "sched/cycle_clock.h"  // cycle_now is inline: no link to the scheduler library
#include "shade/surface.h"
#include "shade/texture.h"

namespace epsray {

namespace {

constexpr float floor_radiance = 1.0f / 255;  // whitted.md 6

// The axes a pattern over the 16 corners depends on (cls[k]: the class of corner k).
// Classes that change with (a, c) only mean an edge running across the cell along (b, d),
// which halving (a, c) alone isolates at half the cost of halving all four axes.
std::uint8_t axes_of_pattern(const std::uint8_t cls[16]) {
  auto depends_only_on = [&](unsigned axes) {
    for (unsigned k = 0; k < 16; ++k)
      if (cls[k] != cls[k & axes]) return false;
    return true;
  };
  if (depends_only_on(split_ac)) return split_ac;
  if (depends_only_on(split_bd)) return split_bd;
  return split_all;
}

// Failures that say nothing of direction (an occluder in a shaft): keep cells near square
// by halving the pair of axes that spans more.
std::uint8_t axes_by_extent(const lt_node& n) {
  float ac = std::max(n.hi[0] - n.lo[0], n.hi[2] - n.lo[2]);
  float bd = std::max(n.hi[1] - n.lo[1], n.hi[3] - n.lo[3]);
  return ac > 1.5f * bd ? split_ac : (bd > 1.5f * ac ? split_bd : split_all);
}

// The rays a ray tree stands for: one per node (a miss included) and one per shadow ray
// (a light in front of the surface).
std::uint16_t tree_rays(const ray_tree& t) {
  size_t n = t.nodes.size();
  for (std::int32_t s : t.lights) n += s != light_behind;
  return std::uint16_t(std::min<size_t>(n, 65535));
}

// A refusal for a discontinuity by a build that could not defer: built again with deferral
// when the cost model does not split the cell (descend).
bool may_rebuild(const interpolant& ip) {
  return ip.reason == cell_reason::discontinuity && !ip.could_defer && ip.shared;
}

bool strictly_inside(const lt_node& n, const float x[4]) {
  for (int i = 0; i < 4; ++i)
    if (!(x[i] > n.lo[i] && x[i] < n.hi[i])) return false;
  return true;
}

}  // namespace

// The 16 extremal lines of a cell, traced against the object alone (occlusion in front of
// it is the visibility ray's business), each looked up in the shared sample cache first and
// published there after tracing; then the topology test and the predicate.
std::unique_ptr<interpolant> build_interpolant(const world& w, int prim, const facepair& fp, const lt_node& n,
                                               bool terminal, bool defer, sample_cache& cache, trace_state& st,
                                               interp_scratch& scratch, bool predicate, int depth) {
  auto ip = std::make_unique<interpolant>();
  ip->could_defer = defer;
  const material& m = w.sc.materials[size_t(w.info[size_t(prim)].material)];
  // Its texture terms are allocated only if the cell is kept: most builds fail.
  const bool textured = m.texture >= 0;
  line_key keys[16];
  line_sample samples[16];
  const ray_tree* trees[16];
  bool known[16];
  ray lines[16];
  float ts[16];
  std::uint8_t cls[16];
  bool any_miss = false;
  // All 16 hits first: cells near a silhouette are common and need no shading to reject;
  // which corners miss tells which axes to halve.
  for (int k = 0; k < 16; ++k) {
    line_key& key = keys[k];
    key.prim = prim, key.facepair = fp.index;
    for (int i = 0; i < 4; ++i) key.x[i] = (k >> i & 1) ? n.hi[i] : n.lo[i];
    if (const line_sample* s = cache.lines.find(key)) {
      samples[k] = *s, known[k] = true;
      cls[k] = s->hit ? 0 : 1;
      any_miss |= !s->hit;
      continue;
    }
    known[k] = false;
    glm::vec3 p0 = front_point(fp, key.x[0], key.x[1]), p1 = back_point(fp, key.x[2], key.x[3]);
    lines[k] = make_ray(p0, glm::normalize(p1 - p0));
    ++st.counts.eye;
    const bool hit = hit_shape(w.shapes[size_t(prim)], w.polys, lines[k], std::numeric_limits<float>::infinity(), ts[k]);
    cls[k] = hit ? 0 : 1;
    if (!hit) {
      any_miss = true;
      cache.lines.insert(key, line_sample{});  // a miss, remembered for the siblings
    }
  }
  if (any_miss) {
    ip->reason = cell_reason::missed, ip->split = axes_of_pattern(cls);
    return ip;
  }
  // A cell that cannot be split any further needs no corner pattern: the first two corners
  // whose topologies differ beyond what it may defer reject it, before the rest are shaded
  // (cached corners first).
  const ray_tree* first = nullptr;
  const size_t nl = w.light_pos.size();
  std::uint32_t deferred = 0, deferred_rays = 0;
  auto differs = [&](const ray_tree* t) {
    if (!first) first = t;
    return t != first && !same_topology_deferring(*first, *t, nl, defer, &deferred, &deferred_rays);
  };
  if (terminal) {
    for (int k = 0; k < 16; ++k) {
      if (known[k] && differs(samples[k].tree)) {
        ip->reason = cell_reason::discontinuity, ip->split = axes_by_extent(n);
        return ip;
      }
    }
  }
  ray_tree* saved_tree = st.tree;
  st.root_depth = depth;
  for (int k = 0; k < 16; ++k) {
    if (known[k]) {
      trees[k] = samples[k].tree;
      continue;
    }
    ray_tree& tree = scratch.trees[size_t(k)];
    tree.clear();
    st.tree = &tree;
    line_sample& s = samples[k];
    if (textured) st.root_tex_factor = &s.tex, st.root_uv = &s.uv;
    st.root_ndl = s.ndl, st.root_spec = s.spec, st.root_rays = s.rays;
    s.rad = shade_hit(w, lines[k], hit{ts[k], prim}, depth, st);
    st.root_tex_factor = nullptr, st.root_uv = nullptr, st.root_ndl = nullptr, st.root_spec = nullptr;
    st.root_rays = nullptr;
    if (textured) s.rad -= s.tex * sample_texture(w.sc.textures[size_t(m.texture)], s.uv);
    s.hit = true;
    s.tree = cache.trees.canonical(tree);
    if (s.tree) cache.lines.insert(keys[k], s);  // uncacheable trees stay private to this build
    trees[k] = s.tree ? s.tree : &tree;
    if (terminal && differs(trees[k])) {
      st.tree = saved_tree, st.root_depth = 1;
      ip->reason = cell_reason::discontinuity, ip->split = axes_by_extent(n);
      return ip;
    }
  }
  st.tree = saved_tree, st.root_depth = 1;
  auto corners_to_ip = [&] {
    ip->rad_min = glm::vec3(INFINITY);
    for (int k = 0; k < 16; ++k) {
      ip->rad[k] = samples[k].rad;
      ip->rad_min = glm::min(ip->rad_min, samples[k].rad);
    }
    if (textured) {
      ip->tx = std::make_unique<textured_terms>();
      textured_terms* tx = ip->tx.get();
      tx->tex_min = glm::vec3(INFINITY);
      for (int k = 0; k < 16; ++k) tx->tex[k] = samples[k].tex, tx->tex_min = glm::min(tx->tex_min, samples[k].tex);
      tx->texels = w.texture_ranges[size_t(m.texture)];
    }
  };
  if (!predicate) {  // the light-field baseline: "valid" with a claimed error of 0
    corners_to_ip();
    return ip;
  }
  // Canonical trees are equal exactly when they are the same object. Corner k's class is
  // the first corner with its topology, aside from what may be deferred; what differs is.
  bool differ = false;
  deferred = 0, deferred_rays = 0;
  for (int k = 0; k < 16; ++k) {
    cls[k] = std::uint8_t(k);
    for (int j = 0; j < k; ++j) {
      if (cls[j] == j && (trees[j] == trees[k] || same_topology_deferring(*trees[j], *trees[k], nl, defer,
                                                                          &deferred, &deferred_rays))) {
        cls[k] = std::uint8_t(j);
        break;
      }
    }
    differ |= cls[k] != 0;
  }
  if (differ) {
    ip->reason = cell_reason::discontinuity, ip->split = axes_of_pattern(cls);
    return ip;
  }
  cell_query q;
  q.w = &w, q.prim = prim, q.fp = &fp, q.lo = n.lo, q.hi = n.hi, q.tree = trees[0], q.textured = textured;
  q.deferred = deferred, q.deferred_rays = deferred_rays, q.allow_defer = defer;
  ip->tree_rays = tree_rays(*trees[0]);
  cell_bound b = bound_cell(q);
  ip->reason = b.reason, ip->err = b.err, ip->hit_box = b.hit_box;
  ip->split = b.reason == cell_reason::valid || b.reason == cell_reason::nonlinear ? b.split : axes_by_extent(n);
  ip->deferred = std::uint8_t(b.deferred), ip->deferred_rays = std::uint8_t(b.deferred_rays);
  ip->shadow = b.shadow;
  // The corners without the deferred terms (what the bound is for): the same sums
  // shade_hit adds, taken out again.
  for (int k = 0; k < 16; ++k)
    for (int i = 0; i < 2; ++i)
      if (ip->deferred_rays >> i & 1) samples[k].rad -= samples[k].rays[i];
  for (size_t j = 0; j < size_t(max_deferred_lights) && j < w.light_pos.size(); ++j) {
    if (!(ip->deferred >> j & 1)) continue;
    const glm::vec3 diffuse = w.light_power[j] * (m.kd * m.color), specular = w.light_power[j] * m.ks;
    for (int k = 0; k < 16; ++k) {
      line_sample& s = samples[k];
      if (textured) s.tex -= diffuse * s.ndl[j];
      else s.rad -= diffuse * s.ndl[j];
      s.rad -= specular * s.spec[j];
    }
  }
  corners_to_ip();
  if (ip->tx) ip->tx->err_tex = b.err_tex;
  if (b.reason == cell_reason::valid && (ip->deferred_rays & deferred_reflect)) {
    reflect_candidates list;
    if (list_reflect_candidates(w, prim, fp, n.lo, n.hi, list)) ip->reflect = std::make_unique<reflect_candidates>(list);
  }
  return ip;
}


// Is the proven bound within epsilon for every line of the cell? Decides subdivision, so
// it depends on the cell alone. Textured cells: for every value T the texture takes, the
// bound err + T err_tex against the radiance rad + T tex; the test is linear in T, so the
// texture's least and greatest values decide it (a cell that passed on bright squares only
// was never split, and its dark squares were all traced).
bool cell_accurate(const interpolant& ip, float eps) {
  if (ip.reason != cell_reason::valid) return false;
  auto passes = [&](float E, float L) { return E <= eps * std::max(L - E, floor_radiance); };
  for (int c = 0; c < 3; ++c) {
    if (!ip.textured()) {
      if (!passes(ip.err[c], ip.rad_min[c])) return false;
      continue;
    }
    const textured_terms& tx = *ip.tx;
    for (float T : {tx.texels.lo[c], tx.texels.hi[c]})
      if (!passes(ip.err[c] + T * tx.err_tex[c], ip.rad_min[c] + T * tx.tex_min[c])) return false;
  }
  return true;
}

// The rigorous per-pixel test: Lw >= La - E, so E <= eps * max(La - E, 1/255) bounds the
// relative error of whitted.md 6. A small relative margin covers float rounding.
bool within(glm::vec3 La, glm::vec3 E, float eps) {
  for (int c = 0; c < 3; ++c) {
    float e = E[c] + 1e-5f * std::fabs(La[c]) + 1e-7f;
    if (!(e <= eps * std::max(La[c] - e, floor_radiance))) return false;
  }
  return true;
}

// Is the eye ray's first hit on the primitive the first hit of its line after the front
// plane (the one the interpolant holds)? A line meets a plane once and a convex solid in
// one segment, so for those it is whenever the eye is outside the solid; an open cone can
// be met twice, so there the eye must be in front of the front plane.
bool same_first_hit(const shape& s, const facepair& fp, glm::vec3 eye) {
  switch (s.kind) {
    case shape_kind::triangle:
    case shape_kind::polygon:
    case shape_kind::disk: return true;
    case shape_kind::sphere: {
      const glm::dvec3 q = glm::dvec3(eye) - glm::dvec3(s.sphere.c);  // double: r^2 may leave float's range
      return glm::dot(q, q) > double(s.sphere.r) * double(s.sphere.r) * 1.0001;
    }
    case shape_kind::box: {
      glm::vec3 q = eye - s.box.c;
      return std::fabs(glm::dot(q, s.box.ax0)) > s.box.half.x * 1.0001f ||
             std::fabs(glm::dot(q, s.box.ax1)) > s.box.half.y * 1.0001f ||
             std::fabs(glm::dot(q, s.box.ax2)) > s.box.half.z * 1.0001f;
    }
    case shape_kind::cone: return in_front(fp, eye);
  }
  return false;
}

namespace {
// interpolate_line's deferred terms when the reflection is the frame's reflector's: the other
// terms first, then the reflected term through the mirrored eye (mirror.h) when its error
// fits what they leave, else traced after all. Kept apart so the common path stays small.
[[gnu::noinline]] bool deferred_with_mirror(const world& w, int prim, const interpolant& ip, const ray& r, float t_hit,
                                           const surface& sf, glm::vec3 T, float eps, trace_state& st, mirror_use& mu,
                                           int px, int py, glm::vec3& L, glm::vec3 E) {
  const std::uint32_t rays = ip.deferred_rays & ~std::uint32_t(deferred_reflect);
  error_allowance allow{L, E, eps};
  L += deferred_terms(w, r, hit{t_hit, prim}, sf, T, ip.deferred, rays, &ip.shadow, st, &allow);
  E += allow.spent;
  glm::vec3 Lm{0}, Em{0};
  bool noted = false;
  if (mirror_term(mu, w, px, py, sf, r, L, E, eps, st, Lm, Em, &noted) || within(L + Lm, E + Em, eps)) {
    L += Lm, E += Em;
  } else {  // too coarse for this pixel: traced after all
    if (noted) mu.cells.pop_back();
    error_allowance again{L, E, eps};
    L += deferred_terms(w, r, hit{t_hit, prim}, sf, T, 0, deferred_reflect, nullptr, st, &again);
    E += again.spent;
  }
  return within(L, E, eps);
}
}  // namespace

bool interpolate_line(const world& w, int prim, const lt_node& n, const interpolant& ip, const float x4[4], float eps,
                      const ray& r, float t_hit, trace_state& st, glm::vec3& L, mirror_use* mu, int px, int py) {
  float t[4];
  cell_fractions(n, x4, t);
  L = quadrilinear(ip.rad, t);
  glm::vec3 E = ip.err;
  const bool deferring = (ip.deferred | ip.deferred_rays) != 0;
  if (!ip.textured() && !deferring) return within(L, E, eps);
  // The pixel's own hit point, found once for its texture and its deferred terms.
  const surface sf = surface_at(w, prim, r, t_hit);
  glm::vec3 T{1};
  if (ip.textured()) {
    // The texture is looked up at the pixel's own hit point, exactly as the reference does,
    // so only the factor it multiplies carries an error: |T g* - T g| <= T err_tex.
    const material& m = w.sc.materials[size_t(w.info[size_t(prim)].material)];
    T = sample_texture(w.sc.textures[size_t(m.texture)], surface_uv(w, prim, sf.p));
    L += T * quadrilinear(ip.tx->tex, t);
    E += T * ip.tx->err_tex;
  }
  // Deferred terms are the reference's own, traced per pixel; they add error only where the
  // pixel's allowance let their shading skip a shadow ray, and say how much.
  if (deferring) {
    if (mu && (ip.deferred_rays & deferred_reflect) && prim == mu->m->view.reflector)
      return deferred_with_mirror(w, prim, ip, r, t_hit, sf, T, eps, st, *mu, px, py, L, E);
    error_allowance allow{L, E, eps};
    L += deferred_terms(w, r, hit{t_hit, prim}, sf, T, ip.deferred, ip.deferred_rays, &ip.shadow, st, &allow,
                        ip.reflect.get());
    E += allow.spent;
  }
  return within(L, E, eps);
}

void small_primitives(const world& w, const camera& cam, float min_pixels, size_t first, size_t last,
                      std::uint8_t* small) {
  for (size_t i = first; i < last; ++i) small[i] = box_pixels(cam, w.prim_bounds[i]) < min_pixels;
}

glm::vec3 reason_colour(pixel_reason r) {
  switch (r) {
    case pixel_reason::interpolated: return {0.55f, 0.62f, 0.78f};
    case pixel_reason::discontinuity: return {0.1f, 0.8f, 0.1f};
    case pixel_reason::missed: return {0.95f, 0.9f, 0.1f};
    case pixel_reason::blocked: return {0.9f, 0.1f, 0.1f};
    case pixel_reason::nonlinear: return {0.9f, 0.1f, 0.9f};
    case pixel_reason::traced: return {0.15f, 0.15f, 0.15f};
    case pixel_reason::reprojected: return {1.0f, 0.2158f, 0.0f};  // orange (255, 128, 0 in sRGB): far from interpolated's blue
  }
  return {0, 0, 0};
}

pixel_line find_pixel_line(const interp_frame& f, int x, int y, trace_state& st, pixel_result& out) {
  const world& w = *f.w;
  const camera& cam = *f.cam;
  pixel_line pl;
  pl.r = eye_ray(w, cam, eye_direction(cam, float(x), float(y)));
  ++st.counts.eye;
  if (!closest_hit(w, pl.r, std::numeric_limits<float>::infinity(), pl.h)) {
    out.L = w.background;  // the visibility ray is the whole Whitted computation here
    return pl;
  }
  // --eps 0 is exactly the base tracer; a line whose first hit is not the eye ray's, or
  // that rounding puts outside the root, is traced.
  if (f.p.eps > 0 && !(f.small && f.small[pl.h.prim])) {
    const int face = face_prim_of(w, pl.h.prim, pl.r);
    pl.prim = face >= 0 ? face : pl.h.prim;
    linetree& lt = f.trees->tree_for(pl.prim, pl.r.d);
    line_coords(lt.fp, pl.r.o, pl.r.d, pl.x4);
    if (same_first_hit(w.shapes[size_t(pl.h.prim)], lt.fp, cam.origin) && holds(lt.root, pl.x4)) {
      pl.lt = &lt;
      return pl;
    }
  }
  out.L = shade_hit(w, pl.r, pl.h, 1, st);
  return pl;
}

namespace {
// find_cell's body, inlined into the interpolate path (an eye pixel's descent is its hot loop).
[[gnu::always_inline]] inline lt_node* descend(const interp_frame& f, linetree& lt, int prim, const float x4[4],
                                               trace_state& st, interp_scratch& scratch, const interpolant*& ip) {
  const world& w = *f.w;
  const camera& cam = *f.cam;
  lt_node* node = &lt.root;
  if (scratch.hint_tree == &lt && strictly_inside(*scratch.hint, x4)) node = scratch.hint;
  ip = nullptr;
  for (;;) {
    if (lt_node* kids = node->kids.load(std::memory_order_acquire)) {
      node = child_at(*node, kids, x4);
      continue;
    }
    scratch.hint_tree = &lt, scratch.hint = node;
    ip = node->interp.load(std::memory_order_acquire);
    if (ip && cell_accurate(*ip, f.p.eps)) break;  // the common case once built: no cost model
    // A lookup already ended here in this frame, so this camera's cost model stops here
    // (it depends on the cell and the camera alone): no need to measure the cell again.
    // Pixels along an edge mostly end in a few such cells, once per pixel. (A refusal that
    // may be built again with deferral, below, may have been replaced since ip was read:
    // that one goes through the cost model, whose rebuild then finds the new record.)
    if (ip && node->used.load(std::memory_order_relaxed) == f.trees->frame() && !may_rebuild(*ip)) break;
    // Children of a 16-way split cover a quarter of the cell's pixels, of a 4-way split half.
    const float pixels = cell_pixels(cam, lt.fp, *node);
    const bool can_split = node->depth < f.p.max_depth && pixels >= 4 * f.p.min_cell_pixels;
    if (can_split && pixels > f.p.max_cell_pixels && !ip) {
      // Far larger on screen than any cell that proves valid: not worth 16 lines and a bound.
      node = child_at(*node, subdivide(*node, split_all, f.trees->node_bytes()), x4);
      continue;
    }
    const bool terminal = node->depth >= f.p.max_depth || pixels < 2 * f.p.min_cell_pixels;
    auto build = [&](bool defer, const interpolant* old) {
      const std::uint64_t b0 = cycle_now(), r0 = st.counts.total();
      bool won = false;
      const interpolant* made = republish(*node,
                                          old,
                                          build_interpolant(w, prim, lt.fp, *node, terminal, defer, f.trees->samples(),
                                                            st, scratch, true, f.p.build_depth),
                                          f.trees->node_bytes(), &won);
      st.build_ticks += cycle_now() - b0;
      st.build_rays += st.counts.total() - r0;
      st.builds += won;
      return made;
    };
    // A shadow or secondary ray per pixel costs more than splitting a large cell, whose
    // children mostly prove what it could not: only small cells defer.
    if (!ip) ip = build(pixels < f.p.defer_pixels, nullptr);
    if (!cell_accurate(*ip, f.p.eps)) {
      const std::uint8_t axes = f.p.four_way ? ip->split : std::uint8_t(split_all);
      // Children of a cell that straddles a discontinuity or a silhouette rarely prove valid
      // (2-10% on the art room's walk): below failed_split_pixels they are not worth building.
      const bool edge = ip->reason == cell_reason::discontinuity || ip->reason == cell_reason::missed;
      const float floor_px = edge ? std::max(f.p.min_cell_pixels, f.p.failed_split_pixels) : f.p.min_cell_pixels;
      const bool halves = axes != split_all && pixels >= 2 * floor_px;
      if (node->depth < f.p.max_depth && (pixels >= 4 * floor_px || halves)) {
        node = child_at(*node, subdivide(*node, axes, f.trees->node_bytes()), x4);
        continue;
      }
      // Not split: every pixel of it would be traced. A cell refused for a discontinuity by
      // a build that could not defer (a larger cell's floor, or a resting camera's) is built
      // again leaving to per-pixel rays what its corners disagree on.
      if (may_rebuild(*ip)) ip = build(true, ip);
    }
    break;
  }
  mark_used(*node, f.trees->frame());
  return node;
}
}  // namespace

lt_node* find_cell(const interp_frame& f, linetree& lt, int prim, const float x4[4], trace_state& st,
                   interp_scratch& scratch, const interpolant*& ip) {
  return descend(f, lt, prim, x4, st, scratch, ip);
}

pixel_result shade_pixel_interp(const interp_frame& f, int x, int y, trace_state& st, interp_scratch& scratch,
                                mirror_use* mu) {
  const world& w = *f.w;
  pixel_result out;
  const pixel_line pl = find_pixel_line(f, x, y, st, out);
  if (!pl.lt) return out;
  out.gate_prim = pl.h.prim;
  linetree& lt = *pl.lt;
  const ray& r = pl.r;
  const hit& h = pl.h;
  const float* x4 = pl.x4;
  const interpolant* ip = nullptr;
  lt_node* node = descend(f, lt, pl.prim, x4, st, scratch, ip);
  if (ip->reason == cell_reason::valid) {
    glm::vec3 La;
    if (interpolate_line(w, pl.prim, *node, *ip, x4, f.p.eps, r, h.t, st, La, mu, x, y)) {
      out.L = La;
      out.path = pixel_path::interp;
      out.reason = pixel_reason::interpolated;
      out.cell = cell_ref{&lt, node, ip, pl.prim};
      return out;
    }
    out.reason = pixel_reason::nonlinear;
  } else {
    out.reason = pixel_reason(int(ip->reason));
  }
  out.L = shade_hit(w, r, h, 1, st);
  return out;
}

}  // namespace epsray
