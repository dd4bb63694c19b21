// The pinhole camera of whitted.md section 1: one ray through each pixel centre.
#pragma once
#include "scene/scene.h"

namespace epsray {

struct camera {
  vec3 origin{0};
  vec3 w{0, 0, -1}, r{1, 0, 0}, u{0, 1, 0};  // forward, right, up (orthonormal)
  float step = 0;                             // s: world units per pixel at unit distance
  int width = 0, height = 0;
};

camera make_camera(const camera_view& v, int width, int height);

// Why `v` gives no usable camera (null when it does): the scene and path parsers' check.
const char* view_problem(const camera_view& v);

// The same eye rays: whether a frame's camera moved since the last one.
inline bool same_camera(const camera& a, const camera& b) {
  return a.origin == b.origin && a.w == b.w && a.r == b.r && a.u == b.u && a.step == b.step && a.width == b.width &&
         a.height == b.height;
}

// Unit direction of the eye ray through pixel (x, y), y = 0 the top row.
inline vec3 eye_direction(const camera& c, float x, float y) {
  float dx = (x - 0.5f * float(c.width - 1)) * c.step;
  float dy = (0.5f * float(c.height - 1) - y) * c.step;
  return glm::normalize(c.w + dx * c.r + dy * c.u);
}

}  // namespace epsray
