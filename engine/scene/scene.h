// The scene as parsed: plain arrays of analytic primitives, materials, textures and lights.
// Nothing here is optimised for tracing; engine/geom and engine/accel build that from it.
#pragma once
#include <glm/glm.hpp>
#include <string>
#include <vector>

namespace epsray {

using glm::vec2;
using glm::vec3;

// NFF's view: `angle` spans the centres of the top and bottom pixel rows (whitted.md 1).
struct camera_view {
  vec3 from{0, 0, 0}, at{0, 0, -1}, up{0, 1, 0};
  float angle = 45;  // degrees
  int width = 512, height = 512;
};

struct material {
  vec3 color{1, 1, 1};
  float kd = 1, ks = 0, shine = 0, t = 0, ior = 1;
  int texture = -1;  // index into scene::textures, modulates `color`
};

enum class texture_kind { checker, image };

struct texture {
  texture_kind kind = texture_kind::checker;
  vec3 color_a{1, 1, 1}, color_b{0, 0, 0};  // checker squares
  vec2 scale{1, 1};                          // world units per repeat along u and v
  int width = 0, height = 0;                 // image texels, linear RGB, top row first
  std::vector<vec3> texels;
  std::string file;
};

struct light {
  vec3 position{0, 0, 0};
  vec3 color{1, 1, 1};
  bool has_color = false;  // NFF: uncoloured lights get sqrt(N)/(2N)
};

enum class prim_kind : unsigned char { sphere, cone, polygon, patch, box, disk };

// `a`, `b`, `r0`, `r1` and `frame` mean different things per kind:
//   sphere:  centre a, radius r0 (negative flips the normal)
//   cone:    base a radius r0, apex b radius r1 (open; negative radii flip the normal)
//   polygon/patch: vertices [first, first+count) of scene::vertices (and ::normals for patches)
//   box:     centre a, half extents b, axes frame[0..2]
//   disk:    centre a, normal b, radius r0
struct primitive {
  prim_kind kind = prim_kind::sphere;
  int material = 0;
  int line = 0;  // where it was defined, for messages
  vec3 a{0}, b{0};
  float r0 = 0, r1 = 0;
  int first = 0, count = 0;
  glm::mat3 frame{1.0f};
};

struct scene {
  std::string file;
  camera_view view;
  bool has_view = false;
  vec3 background{0, 0, 0};
  vec3 ambient{0, 0, 0};
  bool has_ambient = false;  // set by the native `ambient` line; else the SPD convention
  std::vector<material> materials;
  std::vector<texture> textures;
  std::vector<light> lights;
  std::vector<primitive> prims;
  std::vector<vec3> vertices, normals;
};

// Ambient and light intensities after the SPD convention (whitted.md 3) is applied.
vec3 scene_ambient(const scene& s);
vec3 light_intensity(const scene& s, const light& l);

}  // namespace epsray
