#include "accel/light_cache.h"

#include <algorithm>
#include <cmath>

namespace epsray {

namespace {

bool finite(const bounds& b) {
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(b.lo[a]) || !std::isfinite(b.hi[a]) || !std::isfinite(b.hi[a] - b.lo[a])) return false;
  return !b.empty();
}

// The least |x| over [lo, hi].
double least_abs(double lo, double hi) { return lo > 0 ? lo : (hi < 0 ? -hi : 0); }

// The rectangle [u0, u1] x [v0, v1] of face (a, s) (s = 0: directions with d[a] > 0) that
// the directions from the light l to the points of box b may fall in. A point q of the box
// seen in that face has z = +-(q[a] - l[a]) >= |x|, |y| (x, y: its other two coordinates
// from the light), so z is at least z0 below, and u = x / z, v = y / z lie within the
// quotients of the box's ranges at z0 and at its far side. The pyramid is taken wider by
// 1e-5 and the range by 1e-5 (50 times the rounding of a lookup's quotient), so a direction
// the lookup rounds onto this face or across a cell's side still finds the box.
struct face_range {
  double u0, u1, v0, v1;
};
bool range_on_face(const bounds& b, glm::dvec3 l, int a, int s, face_range& out) {
  const int a1 = a == 2 ? 0 : a + 1, a2 = a == 0 ? 2 : a - 1;
  double zlo = double(b.lo[a]) - l[a], zhi = double(b.hi[a]) - l[a];
  if (s) std::swap(zlo, zhi), zlo = -zlo, zhi = -zhi;
  if (!(zhi > 0)) return false;
  const double xlo = double(b.lo[a1]) - l[a1], xhi = double(b.hi[a1]) - l[a1];
  const double ylo = double(b.lo[a2]) - l[a2], yhi = double(b.hi[a2]) - l[a2];
  const double widen = 1 - 1e-5;
  const double z0 = std::max({zlo, widen * least_abs(xlo, xhi), widen * least_abs(ylo, yhi)});
  if (z0 > zhi) return false;
  double u0 = -1, u1 = 1, v0 = -1, v1 = 1;
  if (z0 > 0) {
    u0 = std::min(xlo / z0, xlo / zhi), u1 = std::max(xhi / z0, xhi / zhi);
    v0 = std::min(ylo / z0, ylo / zhi), v1 = std::max(yhi / z0, yhi / zhi);
  }
  const double m = 1e-5;
  out = {std::max(u0 - m, -1.0), std::min(u1 + m, 1.0), std::max(v0 - m, -1.0), std::min(v1 + m, 1.0)};
  return out.u0 <= out.u1 && out.v0 <= out.v1;
}

// The cell of a grid's row or column that u falls in, as face_grid::cell finds it, taken a
// thousandth of a cell towards `side` (-1 or 1) for the lookup's rounding of (u - lo) s.
int cell_of(double u, float lo, float s, int res, int side) {
  const double x = (u - double(lo)) * double(s) + 1e-3 * side;
  return x >= 1 ? int(std::min(x, double(res - 1))) : 0;
}

// The distance from l to box b, rounded down.
float box_distance(const bounds& b, glm::dvec3 l) { return float(box_gap(b, l, l) * (1 - 1e-6)); }

// Entries (8 bytes each) one buffer and all of them may hold: a light whose buffer would
// hold more than its share at the coarsest grid walks the BVH.
constexpr size_t light_entries = size_t(1) << 22, all_entries = size_t(1) << 23;
constexpr int min_res = 8;

}  // namespace

light_cache::light_cache(const world& w) : w_(w) {
  if (!finite(w.box) || w.light_pos.empty()) return;  // no lists: every ray walks the BVH
  // About four cells a face for each primitive: where a shadow ray crosses a mesh, its cell
  // then lists a few of the mesh's triangles.
  const double n = double(std::max<size_t>(w.scene_prims, 1));
  const int res = std::clamp(int(std::ceil(2 * std::sqrt(n))), 16, 256);
  bufs_.resize(w.light_pos.size());
  size_t left = all_entries;
  for (size_t j = 0; j < bufs_.size(); ++j) {
    build(bufs_[j], w.light_pos[j], res, std::min(left, light_entries));
    left -= bufs_[j].list.size();
  }
}

