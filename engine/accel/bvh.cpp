#include "accel/bvh.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace epsray {

namespace {

double box_area(const bounds& b) {
  if (b.empty()) return 0;
  glm::dvec3 e = glm::dvec3(b.hi) - glm::dvec3(b.lo);
  return 2 * (e.x * e.y + e.y * e.z + e.z * e.x);
}

struct builder {
  const std::vector<bounds>& prims;
  const bvh_params& params;
  std::vector<vec3> centres;
  std::vector<int> idx;
  std::vector<bvh2_node> nodes;

  builder(const std::vector<bounds>& p, const bvh_params& pr) : prims(p), params(pr) {
    centres.resize(p.size());
    for (size_t i = 0; i < p.size(); ++i) centres[i] = p[i].centre();
    idx.resize(p.size());
    std::iota(idx.begin(), idx.end(), 0);
  }

  void make_leaf(bvh2_node& n, int begin, int end) {
    n.index = std::uint32_t(begin);
    n.count = std::uint16_t(end - begin);
  }

  // Builds the subtree of idx[begin, end) into nodes[at]; depth guards the fixed stack.
  void build(std::uint32_t at, int begin, int end, int depth) {
    bounds box, cbox;
    for (int i = begin; i < end; ++i) box.grow(prims[size_t(idx[size_t(i)])]), cbox.grow(centres[size_t(idx[size_t(i)])]);
    nodes[at].lo = box.lo;
    nodes[at].hi = box.hi;
    nodes[at].axis = 0;
    int n = end - begin;
    if (n <= 1) return make_leaf(nodes[at], begin, end);

    vec3 ext = cbox.extent();
    int axis = ext.x >= ext.y ? (ext.x >= ext.z ? 0 : 2) : (ext.y >= ext.z ? 1 : 2);
    int mid = no_split;
    // Past depth 40 split at the median so the traversal stack (64) can never overflow.
    if (ext[axis] > 0 && depth < 40) {
      mid = sah_split(begin, end, axis, cbox, box, n);
      if (mid == leaf_cheaper) return make_leaf(nodes[at], begin, end);
    }
    if (mid <= begin || mid >= end) {
      if (n <= params.max_leaf) return make_leaf(nodes[at], begin, end);
      // Coincident centres or no useful split: halve by index so leaves stay small.
      mid = begin + n / 2;
      std::nth_element(idx.begin() + begin, idx.begin() + mid, idx.begin() + end,
                       [&](int a, int b) { return centres[size_t(a)][axis] < centres[size_t(b)][axis] ||
                                                  (centres[size_t(a)][axis] == centres[size_t(b)][axis] && a < b); });
    }
    nodes[at].axis = std::uint8_t(axis);
    nodes[at].count = 0;
    std::uint32_t left = std::uint32_t(nodes.size());
    nodes.emplace_back();
    build(left, begin, mid, depth + 1);
    std::uint32_t right = std::uint32_t(nodes.size());
    nodes.emplace_back();
    nodes[at].index = right;
    build(right, mid, end, depth + 1);
  }

  static constexpr int no_split = -1;       // no SAH split found: the caller halves
  static constexpr int leaf_cheaper = -2;   // SAH prefers a leaf (only for n <= max_leaf)

