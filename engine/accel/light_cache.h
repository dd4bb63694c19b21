// Shadow rays answered from short lists of what may block them. Shadows do not depend on
// the camera: whether a point sees a light is a function of the point alone, so one
// structure serves every frame of a walk, every depth of the ray tree and every path of a
// pixel. Per light, an octree over the scene's box; a leaf holds the primitives that may
// meet some segment from the leaf to the light (the shaft of the two, shaft_shape.h), and
// a shadow ray whose origin lies in the leaf tests those alone. Every primitive the ray
// can meet is listed, so the answer (lit, or blocked) is the BVH walk's: images do not
// change, only the cost of a shadow ray. Nodes are built lazily, by the first ray that
// reaches them, and published lock-free; a node's list depends on its box alone, so what
// is built does not depend on which thread built it.
#pragma once
#include <atomic>
#include <cmath>
#include <cstdint>
#include <memory>

#include "accel/world.h"

namespace epsray {

// A thread's last two leaves for one light, with their boxes: neighbouring shadow rays mostly
// start in one of them (two: a pixel's eye hit and its reflection's hit take turns), and a
// published leaf never changes.
struct light_hint {
  const std::int32_t* list[2] = {nullptr, nullptr};  // the leaf's list; null: it has none
  vec3 lo[2] = {vec3(INFINITY), vec3(INFINITY)}, hi[2] = {vec3(-INFINITY), vec3(-INFINITY)};  // empty: unset
  int next = 0;  // the slot a new leaf replaces
};

class light_cache {
 public:
  // A leaf lists at most this many primitives; a node whose shaft holds more is split.
  static constexpr int max_list = 8;
  // A node whose shaft holds dense_list primitives or more (or meets twice as many boxes)
  // is split only above dense_depth.
  static constexpr int dense_list = 32, dense_depth = 3;
  // Splits stop this deep (a 64th of the box along each axis: 12 levels measured the same),
  // and when max_nodes are made: such a node's rays walk the BVH.
  static constexpr int max_depth = 6;
  static constexpr int not_listed = -2;  // a leaf whose shaft is crowded: the BVH answers
  static constexpr int not_built = -3;   // no leaf: outside the box, or a trial frame's builds spent
  // Nodes a trial frame may build (next_frame).
  static constexpr std::int64_t trial_builds = 512;

  explicit light_cache(const world& w, size_t max_nodes = size_t(1) << 18);
  ~light_cache();
  light_cache(const light_cache&) = delete;
  light_cache& operator=(const light_cache&) = delete;

  // The shadow ray r (from its origin towards light j, at distance dist): -1 when no
  // primitive blocks it, some primitive that does, or not_listed / not_built when its
  // origin lies in no listed leaf: the caller walks the BVH.
  // `self` (-1: none) is a primitive the caller knows the ray cannot meet: the flat one it leaves.
  int blocker(size_t j, const ray& r, float dist, int self, light_hint* hint) const {
    const std::int32_t* l;
    if (!(hint && hinted(*hint, r.o, l)) && !(j < lights_ && listed(j, r.o, hint, l))) return not_built;
    if (!l) return not_listed;
    for (std::int32_t i = 1; i <= l[0]; ++i) {
      const int id = l[i];
      if (id == self) continue;
      // Its box first, as the BVH tests it: a polygon of many vertices is dear to test whole.
      const bounds& b = w_.hit_boxes[size_t(id)];
      float t;
      if (hit_bounds(b.lo, b.hi, r, dist, t) && hit_shape(w_.shapes[size_t(id)], w_.polys, r, dist, t)) return id;
    }
    return -1;
  }

  // Between frames, from the frame's counts (never its clocks): the shadow rays that asked
  // the lists, those that found no leaf built (not_built) and those a list answered. Where
  // a list answered under 3/4 of those that found a leaf (shafts through meshes, crowds of
  // spheres), the rays sent on to the BVH paid a lookup for nothing and the lists that
  // answered were long: the lists rest for 8 frames, then 16, 32, 64 while that lasts. The
  // first frame and each after a rest are trials that build at most trial_builds nodes, so
  // a scene the lists do not suit pays little to find out. `used`: this frame asked them.
  void next_frame(bool used, std::uint64_t asked, std::uint64_t unbuilt, std::uint64_t answered);
  bool in_use() const { return wait_ == 0; }

  size_t nodes() const { return nodes_.load(std::memory_order_relaxed); }
  size_t bytes() const;

  struct node;

 private:
  // p in one of the hint's leaves: its list (null when crowded) in l.
  static bool hinted(const light_hint& h, vec3 p, const std::int32_t*& l) {
    for (int s = 0; s < 2; ++s)
      if (p.x >= h.lo[s].x && p.y >= h.lo[s].y && p.z >= h.lo[s].z && p.x <= h.hi[s].x && p.y <= h.hi[s].y &&
          p.z <= h.hi[s].z)
        return l = h.list[s], true;
    return false;
  }
  // The descent to p's leaf, building what is missing; false when p lies outside the box
  // or a trial frame's builds are spent.
  bool listed(size_t j, vec3 p, light_hint* hint, const std::int32_t*& l) const;
  const std::int32_t* build(size_t j, node& n, const bounds& box, int depth) const;

  const world& w_;
  bounds root_box_;
  std::unique_ptr<node[]> roots_;  // one per light
  size_t lights_ = 0;
  size_t max_nodes_;
  mutable std::atomic<size_t> nodes_{0};
  mutable std::atomic<size_t> list_ints_{0};
  int wait_ = 0, rest_ = 8;
  bool trial_ = true;
  mutable std::atomic<std::int64_t> builds_left_{trial_builds};
};

}  // namespace epsray
