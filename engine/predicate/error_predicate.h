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
};

struct cell_bound {
  cell_reason reason = cell_reason::valid;
  std::uint8_t split = split_all;  // the axes to halve if the bound is too large
  glm::vec3 err{0}, err_tex{0};
  glm::vec2 err_uv{0};
  bounds hit_box;  // valid cells: a box holding every point where the cell's lines meet the object
};

cell_bound bound_cell(const cell_query& q);

}  // namespace epsray
