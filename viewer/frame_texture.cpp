#include "viewer/frame_texture.h"

#include <GL/gl.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace epsray {

frame_texture::frame_texture() {
  glGenTextures(1, &id_);
  glBindTexture(GL_TEXTURE_2D, id_);
  // Nearest: at 1:1 each screen pixel is exactly one rendered pixel (the screenshot tests
  // compare them with `epsray render`).
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

frame_texture::~frame_texture() { glDeleteTextures(1, &id_); }

void frame_texture::upload(const unsigned char* rgb, int width, int height) {
  glBindTexture(GL_TEXTURE_2D, id_);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);  // RGB rows are not padded to 4 bytes
  if (width != width_ || height != height_) {
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, width, height, 0, GL_RGB, GL_UNSIGNED_BYTE, rgb);
    width_ = width, height_ = height;
  } else {
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, rgb);
  }
}

void frame_texture::draw() const {
  if (!width_) return;
  const ImVec2 win = ImGui::GetIO().DisplaySize;
  const float scale = std::min(win.x / float(width_), win.y / float(height_));
  const float w = float(width_) * scale, h = float(height_) * scale;
  // Whole pixels, so that at scale 1 texel centres fall on pixel centres.
  const ImVec2 p0(std::floor((win.x - w) / 2), std::floor((win.y - h) / 2));
  ImGui::GetBackgroundDrawList()->AddImage(reinterpret_cast<ImTextureID>(std::intptr_t(id_)), p0,
                                           ImVec2(p0.x + w, p0.y + h));
}

}  // namespace epsray
