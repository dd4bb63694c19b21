// Reprojection and span filling (section 6). The cells that gave pixels their radiance in
// the last frame are looked at from the new eye: a pixel whose eye ray lies in one of them,
// when the cell is trusted from that eye, takes the cell's interpolant with no visibility
// ray and no lookup. Runs of pixels owned by one cell along a scan line are the paper's
// spans; each pixel of a span evaluates the cell's quadrilinear interpolant at its own
// line, so span-filled pixels carry the same proven bound as interpolated ones (no
// screen-space interpolation error to fold in).
//
// Where the paper rasterizes cell faces with conflict detection, ownership here is decided
// exactly, per pixel: the pixel's line must lie inside the cell's four ranges (and, for a
// box face's cell that reaches past the face, meet the face: cell_trust::face_check).
// Cells keep a deterministic order, and the first containing trusted cell owns the pixel. (`--reproject
// osmesa` draws the same rule instead: face_raster.h.)
#pragma once
#include <algorithm>
#include <cstdint>
#include <vector>

#include "accel/world.h"
#include "interp/cell_screen.h"
#include "interp/interp_shade.h"
#include "predicate/shaft_shape.h"

namespace epsray {

// How far cell c is trusted from an eye: `ok` when its interpolant is valid, the points
// where its lines meet the object lie ahead of the eye along the cell's direction, the eye
// ray's first hit on the object is the one its lines hold, and at most max_candidates
// other primitives meet the shaft from the eye to those points. Those candidates may hide
// some of its points: each pixel tests its own eye ray against them (fill_pixel), which
// the shaft makes exact, since no other primitive can meet the ray before the object.
struct cell_trust {
  static constexpr int max_candidates = 7;
  bool ok = false;
  // A box face's cell (world::face_prims) whose lines may meet its plane off the face: it
  // owns only pixels whose lines meet the face's rectangle (face_at on the facepair's
  // axis, [face_lo, face_hi] along its u and v), and each pixel's eye ray must meet the
  // box by that face (fill_pixel), which rounding at the rectangle's edges needs.
  bool face_check = false;
  float face_at = 0, face_lo[2] = {0, 0}, face_hi[2] = {0, 0};
  std::uint8_t count = 0;
  std::int32_t candidates[max_candidates] = {};
};
cell_trust trust_from(const world& w, const cell_ref& c, glm::vec3 eye);

// Sets out.ok and lists in out.candidates the primitives, but those `ignore(id)` names,
// that meet the shaft from `from` to `to`; out.ok is false when more than max_candidates do.
template <class Ignore>
void list_candidates(const world& w, const bounds& from, const bounds& to, Ignore&& ignore, cell_trust& out) {
  const shaft s = make_shaft(from, to);
  const bool crowded = for_each_shape_in_shaft(w, s, from, to, [&](int id) {
    if (ignore(id) || std::find(out.candidates, out.candidates + out.count, id) != out.candidates + out.count)
      return false;
    if (out.count == cell_trust::max_candidates) return true;
    out.candidates[out.count++] = id;
    return false;
  });
  out.ok = !crowded;
}

// The line of pixel (x, y) in the cell's facepair coordinates, as the interpolate path
// computes it; true when the pixel's ray runs in the facepair's direction and its line
// lies inside the cell.
bool eye_line_in_cell(const camera& cam, const cell_ref& c, int x, int y, float x4[4]);
// The same, and for a cell that needs a face check, the line meets the face's rectangle:
// the pixels the cell owns when no earlier cell does (splat_rows).
bool eye_line_owned(const camera& cam, const cell_ref& c, const cell_trust& trust, int x, int y, float x4[4]);

// Owner of each pixel of rows [y0, y1): the index of the first trusted cell (in list order)
// holding the pixel's line, or -1. `owner` is the whole image's buffer, row-major. With
// first > 0 only cells[first, end) are splatted, into the pixels still unowned (-1).
void splat_rows(const camera& cam, const std::vector<cell_ref>& cells, const std::vector<cell_trust>& trusted,
                const std::vector<pixel_rect>& rects, int y0, int y1, std::int32_t* owner, std::size_t first = 0);

// Span fill of pixel (x, y) from its owner: false when a candidate occluder may hide the
// pixel's point or the bound does not meet epsilon for its line (the pixel then takes the
// interpolate path).
bool fill_pixel(const world& w, const camera& cam, const cell_ref& c, const cell_trust& trust, int x, int y,
                float eps, trace_state& st, glm::vec3& L, mirror_use* mu = nullptr);

// Keeps each cell's first occurrence, in order. A frame's tiles list the cells their pixels
// used in raster order, so their lists, deduplicated each and then together in tile order,
// give the cells in the raster order of their first use: the next frame's list, the same
// for any tiling and schedule. (Sorting by the cells' ranges instead cost 3% of a walk.)
void keep_first_uses(std::vector<cell_ref>& cells);

// Appends c to a list of cells used in raster order unless it is the last one there (runs of
// a cell's pixels note it once); says whether it appended.
inline bool note_cell(std::vector<cell_ref>& cells, const cell_ref& c) {
  if (!cells.empty() && cells.back().node == c.node) return false;
  cells.push_back(c);
  return true;
}

}  // namespace epsray
