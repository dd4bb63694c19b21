// The unique-ray hash and the unique-ray-tree cache of section 7: sibling cells share most
// of their extremal lines (16 children of a cell have 81 distinct corners, not 256), so
// each line's sample is traced once and found by its key; and the ray trees of successful
// and failed interpolants are mostly alike, so each distinct tree is stored once.
#pragma once
#include <atomic>
#include <cstdint>
#include <cstring>
#include <glm/glm.hpp>

#include "sched/ray_hash.h"
#include "shade/ray_tree.h"
#include "shade/whitted.h"

namespace epsray {

// A line of one object's facepair, by the exact bits of its intercepts.
struct line_key {
  std::int32_t prim = -1, facepair = -1;
  float x[4] = {0, 0, 0, 0};
  bool operator==(const line_key& o) const {
    return prim == o.prim && facepair == o.facepair && std::memcmp(x, o.x, sizeof x) == 0;
  }
};

struct line_key_hash {
  std::uint64_t operator()(const line_key& k) const {
    std::uint64_t h = 0x9e3779b97f4a7c15ull ^ (std::uint64_t(std::uint32_t(k.prim)) << 3) ^ std::uint64_t(k.facepair);
    for (float f : k.x) {
      std::uint32_t b;
      std::memcpy(&b, &f, 4);
      h = (h ^ b) * 0xff51afd7ed558ccdull;
      h ^= h >> 32;
    }
    return h;
  }
};

// What a line's trace leaves for interpolants: its radiance split as in interpolant,
// and its canonical ray tree (null when the line misses the object).
struct line_sample {
  glm::vec3 rad{0}, tex{0};
  glm::vec2 uv{0};
  // Per light j < 8 where it reaches the hit: its diffuse cosine and specular power, so an
  // interpolant can take a light's or a secondary ray's term out (0 where the light does
  // not reach).
  float ndl[max_deferred_lights] = {}, spec[max_deferred_lights] = {};
  glm::vec3 rays[2] = {glm::vec3{0}, glm::vec3{0}};  // the reflected and transmitted terms
  const ray_tree* tree = nullptr;
  bool hit = false;
};

struct identity_hash {
  std::uint64_t operator()(std::uint64_t h) const { return h; }
};

// Each distinct ray-tree topology stored once; trees are immutable once published.
class tree_cache {
 public:
  explicit tree_cache(std::size_t capacity) : map_(capacity) {}
  ~tree_cache();
  tree_cache(const tree_cache&) = delete;
  tree_cache& operator=(const tree_cache&) = delete;
  // The stored tree with t's topology, storing a copy if new; null if it cannot be stored
  // (a hash shared with another topology, or a full table): the caller keeps its own.
  const ray_tree* canonical(const ray_tree& t);
  // Counted as trees are published, not by walking the table: a frame's statistics read it
  // on the walk's clock, and the walk over every tree took a serial 0.4 ms a frame.
  std::size_t bytes() const { return map_.bytes() + tree_bytes_.load(std::memory_order_relaxed); }
  std::size_t size() const { return map_.size(); }
  std::size_t capacity() const { return map_.capacity(); }
  void clear();  // frees every tree; not concurrent

 private:
  insert_only_map<std::uint64_t, ray_tree*, identity_hash> map_;
  std::atomic<std::size_t> tree_bytes_{0};
};

struct sample_cache {
  insert_only_map<line_key, line_sample, line_key_hash> lines;
  tree_cache trees;
  explicit sample_cache(std::size_t line_capacity = std::size_t(1) << 18, std::size_t tree_capacity = 1 << 16)
      : lines(line_capacity), trees(tree_capacity) {}
  std::size_t bytes() const { return lines.bytes() + trees.bytes(); }
  // Forgets every sample and tree (line samples point at the trees). Not concurrent.
  void clear() { lines.clear(), trees.clear(); }
  // Over three quarters full, a table's probes for new keys run long and new entries start
  // to miss their slots: time to start over (values are pure functions of their keys, so
  // forgetting them costs only sharing, never changes an image).
  bool crowded() const {
    return lines.size() > lines.capacity() / 4 * 3 || trees.size() > trees.capacity() / 4 * 3;
  }
};

}  // namespace epsray
