// epsray view's main loop. The window thread takes input, moves the camera, asks the render
// thread for the newest camera and shows the newest finished frame; it never waits for a
// frame (a script waits by turning the loop until its frame is on screen).
#include <GLFW/glfw3.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <optional>
#include <stdexcept>

#include "accel/world.h"
#include "common.h"
#include "scene/nff.h"
#include "scene/path_file.h"
#include "viewer/controls.h"
#include "viewer/frame_texture.h"
#include "viewer/hud.h"
#include "viewer/render_thread.h"
#include "viewer/screenshot.h"
#include "viewer/script.h"
#include "viewer/view.h"
#include "viewer/window.h"

namespace epsray {

namespace {

using clock_type = std::chrono::steady_clock;

// A camera that moved within this time still renders at the moving bound, so that a pause
// between two mouse events does not start a slow refined frame.
constexpr double settle_seconds = 0.15;

// The art room of this repository: where it was built from, else beside the executable's
// folder (build/epsray), else below the working folder.
std::string default_scene() {
  namespace fs = std::filesystem;
  std::vector<fs::path> tries{EPSRAY_DEFAULT_SCENE};
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) tries.push_back(exe.parent_path().parent_path() / "scenes" / "artroom.nff");
  tries.push_back("scenes/artroom.nff");
  for (const fs::path& p : tries)
    if (fs::is_regular_file(p)) return p.string();
  return tries.front().string();  // load_scene says that it is missing
}

// What the window thread knows of the render thread's work.
struct request_log {
  bool any = false;
  camera_view view;  // of the last request
  float eps = 0;
  bool cells = false;
  float pick_x = 0, pick_y = 0;
  std::uint64_t id = 0;
};

}  // namespace

