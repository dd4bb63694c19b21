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

}  // namespace epsray
