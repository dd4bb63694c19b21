// Whitted radiance exactly as ../shared/spec/whitted.md section 4 defines it: the reference
// every accelerated path is judged against.
#pragma once
#include <cstdint>

#include "accel/light_cache.h"
#include "accel/prim_list.h"
#include "accel/world.h"
#include "shade/ray_tree.h"

namespace epsray {

// max_depth (eye ray = depth 1): shade/radiance_bound.h, which world.h includes.

struct ray_counts {
  std::uint64_t eye = 0, reflect = 0, refract = 0, shadow = 0;
  // Rays an error allowance bounded instead of casting: shadow rays (a light taken at half
  // its term) and secondary rays with their subtrees (taken at the middle of their range).
  // Not rays traced, so not in total().
  std::uint64_t shadow_bounded = 0, secondary_bounded = 0;
  // Of the shadow rays, those that asked the light cache (accel/light_cache.h) and those it
  // answered from a cell's list instead of a BVH walk: still rays cast, in shadow and total().
  std::uint64_t shadow_asked = 0, shadow_listed = 0;
  // Deferred lights a cell proved lit at every pixel (shadow_candidates::lit), shaded with
  // no shadow ray: not rays, so not in total().
  std::uint64_t shadow_proven = 0;
  // Of the reflected rays, those a cell's list of what its beam may meet answered instead
  // of a BVH walk (reflect_candidates): still rays cast, in reflect and total().
  std::uint64_t reflect_listed = 0;
  std::uint64_t total() const { return eye + reflect + refract + shadow; }
  ray_counts& operator+=(const ray_counts& o) {
    eye += o.eye, reflect += o.reflect, refract += o.refract, shadow += o.shadow;
    shadow_bounded += o.shadow_bounded, secondary_bounded += o.secondary_bounded;
    shadow_asked += o.shadow_asked, shadow_listed += o.shadow_listed, shadow_proven += o.shadow_proven;
    reflect_listed += o.reflect_listed;
    return *this;
  }
};

// Per-thread state of one trace: counters, and the ray tree to record (or null).
constexpr int shadow_cache_lights = 8;

struct trace_state {
  ray_counts counts;
  // Time-stamp counter ticks spent building interpolants (engine/interp), which the
  // pixel that first reaches a cell pays: --stats build_ms.
  std::uint64_t build_ticks = 0;
  // Rays traced while building interpolants (within counts) and the cells this state
  // published: which pixel pays for a build depends on the threads' race, so the object
  // gate (engine/interp/object_gate.h) counts a pixel's own rays without these, and the
  // builds by their number, which does not depend on it.
  std::uint64_t build_rays = 0;
  std::uint32_t builds = 0;
  ray_tree* tree = nullptr;
  // Per light, the primitive that last blocked a shadow ray: neighbouring points are mostly
  // shadowed by the same one, so it is tested before a BVH walk. Only whether something
  // blocks enters the radiance, so images cannot change; while a ray tree is recorded
  // (which names the blocker) the cache is bypassed, so trees never depend on what this
  // state traced before. One state per tile keeps it off other threads' tiles.
  int last_blocker[shadow_cache_lights] = {-1, -1, -1, -1, -1, -1, -1, -1};
  // Interp and full modes: shadow rays are tested against the light cache's lists, which
  // give the BVH walk's answer (accel/light_cache.h); while a ray tree is recorded, which
  // names the blocker, only their lit answers are taken and a blocked ray asks the BVH for
  // its blocker. Null (base mode, the reference): every shadow ray walks the BVH.
  const light_cache* lights = nullptr;
  // When set, shading at depth 1 stores the factor the root's texture multiplies
  // (A*Kd*C + sum of lit Ij*Kd*C*dot(Nf, Lj), texture excluded) and the root's uv, so an
  // interpolant can keep texture lookups out of the interpolated terms.
  vec3* root_tex_factor = nullptr;
  // The depth of the ray whose shading the root_ pointers record: 1, an eye line's; 2, a
  // reflected line's (cells built for a planar reflector's reflections, engine/reproject/mirror.h).
  int root_depth = 1;
  vec2* root_uv = nullptr;
  // When set, shading at depth 1 stores per light j < max_deferred_lights its diffuse
  // cosine and specular power where the light reaches the point (0 elsewhere): an
  // interpolant that leaves light j to per-pixel shadow rays subtracts its term from the
  // corners (engine/interp).
  float* root_ndl = nullptr;
  float* root_spec = nullptr;
  // When set, shading at depth 1 stores its reflected and transmitted terms (ks Lr, t Lt;
  // 0 when not traced), which an interpolant may leave to per-pixel rays.
  vec3* root_rays = nullptr;
  // When set (deferred_terms with an error_allowance, never while a tree is recorded): the
  // error, per channel and in the pixel's units, that shading below the deferred secondary
  // ray may still add. A light whose unshadowed term t, times the path's weight (the
  // product of ks and T down to here), fits in half of what is left is taken at t / 2 with
  // no shadow ray: its true term is 0 or t, so the error is at most weight * t / 2.
  vec3* error_left = nullptr;
  float path_weight = 1;
};

// What a pixel may spend on its deferred secondary rays: the radiance already summed and
// its proven error (before the deferred terms), the pixel's epsilon, and on return the
// error the per-pixel rays' shading added (to be added to the pixel's bound).
struct error_allowance {
  vec3 known{0}, err{0};
  float eps = 0;
  vec3 spent{0};
};

// The error a pixel's secondary rays may still add, per channel: its radiance so far is at
// least `known` with proven error `err`, and it passes when E <= eps (L - E) (within,
// engine/interp), so error s may be added while (1 + eps)(err + s) <= eps known; most of
// that, with a margin for within's rounding allowance.
inline vec3 error_room(vec3 known, vec3 err, float eps) {
  return glm::max(vec3{0}, 0.9f * (eps * known / (1 + eps) - err) - 1e-5f * known - 1e-6f);
}

// The primitives that may block deferred lights' shadow rays, for a cell whose shadow
// shafts hold few of them: each listed light's per-pixel shadow ray is tested against
// these alone, which gives the BVH walk's answer since no other primitive meets its shaft.
// A deferred light whose shaft nothing meets (`lit`) reaches every pixel of the cell: its
// term is computed per pixel as the reference computes it, with no shadow ray (the cell's
// corners disagree on it only through its diffuse cosine or highlight, too curved to
// interpolate, or its side of the surface).
struct shadow_candidates {
  static constexpr int max_prims = 6;
  std::uint32_t lights = 0;  // bit j: light j's shaft is covered by prims
  std::uint32_t lit = 0;     // bit j: light j's shaft holds no primitive at all
  int count = 0;
  std::int32_t prims[max_prims] = {};
};

// The primitives a cell's per-pixel reflected rays may meet (engine/predicate/reflect_shaft.h),
// and what any of those rays can carry: the range of a depth-2 ray (radiance_bound.h) over
// the listed primitives' materials and the background, within world::rad's.
struct reflect_candidates : prim_list {
  vec3 rad_lo{0}, rad_hi{0};
};

// Secondary rays of an eye ray's hit that a cell may leave to per-pixel tracing.
enum : std::uint32_t { deferred_reflect = 1, deferred_refract = 2 };

// Lights a cell may leave to per-pixel shadow rays: the first 8, one bit each.
constexpr int max_deferred_lights = 8;

// The direction of the reflected ray (whitted.md 4): unit d and nf give a unit reflection,
// with no normalize on the hot path.
inline vec3 reflect_dir(vec3 d, vec3 nf) { return d - 2 * glm::dot(d, nf) * nf; }

// Radiance along an eye ray (depth 1); records the ray tree into state.tree when set.
vec3 trace_eye(const world& w, const ray& r, trace_state& state);

// Radiance along any ray at the given depth (1 = eye ray).
vec3 radiance(const world& w, const ray& r, int depth, trace_state& state);

// Radiance leaving the surface at a hit already found (the eye ray's visibility hit, or a
// line's hit on one object); records the ray tree from this node on when state.tree is set
// (the caller clears it).
vec3 shade_hit(const world& w, const ray& r, const hit& h, int depth, trace_state& state);

// The terms of an eye ray's hit that an interpolant left to per-pixel rays, computed
// exactly as shade_hit computes them at depth 1: the direct terms of the lights in
// `lights` (bit j: light j), shadow rays included, and the reflected / transmitted terms
// named in `rays` (deferred_reflect, deferred_refract), traced.
vec3 deferred_terms(const world& w, const ray& r, const hit& h, std::uint32_t lights, std::uint32_t rays,
                    trace_state& state);
// The same at a surface point the caller has already found (surface_at of r and h) with
// its texture value (1 when untextured): the interpolate path has both at hand. Lights
// listed in `candidates` (may be null) test their shadow rays against its prims alone.
struct surface;
// With `reflect` (and `allow`), the reflected ray finds its hit among those primitives.
// With `allow`, the secondary rays' shading may skip shadow rays within the pixel's
// remaining error (trace_state::error_left); allow->spent says how much it used.
vec3 deferred_terms(const world& w, const ray& r, const hit& h, const surface& sf, vec3 texel, std::uint32_t lights,
                    std::uint32_t rays, const shadow_candidates* candidates, trace_state& state,
                    error_allowance* allow = nullptr, const reflect_candidates* reflect = nullptr);

// The radiance of an eye ray's hit, for a pixel of full mode's plain frames
// (engine/interp/object_gate.h): every term as shade_hit computes it at depth 1, except that
// lights and secondary rays whose error fits the pixel's epsilon are bounded instead of
// traced (terms_within in whitted.cpp), down the whole ray tree. Within eps of shade_hit's
// radiance (whitted.md 6); under eps 1e-5, where nothing fits, it is shade_hit's. (Traced
// pixels of frames with cells stay exact: there its checks cost the balls-s3 orbit 4% for
// 5% fewer shadow rays, and gained mount-s4's glass 7%.)
vec3 shade_within(const world& w, const ray& r, const hit& h, float eps, trace_state& st);

}  // namespace epsray
