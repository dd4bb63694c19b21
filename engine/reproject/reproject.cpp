#include "reproject/reproject.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "predicate/shaft_shape.h"

namespace epsray {

namespace {
// Do all points of `b` lie strictly inside the face of its box that face rectangle
// `face` extends? Then every line meeting the rectangle's plane there from the outside
// enters the box by that face.
// (k: the face's normal axis.)
bool inside_face(const world& w, int face, int k, const bounds& b) {
  const bounds& f = w.prim_bounds[size_t(w.face_owner[size_t(face)])];
  for (int i = 0; i < 3; ++i)
    if (i != k && !(b.lo[i] > f.lo[i] && b.hi[i] < f.hi[i])) return false;
  return true;
}
}  // namespace

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
  const int self = scene_prim_of(w, c.prim);  // a face rectangle's box
  if (!same_first_hit(w.shapes[size_t(self)], fp, eye)) return out;
  const int k = self != c.prim ? flat_axis(w.prim_bounds[size_t(c.prim)]) : -1;
  if (self != c.prim && !inside_face(w, c.prim, k, with_rounding_margin(c.ip->hit_box, eye))) {
    // Its pixels are those whose lines lie in the cell and meet the face: the face's
    // rectangle is one more clip of the cell's screen region, in the face's own facepair.
    if (fp.axis != k) return out;
    const bounds& f = w.prim_bounds[size_t(self)];
    out.face_check = true;
    out.face_at = w.prim_bounds[size_t(c.prim)].lo[k];
    out.face_lo[0] = f.lo[fp.u], out.face_hi[0] = f.hi[fp.u];
    out.face_lo[1] = f.lo[fp.v], out.face_hi[1] = f.hi[fp.v];
  }
  // A pixel's point, computed in floats from its own eye ray, may lie some ulps outside the
  // box the predicate proved for the cell's lines.
  const bounds from{eye, eye}, to = with_rounding_margin(c.ip->hit_box, eye);
  list_candidates(w, from, to, [&](int id) { return id == self; }, out);
  return out;
}

namespace {
// The line of the eye ray with direction d, in the cell's facepair coordinates.
bool line_in_cell(const camera& cam, const cell_ref& c, glm::vec3 d, float x4[4]) {
  if (facepair_for(c.lt->fp.flat, d) != c.lt->fp.index) return false;  // run the other way, or another facepair's
  line_coords(c.lt->fp, cam.origin, d, x4);
  return holds(*c.node, x4);
}
}  // namespace

bool eye_line_in_cell(const camera& cam, const cell_ref& c, int x, int y, float x4[4]) {
  return line_in_cell(cam, c, eye_direction(cam, float(x), float(y)), x4);
}

bool eye_line_owned(const camera& cam, const cell_ref& c, const cell_trust& trust, int x, int y, float x4[4]) {
  const glm::vec3 d = eye_direction(cam, float(x), float(y));
  if (!line_in_cell(cam, c, d, x4)) return false;
  if (!trust.face_check) return true;
  const glm::dvec2 p = plane_intercept(c.lt->fp, cam.origin, d, trust.face_at);  // on the face's plane
  return p.x >= trust.face_lo[0] && p.x <= trust.face_hi[0] && p.y >= trust.face_lo[1] && p.y <= trust.face_hi[1];
}

