// libFuzzer target: the camera-path parser, then the camera of every frame it accepts.
// input_error is the expected answer to malformed input; any other exception, a sanitizer
// report or a camera with non-finite axes (every eye ray of that frame would be NaN) is a
// finding.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "scene/camera.h"
#include "scene/input_error.h"
#include "scene/path_file.h"

using namespace epsray;

namespace {

bool finite(vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  camera_path path;
  try {
    path = parse_camera_path(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.path");
  } catch (const input_error&) {
    return 0;
  }
  for (size_t i = 0; i < path.frames.size(); ++i) {
    const camera c = make_camera(path.frames[i], 64, 48);
    if (!finite(c.w) || !finite(c.r) || !finite(c.u) || !std::isfinite(c.step) || !(c.step > 0)) {
      std::fprintf(stderr, "fuzz_path: frame %zu gives a camera with non-finite axes\n", i);
      std::abort();
    }
  }
  return 0;
}
