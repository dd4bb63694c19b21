#include "interp/cell_screen.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace epsray {

namespace {
// Screen coordinates (pixels from the image centre) of the point at q from the eye, z = q . w > 0.
inline void project(const camera& cam, glm::vec3 q, float z, float& px, float& py) {
  px = glm::dot(q, cam.r) / (z * cam.step), py = glm::dot(q, cam.u) / (z * cam.step);
}
}  // namespace

screen_box cell_screen_box(const camera& cam, const facepair& fp, const lt_node& n) {
  float x0[2] = {-INFINITY, -INFINITY}, x1[2] = {INFINITY, INFINITY};
  float y0[2] = {-INFINITY, -INFINITY}, y1[2] = {INFINITY, INFINITY};
  bool bounded[2] = {true, true};
  screen_box out;
  for (int face = 0; face < 2; ++face) {
    bool behind = false;
    float fx0 = INFINITY, fx1 = -INFINITY, fy0 = INFINITY, fy1 = -INFINITY;
    for (int k = 0; k < 4 && bounded[face]; ++k) {
      float a = (k & 1) ? n.hi[2 * face] : n.lo[2 * face];
      float b = (k & 2) ? n.hi[2 * face + 1] : n.lo[2 * face + 1];
      glm::vec3 p = face == 0 ? front_point(fp, a, b) : back_point(fp, a, b);
      glm::vec3 q = p - cam.origin;
      float z = glm::dot(q, cam.w);
      // An eye ray's line meets a face behind the eye too (a floor's front plane often lies
      // behind the camera): the line through the eye and p is the one through -q. A face
      // crossing the eye's plane has no bounded projection.
      if (k == 0) behind = z < 0;
      if (z == 0 || (z < 0) != behind) {
        bounded[face] = false;
        break;
      }
      if (behind) q = -q, z = -z;
      float px, py;
      project(cam, q, z, px, py);
      fx0 = std::min(fx0, px), fx1 = std::max(fx1, px);
      fy0 = std::min(fy0, py), fy1 = std::max(fy1, py);
    }
    if (bounded[face]) x0[face] = fx0, x1[face] = fx1, y0[face] = fy0, y1[face] = fy1;
  }
  // Every eye ray of the cell crosses both faces, so it lies in each bounded face's
  // projection: one bounded face suffices (near the eye the slab of a floor or a wall
  // holds it, and one face or the other crosses the eye's plane for many cells, which
  // would otherwise look infinitely large and be split to the depth limit).
  if (!bounded[0] && !bounded[1]) {
    out.bounded = false;
    return out;
  }
  out.x0 = std::max(x0[0], x0[1]), out.x1 = std::min(x1[0], x1[1]);
  out.y0 = std::max(y0[0], y0[1]), out.y1 = std::min(y1[0], y1[1]);
  return out;
}

float cell_pixels(const camera& cam, const facepair& fp, const lt_node& n) {
  screen_box b = cell_screen_box(cam, fp, n);
  if (!b.bounded) return std::numeric_limits<float>::infinity();
  return b.empty() ? 0 : (b.x1 - b.x0) * (b.y1 - b.y0);
}

float box_pixels(const camera& cam, const bounds& b) {
  float x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  for (int k = 0; k < 8; ++k) {
    const glm::vec3 p{(k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y, (k & 4) ? b.hi.z : b.lo.z};
    const glm::vec3 q = p - cam.origin;
    const float z = glm::dot(q, cam.w);
    if (!(z > 0)) return std::numeric_limits<float>::infinity();
    float px, py;
    project(cam, q, z, px, py);
    x0 = std::min(x0, px), x1 = std::max(x1, px), y0 = std::min(y0, py), y1 = std::max(y1, py);
  }
  // Pixel centres lie within half the image of its centre; a pixel beyond the box's edge
  // may still hold a ray that meets it.
  const float hx = 0.5f * float(cam.width), hy = 0.5f * float(cam.height);
  const float w = std::min(x1 + 1, hx) - std::max(x0 - 1, -hx), h = std::min(y1 + 1, hy) - std::max(y0 - 1, -hy);
  return w > 0 && h > 0 ? w * h : 0;
}

pixel_rect raster_rect(const camera& cam, const screen_box& b) {
  pixel_rect r;
  if (!b.bounded) return pixel_rect{0, 0, cam.width, cam.height};
  if (b.empty()) return r;
  const float cx = 0.5f * float(cam.width - 1), cy = 0.5f * float(cam.height - 1);
  // Column x has its centre at x - cx; row y at cy - y.
  auto clampi = [](float v, int hi) { return int(std::clamp(v, 0.0f, float(hi))); };
  r.x0 = clampi(std::floor(b.x0 + cx) - 1, cam.width);
  r.x1 = clampi(std::ceil(b.x1 + cx) + 2, cam.width);
  r.y0 = clampi(std::floor(cy - b.y1) - 1, cam.height);
  r.y1 = clampi(std::ceil(cy - b.y0) + 2, cam.height);
  return r;
}

}  // namespace epsray
