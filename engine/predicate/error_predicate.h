// The error predicate (section 5), made conservative: for a cell of one object's linetree
// whose 16 extremal lines share one ray-tree topology, it either proves that every line
// of the cell has that topology (no gap, occluder, TIR edge, light-side or sheet change)
// and bounds |f - If| for the quadrilinear interpolant If of the radiance f, or says why
// it cannot.
#pragma once
#include "accel/world.h"
#include "interp/interpolant.h"
#include "interp/line_space.h"
#include "shade/ray_tree.h"

namespace epsray {

struct cell_query {
  const world* w = nullptr;
  int prim = -1;                 // primitive id (BVH order) the lines hit first
  const facepair* fp = nullptr;
  const float* lo = nullptr;     // the cell: a, b, c, d ranges
  const float* hi = nullptr;
  const ray_tree* tree = nullptr;  // the common topology of the 16 extremal lines
  bool textured = false;         // split the root's texture factor and uv off (section 7)
  std::uint32_t deferred = 0;    // the root's lights left to per-pixel shadow rays (the
                                 // corners' statuses differ): bit j, light j < 8
  std::uint32_t deferred_rays = 0;  // the root's subtrees left to per-pixel rays
                                    // (deferred_reflect, deferred_refract)
  bool allow_defer = false;      // may more lights and subtrees be deferred when they cannot
                                 // be proven or bounded
};

struct cell_bound {
  cell_reason reason = cell_reason::valid;
  std::uint8_t split = split_all;  // the axes to halve if the bound is too large
  glm::vec3 err{0}, err_tex{0};
  bounds hit_box;  // valid cells: a box holding every point where the cell's lines meet the object
  std::uint32_t deferred = 0;  // q.deferred and (allow_defer) the root lights whose
                               // visibility or shading this cell could not prove: bounded
                               // without them, they are shaded per pixel with a shadow ray
                               // (deferred_terms)
  std::uint32_t deferred_rays = 0;  // likewise the root's subtrees, traced per pixel
  shadow_candidates shadow;         // deferred lights whose shadow rays may test these alone
};

cell_bound bound_cell(const cell_query& q);

}  // namespace epsray
