// A finished frame as the window shows it: 8-bit sRGB bytes for every display mode, made
// on the render thread so that the window thread only uploads a texture.
#pragma once
#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "scene/scene.h"
#include "sched/frame_render.h"

namespace epsray {

// Tab cycles them in this order. cells: the linetree cells of the picked object.
enum class display_mode { image, reasons, paths, cells };
constexpr int display_mode_count = 4;
const char* display_mode_name(display_mode m);
bool parse_display_mode(std::string_view s, display_mode& out);

using rgb8 = std::array<unsigned char, 3>;
// The paths display: fast (reprojected), interp, base, as sRGB bytes (the HUD's legend too).
extern const std::array<rgb8, 3> path_colours;

// The reasons display, indexed by pixel_reason, as sRGB bytes (the legend's too): the
// paper's colours (reason_colour), but for reprojected pixels, which the engine marks in a
// second blue hard to tell from interpolated's; the display shows them orange.
constexpr int reason_count = 7;
const std::array<rgb8, reason_count>& reason_bytes();
// What each colour means, for the legend.
extern const std::array<const char*, reason_count> reason_names;

struct frame_stats {
  double ms = 0, reproject_ms = 0;
  path_times path_ms;
  pixel_counts pixels;
  std::uint64_t memory_bytes = 0;
};

struct shown_frame {
  std::uint64_t id = 0;  // the request it answers
  camera_view view;
  float eps = 0;  // the bound it was rendered with
  int width = 0, height = 0;
  std::array<std::vector<unsigned char>, display_mode_count> rgb;  // RGB rows, top row first
  int cells_object = -1;  // the cells display's picked primitive; -1: none (or not painted)
  frame_stats stats;
};

// Linear radiance to 8-bit sRGB bytes, row by row.
void encode_srgb(const image& img, std::vector<unsigned char>& out);

// Fills `out` from a frame rendered with frame_params::reasons (the cells display is left
// to paint_cells). The byte buffers keep their
// capacity from frame to frame: nothing is allocated once the size is steady.
void fill_shown_frame(const frame_result& fr, shown_frame& out);

}  // namespace epsray
