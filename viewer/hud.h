// The heads-up display (Dear ImGui): frame rate and times, pixels and time per path,
// epsilon (with a field to type it), memory, threads, a frame-time plot and the keys.
#pragma once
#include <array>

#include "viewer/controls.h"
#include "viewer/frame_bytes.h"

namespace epsray {

// The last frame times, oldest first from `next` (a ring for ImGui::PlotLines).
struct frame_times {
  std::array<float, 120> ms{};
  int next = 0, count = 0;
  void add(float v) {
    ms[size_t(next)] = v, next = (next + 1) % int(ms.size());
    if (count < int(ms.size())) ++count;
  }
};

// Draws the HUD window when s.hud is set; typing a bound into its field changes s.eps.
void draw_hud(viewer_state& s, const shown_frame& f, const frame_times& times, const char* scene, int threads);

}  // namespace epsray
