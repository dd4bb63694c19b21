// Linear RGB radiance, top row first (whitted.md 7).
#pragma once
#include <glm/glm.hpp>
#include <vector>

namespace epsray {

struct image {
  int width = 0, height = 0;
  std::vector<glm::vec3> pixels;
  image() = default;
  image(int w, int h) : width(w), height(h), pixels(size_t(w) * size_t(h), glm::vec3(0)) {}
  glm::vec3& at(int x, int y) { return pixels[size_t(y) * size_t(width) + size_t(x)]; }
  const glm::vec3& at(int x, int y) const { return pixels[size_t(y) * size_t(width) + size_t(x)]; }
};

}  // namespace epsray
