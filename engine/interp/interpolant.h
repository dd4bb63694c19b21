// A radiance interpolant (section 4.3): the radiance of the 16 extremal lines of a 4D cell,
// interpolated quadrilinearly, with the error bound the predicate proved for the cell.
#pragma once
#include <cstdint>
#include <memory>
#include <glm/glm.hpp>

#include "geom/bounds.h"
#include "interp/node_pool.h"
#include "shade/whitted.h"

namespace epsray {

// Which axes a subdivision halves, bit i for axis i of (a, b, c, d). Halving (a, c) or
// (b, d) alone gives 4 children (the paper's 4-way split, section 8.6); all four, 16.
enum : std::uint8_t { split_ac = 0x5, split_bd = 0xA, split_all = 0xF };

// Why a cell may not be interpolated; the colours of the error-coded image (--reasons).
enum class cell_reason : std::uint8_t {
  valid,          // grey-blue: interpolated
  discontinuity,  // green: ray trees differ, TIR, a light's side or a sheet changes
  missed,         // yellow: some line of the cell misses the object
  blocked,        // red: an occluder may lie in a shaft of the cell
  nonlinear,      // magenta: the second-order bound exceeds epsilon
};

// What a textured cell adds: kept apart, since most cells are untextured and a linetree's
// memory is mostly interpolants (this is 240 of an interpolant's 520 bytes otherwise).
struct textured_terms {
  glm::vec3 tex[16];       // the factor the root's texture multiplies, per corner
  glm::vec3 tex_min{0};    // the smallest corner factor per channel
  texture_range texels;    // the values the texture takes
  glm::vec3 err_tex{0};    // proven bound of |f - interpolated f| for tex, per channel
  static void* operator new(std::size_t bytes) { return node_pool::allocate(bytes); }
  static void operator delete(void* p, std::size_t bytes) noexcept { node_pool::deallocate(p, bytes); }
};

// Corner k of a cell: bit 0 picks a's upper end, bit 1 b's, bit 2 c's, bit 3 d's.
struct interpolant {
  cell_reason reason = cell_reason::valid;
  bool shared = false;     // a failure_record: owned by no node
  bool could_defer = false;  // built with per-pixel rays allowed (build_interpolant's `defer`)
  std::uint8_t split = split_all;  // the axes worth halving when the cell is not accurate
  std::uint8_t deferred = 0;  // bit j: light j is shaded per pixel with a shadow ray, not
                              // interpolated (its visibility changes inside the cell)
  std::uint8_t deferred_rays = 0;  // deferred_reflect / deferred_refract: traced per pixel
  // Rays the reference casts for corner 0's line (its ray tree's rays and shadow rays,
  // deferred parts included): what a pixel served by the cell would cost traced, in the
  // object gate's count of what cells save (engine/interp/object_gate.h).
  std::uint16_t tree_rays = 0;
  shadow_candidates shadow;        // deferred lights' possible blockers (engine/shade/whitted.h)
  glm::vec3 rad[16];       // radiance but the deferred lights'; textured: the part the
                           // texture does not multiply
  glm::vec3 rad_min{0};    // the smallest corner radiance per channel
  glm::vec3 err{0};        // proven bound of |f - interpolated f| for rad, per channel
  bounds hit_box;          // valid cells: where the cell's lines meet the object (reprojection's
                           // occlusion test from a new eye)
  std::unique_ptr<textured_terms> tx;  // textured cells only
  // Cells of a flat mirror that trace its reflection per pixel: what the reflected rays may
  // meet, when a short list holds it (engine/predicate/reflect_shaft.h).
  std::unique_ptr<reflect_candidates> reflect;
  bool textured() const { return tx != nullptr; }
  // From the node pool (node_pool.h), as the nodes are.
  static void* operator new(std::size_t bytes) { return node_pool::allocate(bytes); }
  static void operator delete(void* p, std::size_t bytes) noexcept { node_pool::deallocate(p, bytes); }
  std::size_t bytes() const {
    return sizeof(interpolant) + (tx ? sizeof(textured_terms) : 0) + (reflect ? sizeof(reflect_candidates) : 0);
  }
};

// Failed cells keep only why they failed and which axes to halve: one shared, immutable
// record per (reason, split) instead of an interpolant of ~600 bytes each.
const interpolant* failure_record(cell_reason r, std::uint8_t split, bool could_defer = false);

// The quadrilinear interpolant of 16 corner values at cell-relative coordinates t (each in
// [0, 1]): halving the corners along a, then b, c and d, 15 lerps in all (the 16 weights
// and their sum cost three times the arithmetic; this runs once per fast pixel).
template <class V>
inline V quadrilinear(const V v[16], const float t[4]) {
  V a[8], b[4], c[2];
  for (int k = 0; k < 8; ++k) a[k] = v[2 * k] + t[0] * (v[2 * k + 1] - v[2 * k]);
  for (int k = 0; k < 4; ++k) b[k] = a[2 * k] + t[1] * (a[2 * k + 1] - a[2 * k]);
  for (int k = 0; k < 2; ++k) c[k] = b[2 * k] + t[2] * (b[2 * k + 1] - b[2 * k]);
  return c[0] + t[3] * (c[1] - c[0]);
}

}  // namespace epsray
