#include "interp/sample_cache.h"

namespace epsray {

tree_cache::~tree_cache() {
  map_.for_each([](ray_tree* t) { delete t; });
}

void tree_cache::clear() {
  map_.for_each([](ray_tree* t) { delete t; });
  map_.clear();
  tree_bytes_.store(0, std::memory_order_relaxed);
}

namespace {
std::size_t tree_bytes(const ray_tree& t) {
  return sizeof(ray_tree) + t.nodes.capacity() * sizeof(ray_tree_node) + t.lights.capacity() * 4;
}
}  // namespace

const ray_tree* tree_cache::canonical(const ray_tree& t) {
  const std::uint64_t h = topology_hash(t);
  if (ray_tree* const* found = map_.find(h)) return same_topology(**found, t) ? *found : nullptr;
  auto* copy = new ray_tree(t);
  ray_tree* const* published = map_.insert(h, copy);
  if (published && *published == copy) {
    tree_bytes_.fetch_add(tree_bytes(*copy), std::memory_order_relaxed);
    return copy;
  }
  delete copy;  // another thread stored it first, or no room
  if (published && same_topology(**published, t)) return *published;
  return nullptr;
}

}  // namespace epsray
