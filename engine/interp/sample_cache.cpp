#include "interp/sample_cache.h"

namespace epsray {

tree_cache::~tree_cache() {
  map_.for_each([](ray_tree* t) { delete t; });
}

void tree_cache::clear() {
  map_.for_each([](ray_tree* t) { delete t; });
  map_.clear();
}

const ray_tree* tree_cache::canonical(const ray_tree& t) {
  const std::uint64_t h = topology_hash(t);
  if (ray_tree* const* found = map_.find(h)) return same_topology(**found, t) ? *found : nullptr;
  auto* copy = new ray_tree(t);
  ray_tree* const* published = map_.insert(h, copy);
  if (published && *published == copy) return copy;
  delete copy;  // another thread stored it first, or no room
  if (published && same_topology(**published, t)) return *published;
  return nullptr;
}

std::size_t tree_cache::bytes() const {
  std::size_t b = map_.bytes();
  map_.for_each([&](ray_tree* t) {
    b += sizeof(ray_tree) + t->nodes.capacity() * sizeof(ray_tree_node) + t->lights.capacity() * 4;
  });
  return b;
}

}  // namespace epsray
