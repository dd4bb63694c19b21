// Linear RGB radiance, top row first (whitted.md 7).
#pragma once
#include <glm/glm.hpp>
#include <memory>
#include <utility>
#include <vector>

namespace epsray {

// An allocator whose value-less construct leaves the element default-initialized, which for
// glm::vec3 and int means unwritten: a frame's tiles write every pixel, in parallel, so a
// serial zero fill of the whole frame first is time the other threads wait for.
template <class T>
struct no_init_allocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = no_init_allocator<U>;
  };
  no_init_allocator() = default;
  template <class U>
  no_init_allocator(const no_init_allocator<U>&) noexcept {}
  template <class U, class... A>
  void construct(U* p, A&&... a) {
    if constexpr (sizeof...(A) == 0) ::new (static_cast<void*>(p)) U;
    else ::new (static_cast<void*>(p)) U(std::forward<A>(a)...);
  }
};

struct image {
  int width = 0, height = 0;
  std::vector<glm::vec3, no_init_allocator<glm::vec3>> pixels;
  image() = default;
  image(int w, int h) : width(w), height(h), pixels(size_t(w) * size_t(h), glm::vec3(0)) {}
  // For a caller that writes every pixel itself.
  static image unwritten(int w, int h) {
    image im;
    im.width = w, im.height = h;
    im.pixels.resize(size_t(w) * size_t(h));
    return im;
  }
  glm::vec3& at(int x, int y) { return pixels[size_t(y) * size_t(width) + size_t(x)]; }
  const glm::vec3& at(int x, int y) const { return pixels[size_t(y) * size_t(width) + size_t(x)]; }
};

}  // namespace epsray
