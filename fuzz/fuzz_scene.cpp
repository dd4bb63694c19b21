// libFuzzer target: the NFF parser, then what the renderer does with a scene that parses
// (world and BVH build, eye rays through a tiny camera), so that degenerate geometry the
// parser lets through reaches the intersection and shading code. input_error is the
// expected answer to malformed input; any other exception, a sanitizer report or a
// non-finite radiance (the CLI refuses to write such an image) is a finding.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "accel/world.h"
#include "geom/ray.h"
#include "scene/camera.h"
#include "scene/input_error.h"
#include "scene/nff.h"
#include "shade/whitted.h"

using namespace epsray;

namespace {

bool finite(vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// The centre of the view, its edges and corners: few rays, so that fuzzing stays fast.
constexpr int pixels_x = 3, pixels_y = 3;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string_view text(reinterpret_cast<const char*>(data), size);
  // Texture names resolve relative to EPSRAY_FUZZ_TEXTURE_DIR; a '/' could name any file,
  // or a device that never ends. -1 keeps such inputs out of the corpus.
  if (text.find('/') != std::string_view::npos) return -1;
  scene s;
  try {
    s = parse_scene(text, "fuzz.nff", EPSRAY_FUZZ_TEXTURE_DIR);
  } catch (const input_error&) {
    return 0;
  }
  world w = make_world(std::move(s));
  const camera cam = make_camera(w.sc.view, pixels_x, pixels_y);
  if (!finite(cam.w) || !finite(cam.r) || !finite(cam.u)) {
    std::fprintf(stderr, "fuzz_scene: the view gives a camera with non-finite axes\n");
    std::abort();
  }
  trace_state state;
  for (int y = 0; y < pixels_y; ++y)
    for (int x = 0; x < pixels_x; ++x) {
      vec3 c = trace_eye(w, make_ray(cam.origin, eye_direction(cam, float(x), float(y))), state);
      if (!finite(c)) {
        std::fprintf(stderr, "fuzz_scene: pixel (%d, %d) radiance is not finite: %g %g %g\n", x, y, double(c.x),
                     double(c.y), double(c.z));
        std::abort();
      }
    }
  return 0;
}
