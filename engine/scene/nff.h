// NFF (Eric Haines' Neutral File Format) plus epsray's small superset, documented in
// docs/scene-format.md. Every malformed line throws input_error with its file and line.
#pragma once
#include <string>
#include <string_view>

#include "scene/scene.h"

namespace epsray {

// Reads and checks a whole scene file. Texture files are resolved relative to its folder.
scene load_scene(const std::string& path);

// Parses scene text already in memory; `name` is used in messages, `base_dir` for textures.
scene parse_scene(std::string_view text, const std::string& name, const std::string& base_dir);

}  // namespace epsray
