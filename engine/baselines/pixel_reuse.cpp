#include "baselines/pixel_reuse.h"

#include <cmath>
#include <cstring>
#include <limits>

namespace epsray {

void reuse_pixels::resize(int w, int h) {
  width = w, height = h;
  const size_t n = size_t(w) * size_t(h);
  point.resize(n), rad.resize(n), age.resize(n);  // shade_rows_reuse writes every pixel
}

void splat_points(const reuse_pixels& last, const camera& cam, int max_age, std::size_t i0, std::size_t i1,
                  std::atomic<std::uint64_t>* nearest) {
  const float cx = 0.5f * float(cam.width - 1), cy = 0.5f * float(cam.height - 1);
  for (std::size_t i = i0; i < i1; ++i) {
    if (last.age[i] == reuse_pixels::no_point || int(last.age[i]) >= max_age) continue;
    const glm::vec3 v = last.point[i] - cam.origin;
    const float z = glm::dot(v, cam.w);
    if (!(z > 0)) continue;
    const float px = glm::dot(v, cam.r) / (z * cam.step) + cx, py = cy - glm::dot(v, cam.u) / (z * cam.step);
    const long x = std::lround(px), y = std::lround(py);
    if (x < 0 || y < 0 || x >= cam.width || y >= cam.height) continue;
    std::uint32_t zbits;
    std::memcpy(&zbits, &z, 4);  // positive floats order as their bits
    const std::uint64_t key = std::uint64_t(zbits) << 32 | std::uint64_t(i);
    std::atomic<std::uint64_t>& slot = nearest[size_t(y) * size_t(cam.width) + size_t(x)];
    std::uint64_t cur = slot.load(std::memory_order_relaxed);
    while (key < cur && !slot.compare_exchange_weak(cur, key, std::memory_order_relaxed)) {
    }
  }
}

std::uint64_t shade_rows_reuse(const world& w, const camera& cam, const reuse_pixels& last,
                               const std::atomic<std::uint64_t>* nearest, int y0, int y1, image& out,
                               reuse_pixels& next, trace_state& st) {
  std::uint64_t reused = 0;
  for (int y = y0; y < y1; ++y) {
    for (int x = 0; x < cam.width; ++x) {
      const size_t p = size_t(y) * size_t(cam.width) + size_t(x);
      const std::uint64_t key = nearest ? nearest[p].load(std::memory_order_relaxed) : ~std::uint64_t(0);
      if (key != ~std::uint64_t(0)) {
        const size_t i = size_t(key & 0xffffffffu);
        out.at(x, y) = next.rad[p] = last.rad[i];
        next.point[p] = last.point[i], next.age[p] = std::uint16_t(last.age[i] + 1);
        ++reused;
        continue;
      }
      ray r = eye_ray(w, cam, eye_direction(cam, float(x), float(y)));
      ++st.counts.eye;
      hit h;
      if (closest_hit(w, r, std::numeric_limits<float>::infinity(), h)) {
        out.at(x, y) = next.rad[p] = shade_hit(w, r, h, 1, st);
        next.point[p] = r.o + h.t * r.d, next.age[p] = 0;
      } else {
        out.at(x, y) = next.rad[p] = w.background;
        next.age[p] = reuse_pixels::no_point;
      }
    }
  }
  return reused;
}

}  // namespace epsray
