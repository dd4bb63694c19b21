#include "accel/light_cache.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "accel/world.h"
#include "predicate/shaft_shape.h"

namespace epsray {

struct light_cache::node {
  std::atomic<node*> kids{nullptr};                 // 8, octant k: bit a set = upper half on axis a
  std::atomic<const std::int32_t*> list{nullptr};  // count, then the primitives; or crowded
};

namespace {

// A node whose shaft holds more than max_list primitives and that may not be split: its
// rays walk the BVH.
const std::int32_t crowded[1] = {-1};

bool inside(vec3 p, vec3 lo, vec3 hi) {
  return p.x >= lo.x && p.y >= lo.y && p.z >= lo.z && p.x <= hi.x && p.y <= hi.y && p.z <= hi.z;
}

bool finite(const bounds& b) {
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(b.lo[a]) || !std::isfinite(b.hi[a]) || !std::isfinite(b.hi[a] - b.lo[a])) return false;
  return !b.empty();
}

void release(light_cache::node& n) {
  if (light_cache::node* k = n.kids.load(std::memory_order_relaxed)) {
    for (int i = 0; i < 8; ++i) release(k[i]);
    delete[] k;
  }
  const std::int32_t* l = n.list.load(std::memory_order_relaxed);
  if (l && l != crowded) delete[] l;
}

}  // namespace

light_cache::light_cache(const world& w, size_t max_nodes) : w_(w), max_nodes_(max_nodes) {
  bounds box = w.box;
  // A shadow ray leaves its surface point by delta (whitted.md 4): every origin lies within
  // delta of the primitives' box.
  box.lo -= vec3(4 * w.delta), box.hi += vec3(4 * w.delta);
  if (!finite(box) || w.light_pos.empty()) return;  // no lists: every ray walks the BVH
  root_box_ = box;
  lights_ = w.light_pos.size();
  roots_ = std::make_unique<node[]>(lights_);
}

light_cache::~light_cache() {
  for (size_t j = 0; j < lights_; ++j) release(roots_[j]);
}

void light_cache::next_frame(bool used, std::uint64_t asked, std::uint64_t unbuilt, std::uint64_t answered) {
  if (!used) {
    if (wait_ > 0) --wait_;
    trial_ = true;
  } else {
    const std::uint64_t judged = asked - std::min(asked, unbuilt);
    if (judged >= 1000 && 4 * answered < 3 * judged) {
      wait_ = rest_, rest_ = std::min(2 * rest_, 64), trial_ = true;
    } else if (judged >= 1000) {
      rest_ = 8, trial_ = false;
    }  // else too few to judge: a trial again
  }
  builds_left_.store(trial_ ? trial_builds : std::numeric_limits<std::int64_t>::max(), std::memory_order_relaxed);
}

size_t light_cache::bytes() const {
  return (lights_ + nodes()) * sizeof(node) + list_ints_.load(std::memory_order_relaxed) * sizeof(std::int32_t);
}

bool light_cache::listed(size_t j, vec3 p, light_hint* hint, const std::int32_t*& out) const {
  if (!inside(p, root_box_.lo, root_box_.hi)) return false;  // NaN too
  bounds box = root_box_;
  node* n = &roots_[j];
  int depth = 0;
  for (;;) {
    if (node* k = n->kids.load(std::memory_order_acquire)) {
      const vec3 c = 0.5f * (box.lo + box.hi);
      int o = 0;
      for (int a = 0; a < 3; ++a) {
        if (p[a] >= c[a]) o |= 1 << a, box.lo[a] = c[a];
        else box.hi[a] = c[a];
      }
      n = &k[o], ++depth;
      continue;
    }
    const std::int32_t* l = n->list.load(std::memory_order_acquire);
    if (!l) {
      // A trial's builds spent: read before the write, so that rays past it share no line.
      if (builds_left_.load(std::memory_order_relaxed) <= 0 || builds_left_.fetch_sub(1, std::memory_order_relaxed) <= 0)
        return false;
      if (!(l = build(j, *n, box, depth))) continue;  // split: descend into the kids
    }
    out = l == crowded ? nullptr : l;
    if (hint) {  // a crowded leaf too: no descent next time
      const int s = hint->next;
      hint->list[s] = out, hint->lo[s] = box.lo, hint->hi[s] = box.hi, hint->next = s ^ 1;
    }
    return true;
  }
}

// The node's list when its shaft holds few primitives; else its kids (returns null) or,
// past the depth or the node budget, crowded. Both ends take a margin of ~100 ulps: a ray's
// origin is computed in floats from its own hit (the cells' shadow lists do the same).
const std::int32_t* light_cache::build(size_t j, node& n, const bounds& box, int depth) const {
  const bounds a = with_rounding_margin(box);
  const bounds b = with_rounding_margin(bounds{w_.light_pos[j], w_.light_pos[j]});
  const shaft s = make_shaft(a, b);
  std::int32_t found[dense_list];
  int count = 0;
  // Boxes first: a shaft that meets many boxes is dense whatever the shapes' own tests say,
  // and those tests (a polygon of 144 vertices in double) cost far more than the boxes'.
  int boxes = 0;
  const bool crowd = for_each_in_shaft(w_.tree, w_.slot_bounds, w_.slot_prim, s, [&](int) { return ++boxes > 2 * dense_list; });
  const bool dense = crowd || for_each_shape_in_shaft(w_, s, a, b, [&](int id) {
    if (std::find(found, found + count, id) != found + count) return false;  // a split primitive's other slot
    if (count == dense_list) return true;
    found[count++] = id;
    return false;
  });
  const std::int32_t* expected = nullptr;
  if (!dense && count <= max_list) {
    std::int32_t* l = new std::int32_t[size_t(count) + 1];
    l[0] = count;
    std::copy(found, found + count, l + 1);
    if (!n.list.compare_exchange_strong(expected, l, std::memory_order_acq_rel, std::memory_order_acquire)) {
      delete[] l;
      return expected;
    }
    list_ints_.fetch_add(size_t(count) + 1, std::memory_order_relaxed);
    return l;
  }
  // A shaft through a mesh meets many of its triangles however thin it gets: past the first
  // levels such a node is left to the BVH instead of splitting down to the last level.
  const bool split = depth < max_depth && (!dense || depth < dense_depth);
  if (split && nodes_.fetch_add(8, std::memory_order_relaxed) + 8 <= max_nodes_) {
    node* k = new node[8];
    node* none = nullptr;
    if (!n.kids.compare_exchange_strong(none, k, std::memory_order_acq_rel, std::memory_order_acquire)) {
      delete[] k;
      nodes_.fetch_sub(8, std::memory_order_relaxed);
    }
    return nullptr;
  }
  if (split) nodes_.fetch_sub(8, std::memory_order_relaxed);
  if (n.kids.load(std::memory_order_acquire)) return nullptr;  // another thread split it
  if (!n.list.compare_exchange_strong(expected, crowded, std::memory_order_acq_rel, std::memory_order_acquire))
    return expected;
  return crowded;
}

}  // namespace epsray
