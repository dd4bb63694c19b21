// The finished frame on screen: an 8-bit sRGB texture drawn behind the HUD, pixel for pixel
// when the window has the frame's size, else scaled to fit with its aspect kept.
#pragma once

namespace epsray {

class frame_texture {
 public:
  frame_texture();
  ~frame_texture();
  frame_texture(const frame_texture&) = delete;
  frame_texture& operator=(const frame_texture&) = delete;

  // RGB bytes, top row first. Reallocates the texture only when the size changes.
  void upload(const unsigned char* rgb, int width, int height);
  // Adds the texture to Dear ImGui's background list of the current frame.
  void draw() const;

 private:
  unsigned int id_ = 0;
  int width_ = 0, height_ = 0;
};

}  // namespace epsray
