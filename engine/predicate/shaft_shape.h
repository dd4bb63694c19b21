// Shaft culling past the boxes: a primitive whose box meets a shaft often does not meet the
// shaft itself (a pillar's square box beside a shadow shaft, a painting's box across a
// reflected one). Each such false candidate costs the predicate a deferred light or a
// refused cell, and reprojection a per-pixel hit test.
#pragma once
#include "accel/world.h"
#include "predicate/shaft.h"

namespace epsray {

// Could primitive `prim` itself meet the convex hull of A and B (the shaft s = make_shaft(a,
// b))? False only when a separating plane is found:
//   - one of the shaft's planes (the hull's faces joining A to B) with the whole primitive
//     beyond it, the primitive's extent taken from its own geometry (a sphere, the two cap
//     disks of a cone, a box's corners, a flat primitive's vertices or rim);
//   - a plane across one of the primitive's own directions (a box's three axes, a cone's
//     axis, a flat primitive's normal) with every corner of A and B beyond it.
// Either is a separating axis of two convex sets, and the primitive lies in the convex set
// whose extent is taken (a polygon in the hull of its vertices, a cone in the hull of its
// caps). Everything runs in double and each test keeps a margin of 2e-5 of the scene's
// scale, larger than the shaft's own slack, for the float tracer's rounding.
bool shape_may_meet_shaft(const world& w, int prim, const shaft& s, const bounds& a, const bounds& b);

// for_each_in_shaft over the world's BVH slots, calling visit(prim) only for primitives
// that shape_may_meet_shaft (a split primitive may be visited once per slot).
template <class Visit>
bool for_each_shape_in_shaft(const world& w, const shaft& s, const bounds& a, const bounds& b, Visit&& visit) {
  return for_each_in_shaft(w.tree, w.slot_bounds, w.slot_prim, s,
                           [&](int id) { return shape_may_meet_shaft(w, id, s, a, b) && visit(id); });
}

}  // namespace epsray