int run_view(const cli_options& given) {
  // Every input is checked before the window opens: scene, path, script, output folders.
  cli_options o = given;
  o.mode = render_mode::full;
  if (o.scene.empty()) o.scene = default_scene();
  scene sc = load_scene(o.scene);
  std::optional<camera_path> path;
  if (!o.path.empty()) path = load_camera_path(o.path);
  std::optional<script_player> player;
  if (!o.script.empty()) player.emplace(load_script(o.script));
  else if (!o.screenshot.empty()) player.emplace(screenshot_script(o.screenshot));
  check_writable(o.record, "--record");
  check_writable(o.screenshot, "--screenshot");
  const bool scripted = player.has_value();
  const int width = o.size ? o.size->first : sc.view.width;
  const int height = o.size ? o.size->second : sc.view.height;

  window win(width, height, "epsray view: " + o.scene, !scripted);  // vsync paces a user's loop
  const world w = make_world(std::move(sc));
  // A session may wander for hours: the linetrees keep to a budget (256 MB unless set).
  const double budget_mb = o.memory_mb > 0 ? o.memory_mb : 256;
  render_thread renderer(w, make_frame_params(o, nullptr, nullptr), width, height,
                         o.threads ? o.threads : hardware_threads(), size_t(budget_mb * 1048576.0), &window::wake);
  frame_texture texture;

  viewer_state st;
  st.home = st.view = path ? path->frames[0] : w.sc.view;
  st.home_speed = st.speed = default_speed(w.box);
  st.eps = o.eps;
  st.rec.file = o.record;
  st.path = path ? &*path : nullptr;

  shown_frame shown;
  std::vector<camera_view> rendered;
  std::vector<int> presses;
  frame_times times;
  request_log last;
  bool upload = false;
  display_mode uploaded_mode = st.mode;
  auto last_turn = clock_type::now(), last_move = last_turn;
  double rest = 0;  // seconds the next turn may wait for input (a finished frame wakes it)

  while (!st.quit && !win.closing()) {
    win.wait_events(rest);
    if (std::string e = renderer.error(); !e.empty()) throw std::runtime_error("rendering failed: " + e);
    const auto now = clock_type::now();
    float seconds = float(std::min(std::chrono::duration<double>(now - last_turn).count(), 0.1));
    last_turn = now;

    bool next_camera = false;  // playback moved on: render even an unchanged camera
    if (renderer.take(shown, rendered)) {
      for (const camera_view& v : rendered) st.rec.add(v);
      times.add(float(shown.stats.ms));
      upload = true;
      if (st.play >= 0 && shown.id >= last.id) advance_playback(st), next_camera = true;
    }

    move_keys keys;
    float dx = 0, dy = 0;
    bool render = false;
    std::string screenshot;
    bool screenshot_hud = false;
    if (scripted) {
      if (last.id <= shown.id) {  // else its frame is not on screen yet: just draw
        const script_turn t = player->next(st, shown);
        if (t.done) break;
        keys = t.keys, dx = t.drag_x, dy = t.drag_y, render = t.render;
        screenshot = t.screenshot, screenshot_hud = t.screenshot_hud;
        seconds = script_frame_seconds;
      }
    } else {
      double scroll = 0;
      win.take_input(presses, scroll);
      for (int k : presses) press_key(st, k);
      st.speed *= float(std::pow(1.25, scroll));
      for (const key_binding& b : key_bindings())
        if (b.held && win.key_held(b.key)) set_move_key(keys, b.key);
      win.drag(dx, dy);
      if (win.take_pick(st.pick_x, st.pick_y)) st.mode = display_mode::cells;
    }
    if (st.play < 0) {
      fly(st.view, keys, st.speed, seconds);
      look(st.view, dx, dy);
    }
    {
      // Progressive refinement: the moving bound until the camera has stood still for a frame.
      const bool changed = !last.any || !same_view(st.view, last.view);
      if (changed) last_move = now;
      const double still = std::chrono::duration<double>(now - last_move).count();
      const bool moving = changed || (!scripted && still < settle_seconds);
      const float eps = moving ? moving_eps(st.eps) : st.eps;
      const bool cells = st.mode == display_mode::cells;
      const bool display_changed = cells != last.cells || (cells && (st.pick_x != last.pick_x || st.pick_y != last.pick_y));
      if (scripted ? render : changed || next_camera || eps != last.eps || display_changed) {
        last.id = renderer.request({st.view, eps, cells, st.pick_x, st.pick_y, moving});
        last.any = true, last.view = st.view, last.eps = eps;
        last.cells = cells, last.pick_x = st.pick_x, last.pick_y = st.pick_y;
      }
      // A script turns as soon as its frame is on screen. A user's loop turns often only
      // while keys move the camera or a path plays, wakes for the refined frame once the
      // camera has settled, and otherwise rests (drawing the HUD costs on a software GL).
      if (scripted) rest = last.id > shown.id ? 0.25 : 0;
      else if (keys.any() || st.play >= 0) rest = 1.0 / 120;
      else if (moving) rest = std::max(settle_seconds - still, 0.005);
      else rest = 0.5;
    }

    if (shown.id && (upload || st.mode != uploaded_mode)) {
      texture.upload(shown.rgb[size_t(st.mode)].data(), shown.width, shown.height);
      upload = false, uploaded_mode = st.mode;
    }
    win.begin_frame();
    texture.draw();
    draw_hud(st, shown, times, o.scene.c_str(), renderer.threads());
    win.end_frame();
    if (!scripted && win.hud_busy()) rest = std::min(rest, 1.0 / 60);
    if (!screenshot.empty() && screenshot_hud) {
      int fw = 0, fh = 0;
      win.framebuffer_size(fw, fh);
      save_screenshot(fw, fh, screenshot);
    } else if (!screenshot.empty()) {
      save_picture(shown.rgb[size_t(st.mode)], shown.width, shown.height, screenshot);
    }
    win.present();
  }
  if (st.rec.on) st.rec.stop();  // the path recorded so far, whole
  return 0;
}

}  // namespace epsray
