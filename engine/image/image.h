// Linear RGB radiance, top row first (whitted.md 7).
#pragma once
#include <cstdint>
#include <cstring>
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

// Every channel of rows [y0, y1) is finite: no NaN, no infinity (an exponent of all ones).
// Branch-free, so the compiler vectorizes it.
inline bool all_finite(const image& im, int y0, int y1) {
  const float* v = reinterpret_cast<const float*>(im.pixels.data()) + size_t(y0) * size_t(im.width) * 3;
  const size_t n = size_t(y1 - y0) * size_t(im.width) * 3;
  std::uint32_t bad = 0;
  for (size_t i = 0; i < n; ++i) {
    std::uint32_t b;
    std::memcpy(&b, v + i, sizeof b);
    bad |= std::uint32_t((b & 0x7f800000u) == 0x7f800000u);
  }
  return bad == 0;
}

}  // namespace epsray
