// The primitives a flat mirror's reflected rays may meet, per linetree cell. A cell that
// leaves its reflection to per-pixel rays (deferred_reflect) sends one reflected ray per
// pixel, and each walked the whole BVH; the rays of one cell run in one narrow beam, so a
// short list found once, when the cell is built, answers them instead (whitted.cpp,
// closest_listed_hit), with the BVH walk's hit.
//
// The beam, for an axis-aligned flat object (a polygon, triangle or disk with no
// interpolated normals, or a box face) held by the facepair of its normal axis: reflecting
// in the plane y = y0 (y the facepair's axis) maps the part of an eye line past the plane
// onto its reflected ray, and the reflection of a direction in an axis plane is exact in
// floating point (one sign flips). The cell's lines cross the planes y = const in boxes:
// at front-plane fraction s a line is (1 - s) (a, b) + s (c, d), so the points of all its
// lines at one y form the box (1 - s) [a] + s [c] by [b] + s [d], and the points between two
// such planes lie in the convex hull of their two boxes. Past the plane a reflected ray
// can meet nothing beyond the scene's box, so the beam is the hull of the cell's box at
// y0 and at the scene's far side, mirrored: the shaft (shaft.h) of those two boxes.
#pragma once
#include <cstdint>

#include "accel/world.h"
#include "interp/line_space.h"
#include "shade/whitted.h"

namespace epsray {

// The two boxes whose shaft holds every reflected ray of the cell lo..hi of primitive
// `prim`'s facepair fp, each ray from where its line meets the plane to where it leaves the
// scene's box, grown for rounding and for the rays' origin offset delta. False when the
// cell is not of an axis-aligned flat mirror's own facepair.
bool reflect_beam(const world& w, int prim, const facepair& fp, const float lo[4], const float hi[4], bounds& from,
                  bounds& to);

// The primitives in that beam, when there are at most max_prims of them. False when the beam
// is not known (reflect_beam) or holds more: the rays walk the BVH.
bool list_reflect_candidates(const world& w, int prim, const facepair& fp, const float lo[4], const float hi[4],
                             reflect_candidates& out);

}  // namespace epsray
