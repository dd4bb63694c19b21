#include "scene/camera.h"

#include <cmath>

namespace epsray {

camera make_camera(const camera_view& v, int width, int height) {
  camera c;
  c.origin = v.from;
  c.w = glm::normalize(v.at - v.from);
  c.r = glm::normalize(glm::cross(c.w, v.up));
  c.u = glm::cross(c.r, c.w);
  // Computed in double: the step enters every eye ray.
  c.step = float(2.0 * std::tan(double(v.angle) * 3.14159265358979323846 / 360.0) / double(height - 1));
  c.width = width;
  c.height = height;
  return c;
}

namespace {
bool finite(vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
}  // namespace

const char* view_problem(const camera_view& v) {
  // Finite coordinates can still overflow: at - from, its length, or the cross product with
  // a huge up would give NaN axes and so NaN in every eye ray.
  vec3 w = v.at - v.from;
  if (!finite(w) || !std::isfinite(glm::length(w))) return "from and at are too far apart";
  if (glm::length(w) == 0) return "from and at coincide";
  if (!(glm::length(glm::cross(glm::normalize(w), v.up)) >= 1e-6f))
    return "up is zero or parallel to the view direction";
  camera c = make_camera(v, 2, 2);
  if (!finite(c.r) || !finite(c.u)) return "up is too large";
  return nullptr;
}

}  // namespace epsray
