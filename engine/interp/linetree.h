// Linetrees (section 4.2): one lazily built 4D tree per object and facepair. Several
// threads look up, build and subdivide the same tree at once without a lock: a thread
// that finds a missing interpolant or missing children builds them privately and
// publishes them with one compare-and-swap; a loser frees its copy and uses the winner's.
// What gets built is a pure function of the cell (and the camera's cost model), so who
// wins changes nothing observable.
#pragma once
#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cstdint>
#include <memory>
#include <vector>

#include "accel/light_cache.h"
#include "interp/interpolant.h"
#include "interp/line_space.h"
#include "interp/node_pool.h"
#include "interp/object_gate.h"
#include "interp/sample_cache.h"

namespace epsray {

struct lt_node {
  float lo[4], hi[4];
  std::uint8_t level[4] = {0, 0, 0, 0};  // halvings of each axis from the root
  std::uint8_t depth = 0;        // the most halvings of any axis
  std::uint8_t parent_axes = 0;  // the axes the parent halved to make this node and its siblings
  std::atomic<lt_node*> kids{nullptr};  // 4 or 16 children, created together
  std::atomic<interpolant*> interp{nullptr};
  // The last frame a pixel's lookup ended here (linetree_set::frame()): what a memory
  // budget evicts last. Every writer of a frame writes the same value.
  mutable std::atomic<std::uint32_t> used{0};
  ~lt_node();
  // Children come 4 or 16 at a time from the node pool (node_pool.h).
  static void* operator new[](std::size_t bytes) { return node_pool::allocate(bytes); }
  static void operator delete[](void* p, std::size_t bytes) noexcept { node_pool::deallocate(p, bytes); }
};

// Marks n used in `frame` (a read first: most lookups find it marked already).
inline void mark_used(const lt_node& n, std::uint32_t frame) {
  if (n.used.load(std::memory_order_relaxed) != frame) n.used.store(frame, std::memory_order_relaxed);
}

inline int child_count(std::uint8_t axes) { return 1 << std::popcount(unsigned(axes)); }

struct linetree {
  facepair fp;
  lt_node root;
};

// Index among children that halve `axes` of the child of `n` holding the point (a, b, c, d):
// one interval test per halved axis.
inline int child_index(const lt_node& n, std::uint8_t axes, const float x[4]) {
  int k = 0, bit = 0;
  for (int i = 0; i < 4; ++i) {
    if (!(axes >> i & 1)) continue;
    if (x[i] >= 0.5f * (n.lo[i] + n.hi[i])) k |= 1 << bit;
    ++bit;
  }
  return k;
}

// Does the cell hold the line x? Closed ranges: a line on a face shared by two cells is in
// both (descents pick one by child_index).
inline bool holds(const lt_node& n, const float x[4]) {
  for (int i = 0; i < 4; ++i)
    if (!(x[i] >= n.lo[i] && x[i] <= n.hi[i])) return false;
  return true;
}

// Where the line x lies in the cell, each coordinate as a fraction of its range (the
// quadrilinear interpolant's t), clamped to [0, 1] against rounding at the cell's faces.
inline void cell_fractions(const lt_node& n, const float x[4], float t[4]) {
  for (int i = 0; i < 4; ++i) t[i] = std::clamp((x[i] - n.lo[i]) / (n.hi[i] - n.lo[i]), 0.0f, 1.0f);
}

// The child of n holding x, given n's published children.
inline lt_node* child_at(const lt_node& n, lt_node* kids, const float x[4]) {
  return &kids[child_index(n, kids[0].parent_axes, x)];
}

// Creates the children of n halving `axes` unless another thread already made children
// (a pure function of the cell, so the same ones); returns the published children.
// The winner adds the children's bytes to *bytes when given (linetree_set::node_bytes).
lt_node* subdivide(lt_node& n, std::uint8_t axes = split_all, std::atomic<std::size_t>* bytes = nullptr);
// Publishes `made` as n's interpolant unless another thread did first; returns the winner,
// whose bytes (a valid interpolant's; failures share records) go to *bytes when given.
// *won (when given) says whether `made` was the one published: exactly one call per node
// wins, so counting wins counts the cells built, whichever thread built them.
const interpolant* publish(lt_node& n, std::unique_ptr<interpolant> made, std::atomic<std::size_t>* bytes = nullptr,
                           bool* won = nullptr);
// The same in place of `old`, a shared failure record (so nothing is freed under a reader):
// a refused cell built again under another cost model.
const interpolant* republish(lt_node& n, const interpolant* old, std::unique_ptr<interpolant> made,
                             std::atomic<std::size_t>* bytes = nullptr, bool* won = nullptr);

// The linetrees of every primitive, six facepairs each, created on first use.
class linetree_set {
 public:
  // memory_budget (bytes, 0: none) also sizes the unique-ray hash to a share of it; so does
  // the frame's pixel count when given (0: the largest table).
  explicit linetree_set(const std::vector<bounds>& prim_bounds, size_t memory_budget = 0, size_t pixels = 0);
  ~linetree_set();
  linetree& get(int prim, int facepair_index);
  // The facepair of prim holding a line of direction d (facepair_for).
  int facepair_index(int prim, glm::vec3 d) const { return facepair_for(flat_[size_t(prim)], d); }
  // The tree holding the line of direction d.
  linetree& tree_for(int prim, glm::vec3 d) { return get(prim, facepair_index(prim, d)); }
  // Nodes, interpolants and the caches: kept by counting what is published and freed, so
  // the stats of every frame need not walk the trees.
  size_t bytes() const;
  size_t measured_bytes() const;  // the same, by walking every tree (tests)
  // Where subdivide and publish count the bytes they add to this set's trees.
  std::atomic<size_t>* node_bytes() { return &node_bytes_; }
  size_t memory_budget() const { return budget_; }

  // Frames number lookups (lt_node::used); a frame starts with next_frame().
  std::uint32_t frame() const { return frame_; }
  void next_frame() { ++frame_; }
  // Between frames: forgets the shared samples and ray trees when their tables are crowded.
  // When over the memory budget: forgets the shared samples and ray trees,
  // then frees the subtrees no lookup reached this frame, least recently used first (ties
  // in a fixed order), until under budget. Cells used this frame are kept, so the budget
  // is exceeded only by one frame's working set. Not concurrent. Returns the bytes after
  // (0 without a budget: nothing is measured).
  size_t evict();
  // Line samples and ray trees shared by every cell of every tree of this set.
  sample_cache& samples() { return samples_; }
  // Which objects are traced with no linetree for now, decided from each frame's counts
  // (object_gate.h); kept with the trees, whose frames it follows.
  object_gate gate;
  // The light cache of the world these trees serve (accel/light_cache.h), made by the first
  // frame that asks: shadows do not depend on the camera, so it lives as long as the trees.
  // Its bytes are not in bytes(): the memory budget evicts cells, never its lists. Not concurrent.
  light_cache* lights(const world& w);
  size_t light_bytes() const;

 private:
  std::unique_ptr<light_cache> lights_;
  std::vector<bounds> bounds_;  // a copy: small, and no lifetime tie to the world
  std::vector<std::int8_t> flat_;  // flat_axis of each
  size_t budget_ = 0;
  std::uint32_t frame_ = 1;
  std::unique_ptr<std::array<std::atomic<linetree*>, 6>[]> trees_;
  size_t count_;
  sample_cache samples_;
  std::atomic<size_t> node_bytes_{0};  // linetrees, nodes and interpolants
};

}  // namespace epsray
