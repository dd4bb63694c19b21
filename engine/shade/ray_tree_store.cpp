#include "shade/ray_tree_store.h"

namespace epsray {

void ray_tree_store::append(const ray_tree& t) {
  nodes.insert(nodes.end(), t.nodes.begin(), t.nodes.end());
  lights.insert(lights.end(), t.lights.begin(), t.lights.end());
  node_begin.push_back(std::uint32_t(nodes.size()));
  light_begin.push_back(std::uint32_t(lights.size()));
}

void ray_tree_store::append(const ray_tree_store& o) {
  std::uint32_t n0 = std::uint32_t(nodes.size()), l0 = std::uint32_t(lights.size());
  nodes.insert(nodes.end(), o.nodes.begin(), o.nodes.end());
  lights.insert(lights.end(), o.lights.begin(), o.lights.end());
  for (size_t i = 1; i < o.node_begin.size(); ++i) {
    node_begin.push_back(n0 + o.node_begin[i]);
    light_begin.push_back(l0 + o.light_begin[i]);
  }
}

void ray_tree_store::get(size_t i, ray_tree& out) const {
  out.nodes.assign(nodes.begin() + node_begin[i], nodes.begin() + node_begin[i + 1]);
  out.lights.assign(lights.begin() + light_begin[i], lights.begin() + light_begin[i + 1]);
}

size_t ray_tree_store::bytes() const {
  return nodes.capacity() * sizeof(ray_tree_node) + lights.capacity() * 4 +
         (node_begin.capacity() + light_begin.capacity()) * 4;
}

}  // namespace epsray
