#include "viewer/frame_bytes.h"

#include <algorithm>

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

const std::array<const char*, reason_count> reason_names{
    "interpolated", "discontinuity", "missed", "blocked", "nonlinear", "traced", "reprojected"};

const std::array<rgb8, reason_count>& reason_bytes() {
  static const std::array<rgb8, reason_count> bytes = [] {
    static_assert(reason_count == int(pixel_reason::reprojected) + 1);
    std::array<rgb8, reason_count> b;
    for (int r = 0; r < reason_count; ++r) {
      const glm::vec3 c = reason_colour(pixel_reason(r));
      b[size_t(r)] = {srgb_byte(c.x), srgb_byte(c.y), srgb_byte(c.z)};
    }
    return b;
  }();
  return bytes;
}

namespace {

// The engine's reasons image holds one reason_colour per pixel; each becomes the display's
// colour for its reason, and its path's colour in the paths display (render_frame marks
// nothing else for them): reprojected pixels took the fast path, interpolated ones the
// interp path, the rest base.
void encode_reasons(const image& reasons, std::vector<unsigned char>& out, std::vector<unsigned char>& paths) {
  std::array<glm::vec3, reason_count> engine;
  for (int r = 0; r < reason_count; ++r) engine[size_t(r)] = reason_colour(pixel_reason(r));
  const std::array<rgb8, reason_count>& shown = reason_bytes();
  out.resize(reasons.pixels.size() * 3);
  paths.resize(reasons.pixels.size() * 3);
  unsigned char *o = out.data(), *q = paths.data();
  for (const glm::vec3& p : reasons.pixels) {
    const int r = int(std::find(engine.begin(), engine.end(), p) - engine.begin());
    const rgb8 c = r < reason_count ? shown[size_t(r)] : rgb8{srgb_byte(p.x), srgb_byte(p.y), srgb_byte(p.z)};
    *o++ = c[0], *o++ = c[1], *o++ = c[2];
    const pixel_reason why = pixel_reason(r);
    const rgb8& pc = path_colours[why == pixel_reason::reprojected ? 0 : why == pixel_reason::interpolated ? 1 : 2];
    *q++ = pc[0], *q++ = pc[1], *q++ = pc[2];
  }
}

}  // namespace

void fill_shown_frame(const frame_result& fr, shown_frame& out) {
  out.width = fr.img.width, out.height = fr.img.height;
  encode_srgb(fr.img, out.rgb[int(display_mode::image)]);
  encode_reasons(fr.reasons, out.rgb[int(display_mode::reasons)], out.rgb[int(display_mode::paths)]);
  out.stats = {fr.ms, fr.reproject_ms, fr.path_ms, fr.pixels, fr.memory_bytes};
}

}  // namespace epsray
