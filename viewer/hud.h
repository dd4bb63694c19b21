// The heads-up display (Dear ImGui). Compact by default: two lines over the top left (frame
// rate and time, epsilon, each path's share of the pixels). F1 opens the full panel: times
// and thread time per path, epsilon (with a field to type it), memory, threads, a
// frame-time plot and the keys. The diagnostic displays add a legend along the bottom, and
// the cells display with nothing picked says how to pick. H hides it all.
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

// Draws the HUD when s.hud is set; typing a bound into the panel's field changes s.eps.
void draw_hud(viewer_state& s, const shown_frame& f, const frame_times& times, const char* scene, int threads);

}  // namespace epsray
