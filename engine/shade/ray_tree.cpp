#include "shade/ray_tree.h"

#include "shade/whitted.h"

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

namespace {

// Subtrees from node i of a and node j of b, compared structurally (pre-order indices move
// when an earlier subtree differs in size).
bool same_subtree(const ray_tree& a, int i, const ray_tree& b, int j, std::size_t nl) {
  if (i < 0 || j < 0) return i == j;
  const ray_tree_node& x = a.nodes[size_t(i)];
  const ray_tree_node& y = b.nodes[size_t(j)];
  if (x.prim != y.prim || x.entering != y.entering || x.tir != y.tir) return false;
  if (x.prim >= 0)
    for (std::size_t k = 0; k < nl; ++k)
      if (a.lights[x.lights + k] != b.lights[y.lights + k]) return false;
  return same_subtree(a, x.reflect, b, y.reflect, nl) && same_subtree(a, x.refract, b, y.refract, nl);
}

}  // namespace

bool same_topology_deferring(const ray_tree& a, const ray_tree& b, std::size_t nl, bool defer,
                             std::uint32_t* lights, std::uint32_t* rays) {
  if (a.nodes.empty() || b.nodes.empty()) return false;
  const ray_tree_node& x = a.nodes[0];
  const ray_tree_node& y = b.nodes[0];
  if (x.prim != y.prim || x.entering != y.entering || (x.reflect < 0) != (y.reflect < 0) ||
      (x.refract < 0) != (y.refract < 0))
    return false;
  std::uint32_t dl = 0, dr = 0;
  if (x.prim >= 0) {
    for (std::size_t k = 0; k < nl; ++k) {
      if (a.lights[x.lights + k] == b.lights[y.lights + k]) continue;
      if (k >= std::size_t(max_deferred_lights)) return false;
      dl |= 1u << k;
    }
  }
  if (!same_subtree(a, x.reflect, b, y.reflect, nl)) dr |= 1;
  if (x.tir != y.tir || !same_subtree(a, x.refract, b, y.refract, nl)) dr |= 2;
  if ((dl | dr) && !defer) return false;
  *lights |= dl, *rays |= dr;
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
