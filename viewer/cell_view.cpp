#include "viewer/cell_view.h"

#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "viewer/frame_bytes.h"

namespace epsray {

namespace {

// A colour per cell from its ranges' bits: stable from frame to frame and run to run.
glm::vec3 cell_colour(const lt_node& n) {
  std::uint64_t h = 0x9e3779b97f4a7c15ull;
  for (int i = 0; i < 4; ++i) {
    std::uint32_t a, b;
    std::memcpy(&a, &n.lo[i], 4), std::memcpy(&b, &n.hi[i], 4);
    h = (h ^ a) * 0xff51afd7ed558ccdull, h = (h ^ b) * 0xc4ceb9fe1a85ec53ull, h ^= h >> 29;
  }
  return {0.25f + 0.75f * float(h & 255) / 255, 0.25f + 0.75f * float(h >> 8 & 255) / 255,
          0.25f + 0.75f * float(h >> 16 & 255) / 255};
}

// The leaf of `prim`'s linetree (or its face's, for a box) holding the eye ray (looked up, never built), or null when
// the ray's first hit is another object or lies outside the tree.
const lt_node* leaf_of(const world& w, const camera& cam, linetree_set& trees, int prim, int x, int y) {
  const ray r = eye_ray(w, cam, eye_direction(cam, float(x), float(y)));
  hit h;
  if (!closest_hit(w, r, std::numeric_limits<float>::infinity(), h) || h.prim != prim) return nullptr;
  const int face = face_prim_of(w, prim, r);  // a box's pixels use their face's tree
  const linetree& lt = trees.tree_for(face >= 0 ? face : prim, r.d);
  float x4[4];
  line_coords(lt.fp, r.o, r.d, x4);
  if (!holds(lt.root, x4)) return nullptr;
  const lt_node* n = &lt.root;
  while (lt_node* kids = n->kids.load(std::memory_order_acquire)) n = child_at(*n, kids, x4);
  return n;
}

}  // namespace

int paint_cells(workers& pool, const world& w, const camera& cam, linetree_set& trees, float fx, float fy,
                const image& img, std::vector<const lt_node*>& leaves, std::vector<unsigned char>& rgb) {
  const int width = cam.width, height = cam.height;
  int picked = -1;
  if (fx >= 0 && fy >= 0) {
    const int px = std::clamp(int(fx * float(width)), 0, width - 1);
    const int py = std::clamp(int(fy * float(height)), 0, height - 1);
    hit h;
    const ray r = eye_ray(w, cam, eye_direction(cam, float(px), float(py)));
    if (closest_hit(w, r, std::numeric_limits<float>::infinity(), h)) picked = h.prim;
  }
  leaves.assign(size_t(width) * size_t(height), nullptr);
  if (picked >= 0) {
    pool.run([&] {
      tbb::parallel_for(0, height, [&](int y) {
        for (int x = 0; x < width; ++x) leaves[size_t(y) * size_t(width) + size_t(x)] = leaf_of(w, cam, trees, picked, x, y);
      });
    });
  }
  image shown(width, height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const size_t i = size_t(y) * size_t(width) + size_t(x);
      const lt_node* n = leaves[i];
      if (!n) {
        shown.pixels[i] = 0.25f * img.pixels[i];
        continue;
      }
      const bool edge = (x > 0 && leaves[i - 1] != n) || (y > 0 && leaves[i - size_t(width)] != n);
      shown.pixels[i] = edge ? glm::vec3(0.02f) : 0.45f * img.pixels[i] + 0.55f * cell_colour(*n);
    }
  }
  encode_srgb(shown, rgb);
  return picked;
}

}  // namespace epsray