  // Binned SAH. Returns the partition point, no_split or leaf_cheaper.
  int sah_split(int begin, int end, int axis, const bounds& cbox, const bounds& box, int n) {
    const int nb = params.bins;
    const size_t nbs = size_t(nb);
    std::vector<bounds> bin_box(nbs);
    std::vector<int> bin_count(nbs, 0);
    // In double: a centroid spread of a denormal would make the float scale infinite.
    double lo = cbox.lo[axis], scale = double(nb) / (double(cbox.hi[axis]) - lo);
    if (!std::isfinite(scale)) return no_split;
    auto bin_of = [&](int prim) {
      double f = (double(centres[size_t(prim)][axis]) - lo) * scale;
      return f >= 0 ? std::min(nb - 1, int(std::min(f, double(nb)))) : 0;
    };
    for (int i = begin; i < end; ++i) {
      int b = bin_of(idx[size_t(i)]);
      bin_box[size_t(b)].grow(prims[size_t(idx[size_t(i)])]);
      ++bin_count[size_t(b)];
    }
    // Areas in double: huge scenes overflow float products of area and count.
    std::vector<double> left_area(nbs), right_area(nbs);
    std::vector<int> left_n(nbs), right_n(nbs);
    bounds acc;
    int cnt = 0;
    for (int i = 0; i < nb; ++i) {
      acc.grow(bin_box[size_t(i)]), cnt += bin_count[size_t(i)];
      left_area[size_t(i)] = box_area(acc), left_n[size_t(i)] = cnt;
    }
    acc = bounds{}, cnt = 0;
    for (int i = nb - 1; i >= 0; --i) {
      acc.grow(bin_box[size_t(i)]), cnt += bin_count[size_t(i)];
      right_area[size_t(i)] = box_area(acc), right_n[size_t(i)] = cnt;
    }
    double best = INFINITY;
    int best_i = -1;
    for (int i = 0; i + 1 < nb; ++i) {
      if (left_n[size_t(i)] == 0 || right_n[size_t(i + 1)] == 0) continue;
      double c = left_area[size_t(i)] * double(left_n[size_t(i)]) + right_area[size_t(i + 1)] * double(right_n[size_t(i + 1)]);
      if (c < best) best = c, best_i = i;
    }
    if (best_i < 0) return no_split;
    double area = box_area(box);
    double split_cost = params.traversal_cost + (area > 0 && std::isfinite(area) ? best / area : 0);
    if (n <= params.max_leaf && split_cost >= double(n)) return leaf_cheaper;
    auto it = std::partition(idx.begin() + begin, idx.begin() + end, [&](int p) { return bin_of(p) <= best_i; });
    return int(it - idx.begin());
  }
};

}  // namespace

// Collapses the binary tree: each 4-wide node takes the children of up to three binary
// nodes, always opening the interior child with the largest surface area.
struct collapser {
  const std::vector<bvh2_node>& in;
  std::vector<bvh4_node> out;

  static float area(const bvh2_node& n) { return bounds{n.lo, n.hi}.area(); }

  std::uint32_t collapse(std::uint32_t root) {
    std::uint32_t at = std::uint32_t(out.size());
    out.emplace_back();
    std::uint32_t kids[4] = {root + 1, in[root].index, 0, 0};
    int nk = 2;
    while (nk < 4) {
      int best = -1;
      float best_area = -1;
      for (int k = 0; k < nk; ++k)
        if (in[kids[k]].count == 0 && area(in[kids[k]]) > best_area) best = k, best_area = area(in[kids[k]]);
      if (best < 0) break;
      std::uint32_t n = kids[best];
      kids[best] = n + 1;
      kids[nk++] = in[n].index;
    }
    bvh4_node node{};
    node.size = std::uint32_t(nk);
    for (int k = 0; k < 4; ++k) {
      for (int a = 0; a < 3; ++a) node.lo[a][k] = INFINITY, node.hi[a][k] = -INFINITY;
    }
    for (int k = 0; k < nk; ++k) {
      const bvh2_node& c = in[kids[k]];
      for (int a = 0; a < 3; ++a) node.lo[a][k] = c.lo[a], node.hi[a][k] = c.hi[a];
      node.count[k] = c.count;
      node.child[k] = c.count ? c.index : 0;
    }
    for (int k = 0; k < nk; ++k)
      if (in[kids[k]].count == 0) node.child[k] = collapse(kids[k]);
    out[at] = node;
    return at;
  }
};

bvh build_bvh(const std::vector<bounds>& prims, const bvh_params& params) {
  bvh out;
  if (prims.empty()) return out;
  builder b(prims, params);
  b.nodes.reserve(2 * prims.size());
  b.nodes.emplace_back();
  b.build(0, 0, int(prims.size()), 0);
  out.nodes2 = std::move(b.nodes);
  out.order = std::move(b.idx);
  out.box = bounds{out.nodes2[0].lo, out.nodes2[0].hi};
  if (out.nodes2[0].count) {
    // A single leaf: wrap it in one 4-wide node so traversal has one shape.
    bvh4_node node{};
    for (int k = 0; k < 4; ++k)
      for (int a = 0; a < 3; ++a) node.lo[a][k] = INFINITY, node.hi[a][k] = -INFINITY;
    for (int a = 0; a < 3; ++a) node.lo[a][0] = out.box.lo[a], node.hi[a][0] = out.box.hi[a];
    node.child[0] = out.nodes2[0].index;
    node.count[0] = out.nodes2[0].count;
    node.size = 1;
    out.nodes.push_back(node);
    return out;
  }
  collapser c{out.nodes2, {}};
  c.out.reserve(out.nodes2.size() / 2 + 1);
  c.collapse(0);
  out.nodes = std::move(c.out);
  return out;
}

}  // namespace epsray
