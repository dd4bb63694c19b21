// Camera path files (whitted.md section 8): one camera per line, checked whole.
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "scene/scene.h"

namespace epsray {

struct camera_path {
  std::string file;
  std::vector<camera_view> frames;  // width/height are not set by path files
};

camera_path load_camera_path(const std::string& path);
camera_path parse_camera_path(std::string_view text, const std::string& name);

}  // namespace epsray