namespace {

// The pixels of one scan line whose lines lie in a cell, found per row instead of per pixel.
// Along a row the unnormalized eye direction is linear in x, D(x) = P + x Q, and each test
// of eye_line_in_cell becomes linear once multiplied by the ray's component along the
// facepair's axis (positive in the cell): the facepair's dominance (two tests per other
// axis, and the axis component's sign), for a flat object's other facepairs that the line
// is flatter than flat_slope (two tests), each of the four ranges (two tests each), and
// for a cell that needs a face check the face's two ranges on its plane (two tests each).
// So the pixels in the cell form one run, the intersection of 19 half-lines g . D(x) >= 0
// (a zero g: no test).
struct row_tests {
  static constexpr int count = 19;
  glm::dvec3 g[count];
};

row_tests cell_row_tests(const camera& cam, const cell_ref& c, const cell_trust& trust) {
  const facepair& fp = c.lt->fp;
  const lt_node& n = *c.node;
  const double s = fp.index & 1 ? -1.0 : 1.0;
  glm::dvec3 ea(0), eu(0), ev(0);
  ea[fp.axis] = s, eu[fp.u] = 1, ev[fp.v] = 1;
  row_tests t;
  int k = 0;
  t.g[k++] = ea;                         // the ray runs towards the back plane
  const double slope = fp.flat == fp.axis ? double(flat_slope) : 1.0;
  t.g[k++] = slope * ea - eu, t.g[k++] = slope * ea + eu;  // |D_u| <= slope s D_a
  t.g[k++] = slope * ea - ev, t.g[k++] = slope * ea + ev;
  if (fp.flat >= 0 && fp.flat != fp.axis) {  // s D_a > flat_slope |D_flat|: not the flat facepair's
    glm::dvec3 ef(0);
    ef[fp.flat] = flat_slope;
    t.g[k++] = ea - ef, t.g[k++] = ea + ef;
  } else {
    t.g[k++] = glm::dvec3(0), t.g[k++] = glm::dvec3(0);
  }
  const glm::dvec3 o(cam.origin);
  // Intercept with the plane at axis coordinate F along axis e: o_e + (F - o_a) D_e / D_a,
  // within [lo, hi] when (o_e - lo) s D_a + (F - o_a) s D_e >= 0 and the mirror test.
  auto range = [&](double plane, const glm::dvec3& e, int along, float lo, float hi) {
    const double K = plane - o[fp.axis], oe = o[along];
    t.g[k++] = (oe - double(lo)) * ea + K * s * e;
    t.g[k++] = (double(hi) - oe) * ea - K * s * e;
  };
  range(fp.front, eu, fp.u, n.lo[0], n.hi[0]);
  range(fp.front, ev, fp.v, n.lo[1], n.hi[1]);
  range(fp.back, eu, fp.u, n.lo[2], n.hi[2]);
  range(fp.back, ev, fp.v, n.lo[3], n.hi[3]);
  if (trust.face_check) {  // and the line meets the box's face (cell_trust::face_check)
    range(trust.face_at, eu, fp.u, trust.face_lo[0], trust.face_hi[0]);
    range(trust.face_at, ev, fp.v, trust.face_lo[1], trust.face_hi[1]);
  } else {
    for (int i = 0; i < 4; ++i) t.g[k++] = glm::dvec3(0);
  }
  return t;
}

// The run [xa, xb] of row y within [x0, x1) in the cell, empty when xa > xb. The solved
// ends are checked, and moved by a pixel or two, with the per-pixel test itself, since
// its float rounding decides membership there; inside the run no pixel is tested here
// (fill_pixel tests its own line again, so a pixel rounding leaves out only takes the
// interpolate path).
void row_run(const camera& cam, const cell_ref& c, const cell_trust& trust, const row_tests& t, int y, int x0, int x1,
             int& xa, int& xb) {
  const double cx = 0.5 * double(cam.width - 1), cy = 0.5 * double(cam.height - 1), step = cam.step;
  const glm::dvec3 Q = step * glm::dvec3(cam.r);
  const glm::dvec3 P = glm::dvec3(cam.w) - cx * Q + (cy - double(y)) * step * glm::dvec3(cam.u);
  double lo = x0, hi = x1 - 1;
  for (int k = 0; k < row_tests::count && lo <= hi; ++k) {
    const double a = glm::dot(t.g[k], P), b = glm::dot(t.g[k], Q);
    if (b > 0) lo = std::max(lo, -a / b);
    else if (b < 0) hi = std::min(hi, -a / b);
    else if (a < 0) hi = lo - 1;
  }
  // Nothing solved (rounding may still leave a pixel or two at the edge: none is worth
  // finding, since such a pixel takes the interpolate path anyway). Checked before the
  // conversion to int: a nearly flat test moves an end far outside int's range.
  if (!(lo <= hi)) {
    xa = 1, xb = 0;
    return;
  }
  xa = int(std::ceil(lo)), xb = int(std::floor(hi));  // both in [x0, x1 - 1] now
  float x4[4];
  auto in = [&](int x) { return x >= x0 && x < x1 && eye_line_owned(cam, c, trust, x, y, x4); };
  while (xa <= xb && !in(xa)) ++xa;
  while (xb >= xa && !in(xb)) --xb;
  if (xa > xb) return;
  for (int i = 0; i < 2 && in(xa - 1); ++i) --xa;
  for (int i = 0; i < 2 && in(xb + 1); ++i) ++xb;
}

}  // namespace