void light_cache::build(buffer& b, vec3 light, int res, size_t max_entries) const {
  const glm::dvec3 l(light);
  const size_t n = w_.slot_prim.size();  // the BVH's: face rectangles are in none
  std::vector<bounds> box(n);
  std::vector<entry> order(n);
  bounds all;
  for (size_t i = 0; i < n; ++i) {
    box[i] = with_rounding_margin(w_.slot_bounds[i], light);
    all.grow(box[i]);
    order[i] = {std::int32_t(i), box_distance(box[i], l)};
  }
  // Filled nearest first, so each cell's list is sorted by distance from the light.
  std::stable_sort(order.begin(), order.end(), [](const entry& x, const entry& y) { return x.near < y.near; });
  for (; res >= min_res; res /= 2) {
    size_t cells = 0;
    for (int f = 0; f < 6; ++f) {
      face_grid& g = b.faces[f];
      g = face_grid{};
      g.first = cells;
      face_range r;
      if (!range_on_face(all, l, f / 2, f % 2, r)) {  // no primitive in this face: one empty cell,
        cells += 1;                                    // which su = 0 sends every lookup to
        continue;
      }
      g.u0 = float(r.u0), g.v0 = float(r.v0);
      g.su = float(res / std::max(r.u1 - double(g.u0), 1e-30)), g.sv = float(res / std::max(r.v1 - double(g.v0), 1e-30));
      cells += size_t(res) * size_t(res);
    }
    struct rect {
      size_t first;
      int u0, u1, v0, v1;
    };
    std::vector<rect> rects;
    std::vector<std::uint32_t> rect_of(n + 1, 0);  // primitive order[k]'s rects: [rect_of[k], rect_of[k + 1])
    std::vector<std::uint32_t> count(cells, 0);
    size_t total = 0;
    for (size_t k = 0; k < n && total <= max_entries; ++k) {
      const bounds& bx = box[size_t(order[k].slot)];
      for (int f = 0; f < 6; ++f) {
        const face_grid& g = b.faces[f];
        face_range r;
        if (g.su == 0 || !range_on_face(bx, l, f / 2, f % 2, r)) continue;
        const rect c{g.first, cell_of(r.u0, g.u0, g.su, res, -1), cell_of(r.u1, g.u0, g.su, res, 1),
                     cell_of(r.v0, g.v0, g.sv, res, -1), cell_of(r.v1, g.v0, g.sv, res, 1)};
        rects.push_back(c);
        for (int v = c.v0; v <= c.v1; ++v)
          for (int u = c.u0; u <= c.u1; ++u) ++count[c.first + size_t(v) * size_t(res) + size_t(u)];
        total += size_t(c.u1 - c.u0 + 1) * size_t(c.v1 - c.v0 + 1);
      }
      rect_of[k + 1] = std::uint32_t(rects.size());
    }
    if (total > max_entries) continue;
    // A buffer whose cells are mostly crowded (a far light over nested shells of spheres)
    // would send most rays on to the BVH after a lookup: none is kept.
    size_t used = 0, crowded = 0;
    for (const std::uint32_t c : count) used += c > 0, crowded += c > std::uint32_t(max_list);
    if (2 * crowded > used) return;
    b.start.assign(count.size() + 1, 0);
    for (size_t c = 0; c < count.size(); ++c) b.start[c + 1] = b.start[c] + count[c];
    b.list.resize(total);
    std::vector<std::uint32_t> fill(b.start.begin(), b.start.end() - 1);
    for (size_t k = 0; k < n; ++k)
      for (std::uint32_t i = rect_of[k]; i < rect_of[k + 1]; ++i) {
        const rect& c = rects[i];
        for (int v = c.v0; v <= c.v1; ++v)
          for (int u = c.u0; u <= c.u1; ++u) b.list[fill[c.first + size_t(v) * size_t(res) + size_t(u)]++] = order[k];
      }
    b.light = light, b.res = res;
    return;
  }
}

void light_cache::next_frame(bool used, std::uint64_t asked, std::uint64_t answered) {
  if (!used) {
    if (wait_ > 0) --wait_;
  } else if (asked >= 1000 && 4 * answered < 3 * asked) {
    wait_ = rest_, rest_ = std::min(2 * rest_, 64);
  } else if (asked >= 1000) {
    rest_ = 8;
  }
}

size_t light_cache::bytes() const {
  size_t s = 0;
  for (const buffer& b : bufs_) s += b.start.size() * sizeof(std::uint32_t) + b.list.size() * sizeof(entry);
  return s;
}

}  // namespace epsray
