// Planar reflections through the mirrored eye. A plane's reflected rays are the eye rays of
// the eye mirrored in it: the floor point P seen through pixel (x, y) reflects along the
// line from the mirrored eye E' through P, which is the mirrored camera's eye ray through
// the same pixel. So the cells that served last frame's reflected rays can be reprojected
// from E' exactly as the eye's cells are from E, and a floor pixel whose cell leaves its
// reflection to a per-pixel ray takes it, where a reprojected mirror cell holds the
// reflected line and nothing can hide the cell, from the cell's interpolant: no BVH walk,
// no shading, no shadow rays. Elsewhere the reflected ray is traced to its first hit and
// looked up in linetrees of their own (built for depth-2 rays, with the mirrored camera's
// cost model), which seeds the next frame's list.
//
// What makes it sound:
//  - the reflected ray is the reference's (origin P + delta n, direction reflect(d, n)),
//    and its own line must lie in the cell (line_coords, holds), so the interpolant's bound
//    is for the pixel's own line;
//  - a mirror cell's lines are shaded as depth-2 rays (trace_state::root_depth), so its
//    corners carry the reference's depth limit for a reflected ray, and it defers nothing;
//  - the trust shaft runs from a box around E' that holds every reflected line's point
//    behind the plane (E' + delta n, padded for rounding) to the cell's hit box; the rays
//    start above the plane, so the reflector and every primitive on or behind its plane
//    are left out, and the other primitives in the shaft are each pixel's candidates;
//  - each pixel checks that its ray's origin sees the first hit the cell's lines hold
//    (same_first_hit from the ray's origin, not from E'), and its own error test decides
//    with the mirror term's error (ks times the cell's bound) added.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "accel/world.h"
#include "interp/interp_shade.h"
#include "reproject/reproject.h"

namespace epsray {

struct surface;

// The reflector of a frame and the eye mirrored in its plane.
struct mirror_view {
  int reflector = -1;      // scene primitive; -1: none this frame
  glm::vec3 n{0};          // unit normal of the plane n.x = d, towards the eye
  float d = 0;
  float ks = 0;
  camera cam;              // the mirrored eye, same pixels: (x, y) looks along the reflection of the eye's (x, y)
  bounds eye_box;          // every pixel's reflected line passes through it behind the plane
};

// The planar primitive (polygon or disk) with ks > 0 whose box covers the most pixels, at
// least min_share of the image, and the eye mirrored in its plane; reflector -1 if none.
// A function of the camera and the scene alone.
mirror_view choose_mirror(const world& w, const camera& cam, float min_share = 0.1f);

// The error a mirror cell may have, relative to its radiance, for a reflector of this ks
// at the pixels' epsilon: the term is weighted by ks, and the pixel's own test decides.
float mirror_eps(float eps, float ks);

// Is every point of b on the plane or behind it (no reflected ray can meet it)?
bool behind_mirror(const mirror_view& m, const bounds& b);

// Trust of cell c from the mirrored eye (trust_from's rules, with the shaft from
// m.eye_box, leaving out the reflector and what lies behind its plane). Cells of box
// faces that reach past their face are not trusted.
cell_trust trust_from_mirror(const world& w, const cell_ref& c, const mirror_view& m);

// What a frame's mirror lookups share (read-only while tiles are shaded).
struct mirror_frame {
  mirror_view view;
  interp_frame f;          // the mirror trees, the mirrored camera and its cost model
  const std::vector<cell_ref>* cells = nullptr;  // last frame's mirror cells
  const std::int32_t* owner = nullptr;           // per pixel, from the mirrored eye; -1: none
  const std::vector<cell_trust>* trust = nullptr;
};

// Per tile: the lookups' hint, the mirror cells its pixels used (for the next frame), counts.
struct mirror_use {
  const mirror_frame* m = nullptr;
  interp_scratch scratch;
  std::vector<cell_ref> cells;
  std::uint64_t filled = 0, looked_up = 0, traced = 0;  // mirror terms from each source
};

// Pixel (x, y)'s reflected term ks Lr at its reflector hit (sf, eye ray r) and its error
// bound E: from a reprojected mirror cell, else from the mirror trees after a BVH walk,
// else traced as the reference traces it, skipping shadow rays within the pixel's
// remaining error (its radiance so far `known`, proven error `err`; error_room), which E
// then reports. Returns true when traced: the term needs no further test. *noted: whether
// a cell was appended to mu.cells (to be taken back when the caller does not use the term).
bool mirror_term(mirror_use& mu, const world& w, int x, int y, const surface& sf, const ray& r, glm::vec3 known,
                 glm::vec3 err, float eps, trace_state& st, glm::vec3& L, glm::vec3& E, bool* noted);

}  // namespace epsray
