// What the viewer's keys do. The keyboard and --script both go through press_key and
// set_move_key, so a script drives exactly the code a user does.
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "scene/path_file.h"
#include "viewer/camera_control.h"
#include "viewer/frame_bytes.h"
#include "viewer/path_recorder.h"

namespace epsray {

struct key_binding {
  const char* name;  // as the HUD and scripts spell it
  int key;           // GLFW key code
  bool held;         // acts while held (movement) rather than once per press
  const char* help;
};
const std::vector<key_binding>& key_bindings();
// A binding's GLFW key code by name (case-insensitive), or -1.
int key_by_name(std::string_view name, bool held);

struct viewer_state {
  camera_view home, view;  // R goes back home
  float home_speed = 1, speed = 1;  // world units per second
  float eps = 0.05f;                // the user's bound; moving_eps while the camera moves
  display_mode mode = display_mode::image;
  // The cells display's object: under this point, fractions of the image; negative until a
  // right click (or a script's pick) picks one.
  float pick_x = -1, pick_y = -1;
  bool hud = true;        // H: the HUD, or nothing over the picture
  bool hud_full = false;  // F1: the full panel rather than the compact lines
  bool quit = false;
  path_recorder rec;
  const camera_path* path = nullptr;  // --path, played by L
  int play = -1;                      // the path camera on screen next; -1: not playing
  std::string note;                   // what the last key did, for the HUD
  int note_serial = 0;                // counts notes: the compact HUD shows a new one a while
};

constexpr float max_eps = 1e6f;  // as --eps
// The coarser bound rendered while the camera moves: 4x the user's, at most 0.2 (never
// below the user's). The predicate rejects discontinuities at any bound.
float moving_eps(float eps);

// Marks `key` held in `k`; false when it is not a movement key.
bool set_move_key(move_keys& k, int key);
// One press of a non-movement key.
void press_key(viewer_state& s, int key);
// A frame of the path being played has been rendered: the next camera, or the end.
void advance_playback(viewer_state& s);

}  // namespace epsray
