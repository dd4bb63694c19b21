#include "viewer/frame_bytes.h"

#include "image/image_io.h"
#include "interp/interp_shade.h"

namespace epsray {

const std::array<rgb8, 3> path_colours{{{70, 120, 255}, {80, 200, 90}, {225, 75, 55}}};

const char* display_mode_name(display_mode m) {
  switch (m) {
    case display_mode::image: return "image";
    case display_mode::reasons: return "reasons";
    case display_mode::paths: return "paths";
    case display_mode::cells: return "cells";
  }
  return "?";
}

bool parse_display_mode(std::string_view s, display_mode& out) {
  for (int i = 0; i < display_mode_count; ++i)
    if (s == display_mode_name(display_mode(i))) return out = display_mode(i), true;
  return false;
}

void encode_srgb(const image& img, std::vector<unsigned char>& out) {
  out.resize(img.pixels.size() * 3);
  unsigned char* o = out.data();
  for (const glm::vec3& p : img.pixels) *o++ = srgb_byte(p.x), *o++ = srgb_byte(p.y), *o++ = srgb_byte(p.z);
}

namespace {

// The reasons image already tells the paths apart (render_frame adds nothing for them):
// reprojected pixels took the fast path, interpolated ones the interp path, the rest base.
void encode_paths(const image& reasons, std::vector<unsigned char>& out) {
  const glm::vec3 fast = reason_colour(pixel_reason::reprojected);
  const glm::vec3 interp = reason_colour(pixel_reason::interpolated);
  out.resize(reasons.pixels.size() * 3);
  unsigned char* o = out.data();
  for (const glm::vec3& p : reasons.pixels) {
    const rgb8& c = path_colours[p == fast ? 0 : p == interp ? 1 : 2];
    *o++ = c[0], *o++ = c[1], *o++ = c[2];
  }
}

}  // namespace

void fill_shown_frame(const frame_result& fr, shown_frame& out) {
  out.width = fr.img.width, out.height = fr.img.height;
  encode_srgb(fr.img, out.rgb[int(display_mode::image)]);
  encode_srgb(fr.reasons, out.rgb[int(display_mode::reasons)]);
  encode_paths(fr.reasons, out.rgb[int(display_mode::paths)]);
  out.stats = {fr.ms, fr.reproject_ms, fr.path_ms, fr.pixels, fr.memory_bytes};
}

}  // namespace epsray
