#include "viewer/controls.h"

#include <GLFW/glfw3.h>

#include <algorithm>
#include <cctype>

namespace epsray {

const std::vector<key_binding>& key_bindings() {
  static const std::vector<key_binding> b{
      // The help lines are short: the full panel lays them out three to a row in 640 pixels.
      {"W", GLFW_KEY_W, true, "forward"},
      {"S", GLFW_KEY_S, true, "back"},
      {"A", GLFW_KEY_A, true, "left"},
      {"D", GLFW_KEY_D, true, "right"},
      {"Q", GLFW_KEY_Q, true, "down"},
      {"E", GLFW_KEY_E, true, "up"},
      {"+", GLFW_KEY_EQUAL, false, "faster"},
      {"-", GLFW_KEY_MINUS, false, "slower"},
      {"]", GLFW_KEY_RIGHT_BRACKET, false, "epsilon x1.5"},
      {"[", GLFW_KEY_LEFT_BRACKET, false, "epsilon /1.5"},
      {"Tab", GLFW_KEY_TAB, false, "next display"},
      {"R", GLFW_KEY_R, false, "reset view"},
      {"P", GLFW_KEY_P, false, "record path"},
      {"L", GLFW_KEY_L, false, "play path"},
      {"F1", GLFW_KEY_F1, false, "HUD compact/full"},
      {"H", GLFW_KEY_H, false, "HUD on/off"},
      {"Esc", GLFW_KEY_ESCAPE, false, "quit"},
  };
  return b;
}

int key_by_name(std::string_view name, bool held) {
  for (const key_binding& b : key_bindings()) {
    const std::string_view n = b.name;
    if (b.held == held && n.size() == name.size() &&
        std::equal(n.begin(), n.end(), name.begin(), [](char x, char y) { return std::tolower(x) == std::tolower(y); }))
      return b.key;
  }
  return -1;
}

float moving_eps(float eps) { return std::max(eps, std::min(4 * eps, 0.2f)); }

bool set_move_key(move_keys& k, int key) {
  switch (key) {
    case GLFW_KEY_W: return k.forward = true;
    case GLFW_KEY_S: return k.back = true;
    case GLFW_KEY_A: return k.left = true;
    case GLFW_KEY_D: return k.right = true;
    case GLFW_KEY_Q: return k.down = true;
    case GLFW_KEY_E: return k.up = true;
  }
  return false;
}

namespace {

void say(viewer_state& s, std::string note) { s.note = std::move(note), ++s.note_serial; }

void toggle_recording(viewer_state& s) {
  if (s.rec.file.empty()) {
    say(s, "P records only with --record FILE");
  } else if (s.rec.on) {
    s.rec.stop();
    say(s, "wrote " + std::to_string(s.rec.views.size()) + " cameras to " + s.rec.file);
  } else {
    s.rec.start();
    say(s, "recording to " + s.rec.file);
  }
}

void toggle_playing(viewer_state& s) {
  if (!s.path) {
    say(s, "L plays only with --path FILE");
  } else if (s.play >= 0) {
    s.play = -1;
    say(s, "playing stopped");
  } else {
    s.play = 0;
    s.view = s.path->frames[0];
    say(s, "playing " + s.path->file);
  }
}

}  // namespace

void press_key(viewer_state& s, int key) {
  switch (key) {
    case GLFW_KEY_TAB: s.mode = display_mode((int(s.mode) + 1) % display_mode_count); break;
    case GLFW_KEY_F1:  // from a hidden HUD, straight to the panel asked for
      s.hud_full = !s.hud || !s.hud_full, s.hud = true;
      break;
    case GLFW_KEY_H: s.hud = !s.hud; break;
    case GLFW_KEY_RIGHT_BRACKET: s.eps = s.eps > 0 ? std::min(s.eps * 1.5f, max_eps) : 0.001f; break;
    case GLFW_KEY_LEFT_BRACKET: s.eps /= 1.5f; break;
    case GLFW_KEY_EQUAL:
    case GLFW_KEY_KP_ADD: s.speed *= 1.25f; break;
    case GLFW_KEY_MINUS:
    case GLFW_KEY_KP_SUBTRACT: s.speed /= 1.25f; break;
    case GLFW_KEY_R:
      s.view = s.home, s.speed = s.home_speed, s.play = -1;
      say(s, "view reset");
      break;
    case GLFW_KEY_P: toggle_recording(s); break;
    case GLFW_KEY_L: toggle_playing(s); break;
    case GLFW_KEY_ESCAPE: s.quit = true; break;
  }
}

void advance_playback(viewer_state& s) {
  if (s.play < 0 || !s.path) return;
  if (++s.play < int(s.path->frames.size())) {
    s.view = s.path->frames[size_t(s.play)];
  } else {
    s.play = -1;
    say(s, "played " + std::to_string(s.path->frames.size()) + " cameras");
  }
}

}  // namespace epsray
