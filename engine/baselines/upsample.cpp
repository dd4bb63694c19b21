#include "baselines/upsample.h"

#include <algorithm>
#include <cmath>

namespace epsray {

camera reduced_camera(const camera& cam, int k) {
  camera low = cam;
  low.width = (cam.width + k - 1) / k, low.height = (cam.height + k - 1) / k;
  low.step = cam.step * float(k);
  return low;
}

void upsample_rows(const image& low, const camera& cam, int k, int y0, int y1, image& out) {
  // Full pixel x looks along the direction of low pixel xl (eye_direction of both cameras).
  const float cx = 0.5f * float(cam.width - 1), lcx = 0.5f * float(low.width - 1);
  const float cy = 0.5f * float(cam.height - 1), lcy = 0.5f * float(low.height - 1);
  auto split = [](float v, int n, int& i0, int& i1, float& t) {
    v = std::clamp(v, 0.0f, float(n - 1));
    i0 = std::min(int(std::floor(v)), n - 1), i1 = std::min(i0 + 1, n - 1), t = v - float(i0);
  };
  for (int y = y0; y < y1; ++y) {
    int ya, yb;
    float ty;
    split((float(y) - cy) / float(k) + lcy, low.height, ya, yb, ty);
    for (int x = 0; x < cam.width; ++x) {
      int xa, xb;
      float tx;
      split((float(x) - cx) / float(k) + lcx, low.width, xa, xb, tx);
      const glm::vec3 top = glm::mix(low.at(xa, ya), low.at(xb, ya), tx);
      const glm::vec3 bottom = glm::mix(low.at(xa, yb), low.at(xb, yb), tx);
      out.at(x, y) = glm::mix(top, bottom, ty);
    }
  }
}

}  // namespace epsray
