#include "shade/ray_tree.h"

namespace epsray {

bool same_topology(const ray_tree& a, const ray_tree& b) {
  // Nodes are laid out in pre-order, so equal topology means equal arrays, field by field.
  if (a.nodes.size() != b.nodes.size() || a.lights != b.lights) return false;
  for (size_t i = 0; i < a.nodes.size(); ++i) {
    const ray_tree_node& x = a.nodes[i];
    const ray_tree_node& y = b.nodes[i];
    if (x.prim != y.prim || x.reflect != y.reflect || x.refract != y.refract || x.lights != y.lights ||
        x.entering != y.entering || x.tir != y.tir)
      return false;
  }
  return true;
}

std::uint64_t topology_hash(const ray_tree& t) {
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a over the fields same_topology compares
  auto mix = [&](std::uint64_t v) { h = (h ^ v) * 1099511628211ull; };
  for (const ray_tree_node& n : t.nodes) {
    mix(std::uint64_t(std::uint32_t(n.prim)));
    mix(std::uint64_t(std::uint16_t(n.reflect)) | (std::uint64_t(std::uint16_t(n.refract)) << 16) |
        (std::uint64_t(n.entering) << 32) | (std::uint64_t(n.tir) << 40));
  }
  for (std::int32_t l : t.lights) mix(std::uint64_t(std::uint32_t(l)));
  return h;
}

}  // namespace epsray
