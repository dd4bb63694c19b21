#include "reproject/reproject.h"

#include <oneapi/tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

#include "predicate/shaft_shape.h"

namespace epsray {

cell_trust trust_from(const world& w, const cell_ref& c, glm::vec3 eye) {
  cell_trust out;
  if (c.ip->reason != cell_reason::valid || c.ip->hit_box.empty()) return out;
  // The hit points must lie ahead of the eye along the cell's direction of travel: a line
  // through the eye meets the object where its cell says, but that may be behind the eye
  // (an object the camera has passed), where the pixel's ray never goes.
  const facepair& fp = c.lt->fp;
  const bool ahead = fp.back > fp.front ? eye[fp.axis] < c.ip->hit_box.lo[fp.axis]
                                        : eye[fp.axis] > c.ip->hit_box.hi[fp.axis];
  if (!ahead) return out;
  if (!same_first_hit(w.shapes[size_t(c.prim)], fp, eye)) return out;
  // A pixel's point, computed in floats from its own eye ray, may lie some ulps outside the
  // box the predicate proved for the cell's lines.
  const bounds from{eye, eye}, to = with_rounding_margin(c.ip->hit_box, eye);
  const shaft s = make_shaft(from, to);
  const bool crowded = for_each_shape_in_shaft(w, s, from, to, [&](int id) {
    if (id == c.prim || std::find(out.candidates, out.candidates + out.count, id) != out.candidates + out.count)
      return false;
    if (out.count == cell_trust::max_candidates) return true;
    out.candidates[out.count++] = id;
    return false;
  });
  out.ok = !crowded;
  return out;
}

namespace {
// The line of the eye ray with direction d, in the cell's facepair coordinates.
bool line_in_cell(const camera& cam, const cell_ref& c, glm::vec3 d, float x4[4]) {
  if (facepair_of(d) != c.lt->fp.index) return false;  // the line, run the other way
  line_coords(c.lt->fp, cam.origin, d, x4);
  return holds(*c.node, x4);
}
}  // namespace

bool eye_line_in_cell(const camera& cam, const cell_ref& c, int x, int y, float x4[4]) {
  return line_in_cell(cam, c, eye_direction(cam, float(x), float(y)), x4);
}

void splat_rows(const camera& cam, const std::vector<cell_ref>& cells, const std::vector<cell_trust>& trusted,
                const std::vector<pixel_rect>& rects, int y0, int y1, std::int32_t* owner) {
  std::fill(owner + size_t(y0) * size_t(cam.width), owner + size_t(y1) * size_t(cam.width), -1);
  for (size_t i = 0; i < cells.size(); ++i) {
    if (!trusted[i].ok) continue;
    const pixel_rect& r = rects[i];
    const int ya = std::max(r.y0, y0), yb = std::min(r.y1, y1);
    for (int y = ya; y < yb; ++y) {
      std::int32_t* row = owner + size_t(y) * size_t(cam.width);
      for (int x = r.x0; x < r.x1; ++x) {
        float x4[4];
        if (row[x] < 0 && eye_line_in_cell(cam, cells[i], x, y, x4)) row[x] = std::int32_t(i);
      }
    }
  }
}

bool fill_pixel(const world& w, const camera& cam, const cell_ref& c, const cell_trust& trust, int x, int y,
                float eps, trace_state& st, glm::vec3& L) {
  float x4[4];
  const glm::vec3 d = eye_direction(cam, float(x), float(y));
  if (!line_in_cell(cam, c, d, x4)) return false;
  // Textures are looked up, and deferred rays leave, at the pixel's own hit: the trusted
  // cell's object is the first hit along the eye ray, so the object alone gives the point
  // closest_hit would.
  const ray r = make_ray(cam.origin, d);
  float t = 0;
  if ((trust.count || c.ip->textured() || c.ip->deferred || c.ip->deferred_rays) &&
      !hit_shape(w.shapes[size_t(c.prim)], w.polys, r, std::numeric_limits<float>::infinity(), t))
    return false;
  // A candidate met before (or, within rounding, at) the point hides it or ties with it:
  // the interpolate path's visibility ray decides.
  for (int i = 0; i < trust.count; ++i) {
    float tc;
    if (hit_shape(w.shapes[size_t(trust.candidates[i])], w.polys, r, t * (1 + 1e-5f), tc)) return false;
  }
  return interpolate_line(w, c.prim, *c.node, *c.ip, x4, eps, r, t, st, L);
}

void settle_cells(std::vector<cell_ref>& cells) {
  auto key = [](const cell_ref& c) {
    const lt_node& n = *c.node;
    return std::make_tuple(c.prim, c.lt->fp.index, n.lo[0], n.lo[1], n.lo[2], n.lo[3], n.hi[0], n.hi[1], n.hi[2],
                           n.hi[3]);
  };
  // The keys are unique per node, so the order (and the image) is the same however the sort
  // is split among threads.
  tbb::parallel_sort(cells.begin(), cells.end(), [&](const cell_ref& a, const cell_ref& b) { return key(a) < key(b); });
  cells.erase(std::unique(cells.begin(), cells.end(), [](const cell_ref& a, const cell_ref& b) { return a.node == b.node; }),
              cells.end());
}

}  // namespace epsray
