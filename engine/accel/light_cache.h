// Shadow rays answered from short lists of what may block them. Shadows do not depend on
// the camera: whether a point sees a light is a function of the point alone, so one
// structure serves every frame of a walk, every depth of the ray tree and every path of a
// pixel. Per light, a light buffer (Haines and Greenberg 1986): a cube of directions around
// the light, each face a grid of cells, each cell listing the primitives whose box, seen
// from the light, may cover some direction of the cell. A shadow ray runs along one
// direction from the light, so only its cell's primitives can meet it; the list is sorted
// by the boxes' distance from the light, and the scan stops at the first one farther than
// the ray's origin. Every primitive the ray can meet is listed, so the answer (lit, or
// blocked) is the BVH walk's: images do not change, only the cost of a shadow ray. The
// buffers are built whole when the cache is made and never change, so what a ray reads
// does not depend on threads.
#pragma once
#include <cmath>
#include <cstdint>
#include <vector>

#include "accel/world.h"

namespace epsray {

// The primitive a shadow ray from a hit on `prim` can never meet again, for
// light_cache::blocker's `self` (-1: none or unsure): a flat one (cannot_reenter whichever
// side it is left from), left towards the light's side by delta, which every shadow ray is
// (none is cast towards a light behind the surface).
inline int shadow_self(const world& w, int prim) {
  return cannot_reenter(w.shapes[size_t(prim)].kind, false, w.info[size_t(prim)].patch) ? prim : -1;
}

class light_cache {
 public:
  // A cell listing more than this leaves its rays to the BVH.
  static constexpr int max_list = 48;
  static constexpr int not_listed = -2;  // the ray's cell is crowded, or no buffer: the BVH answers

  explicit light_cache(const world& w);

  // The shadow ray r (from its origin towards light j, at distance dist): -1 when no
  // primitive blocks it, some primitive that does, or not_listed: the caller walks the BVH.
  // `self` (-1: none) is a primitive the caller knows the ray cannot meet: the flat one it leaves.
  int blocker(size_t j, const ray& r, float dist, int self) const {
    if (j >= bufs_.size() || bufs_[j].res == 0) return not_listed;
    const buffer& b = bufs_[j];
    const vec3 d = r.o - b.light;
    const vec3 m = glm::abs(d);
    const int a = m.x >= m.y && m.x >= m.z ? 0 : (m.y >= m.z ? 1 : 2);
    if (!(m[a] > 0)) return not_listed;  // at the light, or NaN
    const int a1 = a == 2 ? 0 : a + 1, a2 = a == 0 ? 2 : a - 1;
    const int f = 2 * a + (d[a] < 0);
    const face_grid& g = b.faces[f];
    const size_t c = g.first + size_t(face_grid::cell(d[a2] / m[a], g.v0, g.sv, b.res)) * size_t(b.res) +
                     size_t(face_grid::cell(d[a1] / m[a], g.u0, g.su, b.res));
    const std::uint32_t first = b.start[c], last = b.start[c + 1];
    if (last - first > std::uint32_t(max_list)) return not_listed;
    // A hit at t < dist lies nearer the light than the origin (dist, less what rounding moves).
    const float reach = dist * 1.0001f;
    for (std::uint32_t i = first; i < last; ++i) {
      const entry& e = b.list[i];
      if (e.near > reach) break;
      const int id = int(w_.slot_prim[size_t(e.slot)]);
      if (id == self) continue;
      // Its box first, as the BVH tests it: a polygon of many vertices is dear to test whole.
      const bounds& bx = w_.slot_bounds[size_t(e.slot)];
      float t;
      if (hit_bounds(bx.lo, bx.hi, r, dist, t) && hit_shape(w_.shapes[size_t(id)], w_.polys, r, dist, t)) return id;
    }
    return -1;
  }

  // Between frames, from the frame's counts (never its clocks): the shadow rays that asked
  // the lists and those a list answered. Where lists answered under 3/4 of them (crowded
  // cells: a light seen through a dense mesh), the rays sent on to the BVH paid a lookup
  // for nothing: the lists rest for 8 frames, then 16, 32, 64 while that lasts.
  // `used`: this frame asked them.
  void next_frame(bool used, std::uint64_t asked, std::uint64_t answered);
  bool in_use() const { return wait_ == 0; }

  // Cells per face side of light j's buffer (0: none), and its cells in all.
  int resolution(size_t j) const { return j < bufs_.size() ? bufs_[j].res : 0; }
  size_t cells(size_t j) const { return j < bufs_.size() && !bufs_[j].start.empty() ? bufs_[j].start.size() - 1 : 0; }
  size_t bytes() const;

 private:
  // A BVH slot (world::slot_prim): a primitive split into pieces is listed by the pieces'
  // boxes, as the BVH's leaves hold them, so a ray is tested against a piece's box first.
  struct entry {
    std::int32_t slot;
    float near;  // the distance from the light to the slot's box, rounded down
  };
  // A face's grid spans only the rectangle of it that the scene's box covers (a far light
  // sees the scene in a small part of one face): the buffer's res x res cells from (u0, v0),
  // su and sv cells per unit; a face the box misses has one empty cell and su = sv = 0. A
  // direction outside it is clamped to the nearest cell: no primitive lies that way, so the
  // ray meets none of what that cell lists.
  struct face_grid {
    size_t first = 0;  // the index of the face's first cell
    float u0 = 0, v0 = 0, su = 0, sv = 0;
    static int cell(float u, float lo, float s, int res) {
      const float x = (u - lo) * s;
      return x >= 1 ? int(std::min(x, float(res - 1))) : 0;  // clamped before the cast; NaN too
    }
  };
  struct buffer {
    vec3 light{0};
    int res = 0;  // 0: no buffer, every ray walks the BVH
    face_grid faces[6];
    // res^2 cells per face the scene covers, 1 per other face, and 1: cell c lists
    // list[start[c], start[c + 1])
    std::vector<std::uint32_t> start;
    std::vector<entry> list;
  };
  void build(buffer& b, vec3 light, int res, size_t max_entries) const;

  const world& w_;
  std::vector<buffer> bufs_;
  int wait_ = 0, rest_ = 8;
};

}  // namespace epsray
