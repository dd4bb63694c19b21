#include "shade/whitted.h"

#include <cmath>
#include <limits>
#include <type_traits>

#include "shade/surface.h"
#include "shade/texture.h"

namespace epsray {

namespace {

// The light cache's answer (accel/light_cache.h), else the BVH's. Out of line: base mode,
// the reference, has no cache and keeps its shading loop as it was. While a ray tree is
// recorded (a build), which names the blocker, a lit answer from the lists is taken (lit is
// lit whichever structure says so), but a blocked ray asks the BVH for the blocker the tree
// names, so trees are those without the cache; those rays are not counted for its rest rule.
[[gnu::noinline]] int listed_blocker_of(const world& w, const ray& r, float dist, size_t light, int prim,
                                        trace_state& st) {
  const int b = st.lights->blocker(light, r, dist, shadow_self(w, prim));
  if (st.tree) return b == -1 ? -1 : first_blocker(w, r, dist);
  ++st.counts.shadow_asked;
  if (b == light_cache::not_listed) return first_blocker(w, r, dist);
  ++st.counts.shadow_listed;
  return b;
}

// `prim`: the primitive the shadow ray leaves.
int shadow_blocker(const world& w, const ray& r, float dist, size_t light, int prim, trace_state& st) {
  const bool cached = !st.tree && light < size_t(shadow_cache_lights);
  if (cached) {
    int last = st.last_blocker[light];
    float t;
    if (last >= 0 && hit_shape(w.shapes[size_t(last)], w.polys, r, dist, t)) return last;
  }
  const int b = st.lights ? listed_blocker_of(w, r, dist, light, prim, st) : first_blocker(w, r, dist);
  if (cached) st.last_blocker[light] = b;
  return b;
}

// Light j at a surface point: whether it reaches the point (lit, behind the surface or
// the blocker's scene index) and, when lit, the diffuse cosine and the specular power.
// One routine for shade_hit and deferred_terms, so a per-pixel shadow ray is the reference's.
struct light_term {
  std::int32_t status = light_behind;
  float ndl = 0, spec = 0;
};

// The highlight's power for unit directions to the light lj and to the eye v.
inline float specular_power(const material& m, vec3 nf, vec3 lj, vec3 v) {
  return m.shine > 0 ? std::pow(std::max(0.0f, glm::dot(nf, glm::normalize(lj + v))), m.shine) : 0.0f;
}

// What a lit light j adds: its power times kd_c ndl + ks spec.
inline vec3 lit_term(const world& w, const material& m, vec3 kd_c, size_t j, float ndl, float spec) {
  return w.light_power[j] * (kd_c * ndl + m.ks * spec);
}

// Some primitive a shadow ray towards light j meets before the light, or -1: the BVH's
// answer, light j's last blocker tried first (shadow_blocker).
struct bvh_blocker {
  const world& w;
  size_t j;
  int prim;  // the primitive the ray leaves
  trace_state& st;
  int operator()(const ray& r, float dist) const { return shadow_blocker(w, r, dist, j, prim, st); }
};

// The shadow ray from `above` to light j: blocker_of(ray, dist) gives some primitive it
// meets before the light, or -1.
template <class Blocker>
inline int shadow_ray(const world& w, vec3 above, size_t j, trace_state& st, Blocker&& blocker_of) {
  ++st.counts.shadow;
  const vec3 so = w.light_pos[j] - above;
  const float dist = safe_length(so);
  return dist > 0 ? blocker_of(make_ray(above, so / dist), dist) : -1;
}

// The blocker of a light whose shaft a cell proved empty (shadow_candidates::lit): none,
// with no shadow ray. light_at's one body shades it, so its term is the reference's bit
// for bit (a second copy of the arithmetic may be contracted into other multiply-adds).
struct proven_lit {};

template <class Blocker>
inline light_term light_at(const world& w, const material& m, vec3 p, vec3 above, vec3 nf, vec3 v, size_t j,
                           trace_state& st, Blocker&& blocker_of) {
  light_term out;
  const vec3 lj = safe_normalize(w.light_pos[j] - p);
  out.ndl = glm::dot(nf, lj);
  if (!(out.ndl > 0)) return out;
  int blocker = -1;
  if constexpr (std::is_same_v<std::decay_t<Blocker>, proven_lit>) ++st.counts.shadow_proven;
  else blocker = shadow_ray(w, above, j, st, blocker_of);
  out.status = blocker >= 0 ? w.info[size_t(blocker)].source : light_lit;
  if (blocker < 0) out.spec = specular_power(m, nf, lj, v);
  return out;
}

// Light j under an error allowance: taken at half its unshadowed term t, with no shadow
// ray, when weight t / 2 fits in `left` (its true term is 0 or t); else its shadow ray is
// cast as light_at casts it. The diffuse part alone (t without the highlight, never more
// than t) refuses most, so the highlight's power is computed only for a light that may fit
// or is lit, as the reference computes it.
struct allowed_light {
  vec3 L{0}, cost{0};
};

template <class Blocker>
inline allowed_light light_within(const world& w, const material& m, vec3 kd_c, vec3 p, vec3 above, vec3 nf, vec3 v,
                                  size_t j, float weight, vec3 left, trace_state& st, Blocker&& blocker_of) {
  allowed_light out;
  const vec3 lj = safe_normalize(w.light_pos[j] - p);
  const float ndl = glm::dot(nf, lj);
  if (!(ndl > 0)) return out;  // behind the surface: no shadow ray, nothing added
  const float half_weight = 0.5f * weight;
  if (glm::all(glm::lessThanEqual(half_weight * (w.light_power[j] * (kd_c * ndl)), left))) {
    const vec3 t = lit_term(w, m, kd_c, j, ndl, specular_power(m, nf, lj, v));
    const vec3 cost = half_weight * t;
    if (glm::all(glm::lessThanEqual(cost, left))) {
      ++st.counts.shadow_bounded;
      out.L = 0.5f * t, out.cost = cost;
      return out;
    }
    if (shadow_ray(w, above, j, st, blocker_of) < 0) out.L = t;
    return out;
  }
  if (shadow_ray(w, above, j, st, blocker_of) < 0) out.L = lit_term(w, m, kd_c, j, ndl, specular_power(m, nf, lj, v));
  return out;
}

// Under an error allowance: a secondary ray of weight k from a hit at `depth` taken at the
// middle of what any ray of depth + 1 carries (world::rad), when the path's share of half
// that range fits in what is left: its true term lies within it, so the error is at most that.
inline bool skip_secondary(const world& w, float k, int depth, trace_state& st, vec3& L) {
  const vec3 lo = w.rad.lo[depth + 1], hi = w.rad.hi[depth + 1];
  const vec3 cost = 0.5f * st.path_weight * k * (hi - lo);
  if (!glm::all(glm::lessThanEqual(cost, *st.error_left))) return false;
  *st.error_left -= cost;
  L += 0.5f * k * (lo + hi);
  ++st.counts.secondary_bounded;
  return true;
}

inline light_term light_at(const world& w, const material& m, vec3 p, vec3 above, vec3 nf, vec3 v, size_t j,
                           int prim, trace_state& st) {
  return light_at(w, m, p, above, nf, v, j, st, bvh_blocker{w, j, prim, st});
}

// A secondary ray's radiance times k, with the path weight scaled by k while it is traced
// (what an error allowance charges for a skipped shadow ray below it).
template <class Trace>
inline vec3 weighted(float k, trace_state& st, Trace&& trace) {
  const float outer = st.path_weight;
  st.path_weight = outer * k;
  const vec3 L = trace();
  st.path_weight = outer;
  return k * L;
}

inline vec3 weighted_radiance(const world& w, float k, const ray& r, int depth, trace_state& st) {
  return weighted(k, st, [&] { return radiance(w, r, depth, st); });
}

// The reflected and transmitted terms of shade_hit (ks Lr, t Lt), shared with
// deferred_terms so a per-pixel secondary ray is the reference's. With `list` (a cell's
// reflected rays, reflect_shaft.h), the reflected ray's hit is found among its primitives:
// the BVH's hit, without the walk.
inline vec3 reflected_term(const world& w, const material& m, const ray& r, vec3 p, vec3 nf, int depth,
                           trace_state& st, const reflect_candidates* list = nullptr) {
  ++st.counts.reflect;
  const ray rr = make_ray(p + w.delta * nf, reflect_dir(r.d, nf));
  if (!list) return weighted_radiance(w, m.ks, rr, depth + 1, st);
  ++st.counts.reflect_listed;
  return weighted(m.ks, st, [&] {
    hit h;
    return closest_listed_hit(w, rr, *list, h) ? shade_hit(w, rr, h, depth + 1, st) : w.background;
  });
}

inline float refraction_k(const material& m, const ray& r, vec3 nf, bool entering, float& eta, float& ci) {
  eta = entering ? 1 / m.ior : m.ior;
  ci = glm::dot(-r.d, nf);
  return 1 - eta * eta * (1 - ci * ci);
}

inline bool total_internal(const material& m, const ray& r, vec3 nf, bool entering) {
  float eta, ci;
  return refraction_k(m, r, nf, entering, eta, ci) < 0;
}

inline vec3 transmitted_term(const world& w, const material& m, const ray& r, vec3 p, vec3 nf, bool entering,
                             int depth, trace_state& st) {
  ++st.counts.refract;
  float eta, ci;
  const float k = refraction_k(m, r, nf, entering, eta, ci);
  if (k < 0) return weighted_radiance(w, m.t, make_ray(p + w.delta * nf, reflect_dir(r.d, nf)), depth + 1, st);
  vec3 td = glm::normalize(eta * r.d + (eta * ci - std::sqrt(k)) * nf);
  return weighted_radiance(w, m.t, make_ray(p - w.delta * nf, td), depth + 1, st);
}

}  // namespace

vec3 radiance(const world& w, const ray& r, int depth, trace_state& st) {
  hit h;
  if (!closest_hit(w, r, std::numeric_limits<float>::infinity(), h)) {
    if (st.tree) st.tree->nodes.emplace_back();  // a miss: prim -1
    return w.background;
  }
  return shade_hit(w, r, h, depth, st);
}

vec3 shade_hit(const world& w, const ray& r, const hit& h, int depth, trace_state& st) {
  ray_tree* tree = st.tree;
  int node = -1;
  if (tree) {
    node = int(tree->nodes.size());
    tree->nodes.emplace_back();
  }

  const surface sf = surface_at(w, h.prim, r, h.t);
  const material& m = w.sc.materials[size_t(w.info[size_t(h.prim)].material)];
  const bool entering = glm::dot(sf.ng, r.d) < 0;
  const vec3 nf = entering ? sf.ns : -sf.ns;
  const vec3 v = -r.d;
  vec3 colour = m.color;
  const bool split = depth == st.root_depth && m.texture >= 0 && st.root_tex_factor;
  vec3 tex_factor{0};
  if (m.texture >= 0) {
    vec2 uv = surface_uv(w, h.prim, sf.p);
    if (split) *st.root_uv = uv, tex_factor = w.ambient * m.kd * m.color;
    colour *= sample_texture(w.sc.textures[size_t(m.texture)], uv);
  }
  const vec3 kd_c = m.kd * colour;

  if (tree) {
    ray_tree_node& n = tree->nodes[size_t(node)];
    n.prim = w.info[size_t(h.prim)].source;
    n.entering = entering;
    n.lights = std::uint32_t(tree->lights.size());
  }

  vec3 L = w.ambient * kd_c;
  const vec3 above = sf.p + w.delta * nf;
  const size_t nl = w.light_pos.size();
  const bool record = depth == st.root_depth && st.root_ndl;
  // An allowance used up (or none left for a dark pixel) is not worth the checks.
  const bool may_skip = st.error_left && !tree && !record && glm::any(glm::greaterThan(*st.error_left, vec3{0}));
  // A whole secondary subtree saves more rays than a shadow ray: offered the allowance first.
  const bool skip_r = may_skip && depth < max_depth && m.ks > 0 && skip_secondary(w, m.ks, depth, st, L);
  const bool skip_t = may_skip && depth < max_depth && m.t > 0 && skip_secondary(w, m.t, depth, st, L);
  for (size_t j = 0; j < nl; ++j) {
    if (may_skip) {
      const allowed_light al =
          light_within(w, m, kd_c, sf.p, above, nf, v, j, st.path_weight, *st.error_left, st, bvh_blocker{w, j, h.prim, st});
      L += al.L, *st.error_left -= al.cost;
      continue;
    }
    const light_term lt = light_at(w, m, sf.p, above, nf, v, j, h.prim, st);
    if (lt.status == light_lit) {
      L += lit_term(w, m, kd_c, j, lt.ndl, lt.spec);
      if (split) tex_factor += w.light_power[j] * (m.kd * m.color * lt.ndl);
    }
    if (record && j < size_t(max_deferred_lights)) {
      const bool lit = lt.status == light_lit;
      st.root_ndl[j] = lit ? lt.ndl : 0, st.root_spec[j] = lit ? lt.spec : 0;
    }
    if (tree) tree->lights.push_back(lt.status);
  }
  if (split) *st.root_tex_factor = tex_factor;

  if (depth == st.root_depth && st.root_rays) st.root_rays[0] = st.root_rays[1] = vec3{0};
  if (depth < max_depth && m.ks > 0 && !skip_r) {
    if (tree) tree->nodes[size_t(node)].reflect = std::int16_t(tree->nodes.size());
    const vec3 Lr = reflected_term(w, m, r, sf.p, nf, depth, st);
    if (depth == st.root_depth && st.root_rays) st.root_rays[0] = Lr;
    L += Lr;
  }
  if (depth < max_depth && m.t > 0 && !skip_t) {
    if (tree) {
      ray_tree_node& n = tree->nodes[size_t(node)];
      n.refract = std::int16_t(tree->nodes.size());
      n.tir = total_internal(m, r, nf, entering);
    }
    const vec3 Lt = transmitted_term(w, m, r, sf.p, nf, entering, depth, st);
    if (depth == st.root_depth && st.root_rays) st.root_rays[1] = Lt;
    L += Lt;
  }
  return L;
}

vec3 deferred_terms(const world& w, const ray& r, const hit& h, std::uint32_t lights, std::uint32_t rays,
                    trace_state& st) {
  const surface sf = surface_at(w, h.prim, r, h.t);
  const int tex = w.sc.materials[size_t(w.info[size_t(h.prim)].material)].texture;
  const vec3 texel = tex >= 0 ? sample_texture(w.sc.textures[size_t(tex)], surface_uv(w, h.prim, sf.p)) : vec3(1);
  return deferred_terms(w, r, h, sf, texel, lights, rays, nullptr, st);
}

namespace {

// A cell's listed candidates (shadow_candidates): some one of them a shadow ray meets
// before the light, or -1.
struct listed_blocker {
  const world& w;
  const shadow_candidates& cands;
  int operator()(const ray& sr, float dist) const {
    for (int i = 0; i < cands.count; ++i) {
      float t;
      const int id = cands.prims[i];
      const bounds& b = w.hit_boxes[size_t(id)];  // first, as the BVH does: most candidates miss
      if (hit_bounds(b.lo, b.hi, sr, dist, t) && hit_shape(w.shapes[size_t(id)], w.polys, sr, dist, t)) return id;
    }
    return -1;
  }
};

inline light_term light_at_listed(const world& w, const material& m, vec3 p, vec3 above, vec3 nf, vec3 v, size_t j,
                                  const shadow_candidates& cands, trace_state& st) {
  return light_at(w, m, p, above, nf, v, j, st, listed_blocker{w, cands});
}

// An eye ray's hit under a pixel's error allowance: the lights of `lights` (bit j; every
// light when `every`) and the secondary rays of `rays`, where the radiance already summed
// is at least `known` with proven error `err` (error_room). A light is taken at half its
// unshadowed term, and a secondary ray at the middle of its range (skip_secondary), when
// that fits; a secondary ray that does not is traced with what is left
// (trace_state::error_left). Adds the error it allowed to `spent`. Returns its terms added
// to `start`, in shade_hit's order, so that where nothing fits it is shade_hit's sum bit for bit.
vec3 terms_within(const world& w, const material& m, const ray& r, int prim, const surface& sf, vec3 nf, bool entering,
                  vec3 kd_c, std::uint32_t lights, bool every, std::uint32_t rays, const shadow_candidates* cands,
                  const reflect_candidates* refl, trace_state& st, vec3 start, vec3 known, vec3 err, float eps,
                  vec3& spent) {
  const vec3 v = -r.d, above = sf.p + w.delta * nf;
  const size_t nl = every ? w.light_pos.size() : std::min(w.light_pos.size(), size_t(max_deferred_lights));
  // L: the sum returned; known + L - start: what the pixel's radiance is at least.
  vec3 L = start;
  known -= start;
  // The room before the lights, less what skipped ones take: the lights traced would widen
  // it, but a division per light cost more than the rays it saved.
  vec3 room = error_room(known + L, err + spent, eps);
  for (size_t j = 0; j < nl; ++j) {
    if (!every && !(lights >> j & 1)) continue;
    if (cands && j < size_t(max_deferred_lights) && (cands->lit >> j & 1)) {  // exact: nothing charged to the room
      const light_term lt = light_at(w, m, sf.p, above, nf, v, j, st, proven_lit{});
      if (lt.status == light_lit) L += lit_term(w, m, kd_c, j, lt.ndl, lt.spec);
      continue;
    }
    const bool listed = cands && j < size_t(max_deferred_lights) && (cands->lights >> j & 1);
    const allowed_light al =
        listed ? light_within(w, m, kd_c, sf.p, above, nf, v, j, 1.0f, room, st, listed_blocker{w, *cands})
               : light_within(w, m, kd_c, sf.p, above, nf, v, j, 1.0f, room, st, bvh_blocker{w, j, prim, st});
    L += al.L, spent += al.cost, room -= al.cost;
  }
  for (int i = 0; i < 2; ++i) {
    const bool traced = i == 0 ? (rays & deferred_reflect) && m.ks > 0 : (rays & deferred_refract) && m.t > 0;
    if (!traced) continue;
    const float k = i == 0 ? m.ks : m.t;
    // A cell's list of what its reflected rays may meet narrows what they can carry.
    const vec3 lo = i == 0 && refl ? refl->rad_lo : w.rad.lo[2], hi = i == 0 && refl ? refl->rad_hi : w.rad.hi[2];
    const vec3 range = hi - lo, mid = 0.5f * (hi + lo);
    vec3 left = error_room(known + L, err + spent, eps);
    if (glm::all(glm::lessThanEqual(0.5f * k * range, left))) {
      L += k * mid, spent += 0.5f * k * range, ++st.counts.secondary_bounded;
      continue;
    }
    const vec3 offered = left;
    st.error_left = &left, st.path_weight = 1;
    L += i == 0 ? reflected_term(w, m, r, sf.p, nf, 1, st, refl) : transmitted_term(w, m, r, sf.p, nf, entering, 1, st);
    st.error_left = nullptr;
    spent += offered - left;
  }
  return L;
}

}  // namespace

vec3 deferred_terms(const world& w, const ray& r, const hit& h, const surface& sf, vec3 texel, std::uint32_t lights,
                    std::uint32_t rays, const shadow_candidates* cands, trace_state& st, error_allowance* allow,
                    const reflect_candidates* reflect) {
  const material& m = w.sc.materials[size_t(w.info[size_t(h.prim)].material)];
  const bool entering = glm::dot(sf.ng, r.d) < 0;
  const vec3 nf = entering ? sf.ns : -sf.ns;
  const vec3 kd_c = m.kd * (m.texture >= 0 ? m.color * texel : m.color);
  if (allow && !st.tree) {
    allow->spent = vec3{0};
    return terms_within(w, m, r, h.prim, sf, nf, entering, kd_c, lights, false, rays, cands, reflect, st, vec3{0},
                        allow->known, allow->err, allow->eps, allow->spent);
  }
  vec3 L{0};
  if (lights) {
    const vec3 above = sf.p + w.delta * nf;
    for (size_t j = 0; j < w.light_pos.size() && j < size_t(max_deferred_lights); ++j) {
      if (!(lights >> j & 1)) continue;
      const bool proven = cands && (cands->lit >> j & 1);
      const bool listed = cands && (cands->lights >> j & 1);
      const light_term lt = proven   ? light_at(w, m, sf.p, above, nf, -r.d, j, st, proven_lit{})
                            : listed ? light_at_listed(w, m, sf.p, above, nf, -r.d, j, *cands, st)
                                     : light_at(w, m, sf.p, above, nf, -r.d, j, h.prim, st);
      if (lt.status == light_lit) L += lit_term(w, m, kd_c, j, lt.ndl, lt.spec);
    }
  }
  if ((rays & deferred_reflect) && m.ks > 0) L += reflected_term(w, m, r, sf.p, nf, 1, st);
  if ((rays & deferred_refract) && m.t > 0) L += transmitted_term(w, m, r, sf.p, nf, entering, 1, st);
  if (allow) allow->spent = vec3{0};
  return L;
}

vec3 shade_within(const world& w, const ray& r, const hit& h, float eps, trace_state& st) {
  // Below error_room's own rounding margin nothing can be bounded, and the reference's sum
  // is kept bit for bit (terms_within's may round an ulp apart where the compiler fuses
  // shade_hit's multiply-adds differently).
  if (!(eps >= 1e-5f)) return shade_hit(w, r, h, 1, st);
  const surface sf = surface_at(w, h.prim, r, h.t);
  const material& m = w.sc.materials[size_t(w.info[size_t(h.prim)].material)];
  const bool entering = glm::dot(sf.ng, r.d) < 0;
  const vec3 nf = entering ? sf.ns : -sf.ns;
  vec3 colour = m.color;
  if (m.texture >= 0) colour *= sample_texture(w.sc.textures[size_t(m.texture)], surface_uv(w, h.prim, sf.p));
  const vec3 kd_c = m.kd * colour;
  const vec3 L = w.ambient * kd_c;
  vec3 spent{0};
  return terms_within(w, m, r, h.prim, sf, nf, entering, kd_c, 0, true, deferred_reflect | deferred_refract, nullptr,
                      nullptr, st, L, L, vec3{0}, eps, spent);
}

vec3 trace_eye(const world& w, const ray& r, trace_state& st) {
  ++st.counts.eye;
  if (st.tree) st.tree->clear();
  return radiance(w, r, 1, st);
}

}  // namespace epsray
