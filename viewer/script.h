// --script FILE: a text script that drives the viewer deterministically for tests and
// demos. One command per line, `#` comments:
//   frames N           render N frames with the camera still
//   refine             render until a frame at the user's epsilon shows the current camera
//   key K N            hold movement key K (W A S D Q E) for N frames
//   drag DX DY         one frame of mouse look by DX, DY pixels
//   press K            press a key once: + - ] [ Tab R P L F1 H Esc
//   mode image|reasons|paths|cells
//   pick FX FY         right click at FX, FY (fractions of the image): the cells display
//   eps E              the user's epsilon, as if typed into the HUD
//   hud on|off         as H: the HUD shown (compact, or the full panel after F1) or hidden
//   screenshot FILE    the rendered picture of the current display as a PNG, no HUD
//   screenshot FILE hud   the whole window, HUD and legend as drawn
//   quit
// Each frame is one step: the script waits for it to finish and show, and a held key moves
// the camera by one 30th of a second at the current speed. The viewer exits when the script ends.
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "viewer/camera_control.h"
#include "viewer/controls.h"
#include "viewer/frame_bytes.h"

namespace epsray {

enum class script_op { frames, refine, key, drag, press, mode, pick, eps, hud, screenshot, quit };

struct script_step {
  script_op op = script_op::quit;
  int count = 1;       // frames, key: frames to render
  int key = -1;        // key, press: GLFW key code
  float x = 0, y = 0;  // drag: pixels; pick: fractions of the image; eps: the bound in x
  display_mode mode = display_mode::image;
  bool on = false;   // hud; screenshot: of the window, HUD included
  std::string file;  // screenshot
};

struct script {
  std::string file;
  std::vector<script_step> steps;
};

// Checked whole before the window opens: bad input is `file:line: what` (exit 2).
script parse_script(std::string_view text, const std::string& name);
script load_script(const std::string& path);
// --screenshot OUT alone: refine, then save the picture.
script screenshot_script(const std::string& out);

constexpr float script_frame_seconds = 1.0f / 30;

// What the main loop does for the script in one of its turns.
struct script_turn {
  bool render = false;  // apply keys and drag, then render one frame and wait for it
  move_keys keys;
  float drag_x = 0, drag_y = 0;
  std::string screenshot;  // save the picture once this turn is drawn
  bool screenshot_hud = false;  // the whole window rather than the picture
  bool done = false;       // the script has ended
};

class script_player {
 public:
  explicit script_player(script s) : s_(std::move(s)) {}
  // Called on each turn of the main loop once the frame asked for last is on screen.
  // Applies the steps that need no frame to `st` and returns the next one that does.
  script_turn next(viewer_state& st, const shown_frame& shown);

 private:
  script s_;
  size_t step_ = 0;
  int done_in_step_ = 0;  // frames rendered, or draws waited, in the current step
};

}  // namespace epsray
