#include "viewer/camera_control.h"

#include <algorithm>
#include <cmath>

namespace epsray {

void fly(camera_view& v, const move_keys& k, float speed, float seconds) {
  const vec3 f = glm::normalize(v.at - v.from);
  const vec3 up = glm::normalize(v.up);
  const vec3 right = glm::normalize(glm::cross(f, up));
  vec3 d(0);
  d += f * float(int(k.forward) - int(k.back));
  d += right * float(int(k.right) - int(k.left));
  d += up * float(int(k.up) - int(k.down));
  if (d == vec3(0)) return;
  d *= speed * seconds;
  v.from += d, v.at += d;
}

void look(camera_view& v, float dx, float dy) {
  if (dx == 0 && dy == 0) return;
  const float dist = glm::length(v.at - v.from);
  const vec3 f = (v.at - v.from) / dist;
  const vec3 up = glm::normalize(v.up);
  // Yaw about the up vector, pitch as an elevation above the plane normal to it.
  const float limit = glm::radians(89.0f);
  const float elevation = std::clamp(std::asin(std::clamp(glm::dot(f, up), -1.0f, 1.0f)) -
                                         glm::radians(dy * look_degrees_per_pixel),
                                     -limit, limit);
  const vec3 flat = glm::normalize(f - glm::dot(f, up) * up);
  const vec3 side = glm::cross(flat, up);  // right of the view
  const float yaw = glm::radians(dx * look_degrees_per_pixel);
  const vec3 heading = std::cos(yaw) * flat + std::sin(yaw) * side;
  v.at = v.from + dist * (std::cos(elevation) * heading + std::sin(elevation) * up);
}

float default_speed(const bounds& box) {
  const float diagonal = glm::length(box.hi - box.lo);
  return std::isfinite(diagonal) && diagonal > 0 ? diagonal / 5 : 1.0f;
}

bool same_view(const camera_view& a, const camera_view& b) {
  return a.from == b.from && a.at == b.at && a.up == b.up && a.angle == b.angle;
}

}  // namespace epsray
