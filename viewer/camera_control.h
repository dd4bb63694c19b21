// Flying the camera: moves along the view, turns it with the mouse. Works on the NFF view
// itself (from, at, up, angle), so a view nobody moved stays bit for bit the scene's and a
// recorded path replays exactly.
#pragma once
#include "geom/bounds.h"
#include "scene/scene.h"

namespace epsray {

// Movement keys held during a step.
struct move_keys {
  bool forward = false, back = false, left = false, right = false, down = false, up = false;
  bool any() const { return forward || back || left || right || down || up; }
};

// Moves `from` and `at` together by `speed * seconds` world units along the view (forward,
// back), its right (left, right) and the view's up vector (down, up).
void fly(camera_view& v, const move_keys& k, float speed, float seconds);

// Turns the view by a mouse drag in pixels: right turns right, down looks down; the view
// stops 1 degree short of the up vector.
void look(camera_view& v, float dx, float dy);
constexpr float look_degrees_per_pixel = 0.25f;

// A speed that crosses the scene's box in about five seconds.
float default_speed(const bounds& box);

bool same_view(const camera_view& a, const camera_view& b);

}  // namespace epsray
