#include "viewer/screenshot.h"

#include <GL/gl.h>

#include <cmath>

#include "image/image_io.h"

namespace epsray {

float linear_from_srgb_byte(unsigned char b) {
  const double s = b / 255.0;
  return float(s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4));
}

image image_from_srgb_bytes(const std::vector<unsigned char>& rgb, int width, int height) {
  image img(width, height);
  for (size_t i = 0; i < img.pixels.size(); ++i)
    img.pixels[i] = {linear_from_srgb_byte(rgb[3 * i]), linear_from_srgb_byte(rgb[3 * i + 1]),
                     linear_from_srgb_byte(rgb[3 * i + 2])};
  return img;
}

void save_screenshot(int width, int height, const std::string& path) {
  std::vector<unsigned char> rgb(size_t(width) * size_t(height) * 3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
  // OpenGL's rows start at the bottom; images' at the top.
  const size_t row = size_t(width) * 3;
  for (int y = 0; y < height / 2; ++y)
    std::swap_ranges(rgb.begin() + std::ptrdiff_t(y * row), rgb.begin() + std::ptrdiff_t((y + 1) * row),
                     rgb.begin() + std::ptrdiff_t((height - 1 - y) * row));
  save_picture(rgb, width, height, path);
}

void save_picture(const std::vector<unsigned char>& rgb, int width, int height, const std::string& path) {
  write_png(image_from_srgb_bytes(rgb, width, height), path);
}

}  // namespace epsray
