// P in the viewer: the camera of every frame rendered while recording, written as a path
// file (whitted.md section 8, what `epsray walk --path` reads) when recording stops or the
// viewer exits.
#pragma once
#include <string>
#include <vector>

#include "scene/scene.h"

namespace epsray {

struct path_recorder {
  std::string file;  // --record; empty: recording is off
  bool on = false;
  std::vector<camera_view> views;

  void start() { on = true, views.clear(); }
  void add(const camera_view& v) {
    if (on) views.push_back(v);
  }
  // Stops and writes the file whole (a temporary renamed over it); nothing when no frame
  // was rendered. Throws std::runtime_error when it cannot write.
  void stop();
};

// One path-file line: `fx fy fz  ax ay az  ux uy uz  angle`, with digits enough to read
// back the same floats.
std::string camera_line(const camera_view& v);

}  // namespace epsray
