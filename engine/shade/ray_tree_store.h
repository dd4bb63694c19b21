// Ray trees of many pixels in three flat arrays, so later stages (interpolants, the
// predicate) can read a pixel's tree without re-tracing it.
#pragma once
#include <cstdint>
#include <vector>

#include "shade/ray_tree.h"

namespace epsray {

struct ray_tree_store {
  std::vector<std::uint32_t> node_begin{0}, light_begin{0};  // one entry per tree, plus one
  std::vector<ray_tree_node> nodes;
  std::vector<std::int32_t> lights;

  size_t size() const { return node_begin.size() - 1; }
  void append(const ray_tree& t);
  void append(const ray_tree_store& other);
  void get(size_t i, ray_tree& out) const;
  size_t bytes() const;
};

}  // namespace epsray
