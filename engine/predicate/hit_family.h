// Where a cell's whole family of lines meets one primitive: the first surface every line
// meets with t > 0, its points, normals and box, proven for the family or refused with the
// reason (a gap, a silhouette, an edge). Used by the error predicate (bound_cell).
#pragma once
#include "accel/world.h"
#include "interp/interpolant.h"
#include "predicate/jet_vec.h"

namespace epsray::family {

struct surface_family {
  djet t;
  jv p, ng;            // hit points; outward geometric normals
  bounds box;          // holds every hit point (tighter than p's range on planes)
  bool from_outside = true;  // spheres, boxes, cones: every ray arrives from outside the solid
};

// The family o + t d hits primitive `prim` at its first surface with t > 0, for every line
// of the cell: valid, or why not. span, when given, is the family's unnormalized direction
// (d = span / |span|); the cell's own lines are o + s span, affine in (a, b, c, d).
cell_reason hit_family(const world& w, int prim, const jv& o, const jv& d, const jv* span, surface_family& s);

// Is every point of the box b (which lies around the polygon's or disk's plane, normal n)
// inside it?
bool inside_planar(const world& w, const primitive& pr, const bounds& b, glm::dvec3 n);

// A patch's interpolated normals at the points p: the family must stay inside one fan
// triangle, else a kink (discontinuity).
cell_reason patch_normal(const world& w, const primitive& pr, const jv& p, jv& ns);

}  // namespace epsray::family
