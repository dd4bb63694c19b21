#include "viewer/path_recorder.h"

#include <cstdio>

#include "common.h"

namespace epsray {

std::string camera_line(const camera_view& v) {
  char line[256];
  std::snprintf(line, sizeof line, "%.9g %.9g %.9g  %.9g %.9g %.9g  %.9g %.9g %.9g  %.9g", v.from.x, v.from.y,
                v.from.z, v.at.x, v.at.y, v.at.z, v.up.x, v.up.y, v.up.z, v.angle);
  return line;
}

void path_recorder::stop() {
  on = false;
  if (views.empty() || file.empty()) return;
  std::string text = "# camera path recorded by epsray view: from, at, up, angle per frame\n";
  for (const camera_view& v : views) text += camera_line(v) + "\n";
  write_text_file(file, text);
}

}  // namespace epsray