void splat_rows(const camera& cam, const std::vector<cell_ref>& cells, const std::vector<cell_trust>& trusted,
                const std::vector<pixel_rect>& rects, int y0, int y1, std::int32_t* owner, std::size_t first) {
  if (first == 0) std::fill(owner + size_t(y0) * size_t(cam.width), owner + size_t(y1) * size_t(cam.width), -1);
  for (size_t i = first; i < cells.size(); ++i) {
    if (!trusted[i].ok) continue;
    const pixel_rect& r = rects[i];
    const int ya = std::max(r.y0, y0), yb = std::min(r.y1, y1);
    if (ya >= yb || r.x0 >= r.x1) continue;
    const row_tests t = cell_row_tests(cam, cells[i], trusted[i]);
    for (int y = ya; y < yb; ++y) {
      int xa, xb;
      row_run(cam, cells[i], trusted[i], t, y, r.x0, r.x1, xa, xb);
      std::int32_t* row = owner + size_t(y) * size_t(cam.width);
      for (int x = xa; x <= xb; ++x)
        if (row[x] < 0) row[x] = std::int32_t(i);
    }
  }
}

namespace {

// The hit of a line the trusted cell holds with the cell's own object. The error predicate
// proved that every line of a valid cell meets a flat object inside its outline, with a
// margin (hit_family's inside tests), so only the plane is intersected: the full test's own
// first step, without the polygon's edge walk or the disk's rim test.
bool hit_proven(const shape& s, const polygon_data& pd, const ray& r, float& t) {
  constexpr float far = std::numeric_limits<float>::infinity();
  switch (s.kind) {
    case shape_kind::polygon: return hit_polygon_plane(s.poly, r, far, t);
    case shape_kind::disk: return hit_disk_plane(s.disk, r, far, t);
    default: return hit_shape(s, pd, r, far, t);
  }
}

}  // namespace

bool fill_pixel(const world& w, const camera& cam, const cell_ref& c, const cell_trust& trust, int x, int y,
                float eps, trace_state& st, glm::vec3& L, mirror_use* mu) {
  float x4[4];
  const glm::vec3 d = eye_direction(cam, float(x), float(y));
  if (!line_in_cell(cam, c, d, x4)) return false;
  // Textures are looked up, and deferred rays leave, at the pixel's own hit: the trusted
  // cell's object is the first hit along the eye ray, so the object alone gives the point
  // closest_hit would.
  const ray r = eye_ray(w, cam, d);
  float t = 0;
  // A face rectangle's pixel meets its box, by that face (the reference's normal there).
  const int self = scene_prim_of(w, c.prim);
  if ((trust.count || trust.face_check || c.ip->textured() || c.ip->deferred || c.ip->deferred_rays) &&
      !hit_proven(w.shapes[size_t(self)], w.polys, r, t))
    return false;
  if (trust.face_check && face_prim_of(w, self, r) != c.prim) return false;
  // A candidate met before (or, within rounding, at) the point hides it or ties with it:
  // the interpolate path's visibility ray decides.
  for (int i = 0; i < trust.count; ++i) {
    float tc;
    if (hit_shape(w.shapes[size_t(trust.candidates[i])], w.polys, r, t * (1 + 1e-5f), tc)) return false;
  }
  return interpolate_line(w, c.prim, *c.node, *c.ip, x4, eps, r, t, st, L, mu, x, y);
}

void keep_first_uses(std::vector<cell_ref>& cells) {
  // Open addressing on the node pointers, at most half full: no allocation per entry and
  // no read of the (mostly cold) nodes themselves.
  size_t size = 16;
  while (size < 2 * cells.size()) size *= 2;
  std::vector<const lt_node*> seen(size, nullptr);
  size_t kept = 0;
  for (const cell_ref& c : cells) {
    size_t h = (reinterpret_cast<std::uintptr_t>(c.node) >> 4) * 0x9E3779B97F4A7C15ull;
    for (h >>= 20;; ++h) {
      const lt_node*& slot = seen[h & (size - 1)];
      if (slot == c.node) break;  // listed already
      if (!slot) {
        slot = c.node;
        cells[kept++] = c;
        break;
      }
    }
  }
  cells.resize(kept);
}

}  // namespace epsray
