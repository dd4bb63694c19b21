#include "viewer/script.h"

#include <filesystem>

#include "scene/line_reader.h"

namespace epsray {

namespace {

// Draws before a screenshot with the HUD: Dear ImGui sizes a new auto-resizing window on its
// second frame.
constexpr int screenshot_draws = 3;

void expect_words(const line_reader& in, const text_line& l, size_t n, const char* usage) {
  if (l.words.size() != n) in.fail(l.number, std::string("expected '") + usage + "'");
}

// The keys `press` takes, as the error message lists them.
std::string pressable_keys() {
  std::string out;
  for (const key_binding& b : key_bindings()) {
    if (b.held) continue;
    if (!out.empty()) out += ' ';
    out += b.name;
  }
  return out;
}

}  // namespace

script parse_script(std::string_view text, const std::string& name) {
  line_reader in(text, name);
  script out;
  out.file = name;
  text_line l;
  while (in.next(l)) {
    script_step st;
    const std::string_view cmd = l.words[0];
    if (cmd == "frames") {
      expect_words(in, l, 2, "frames N");
      st.op = script_op::frames, st.count = int(in.integer(l, 1, "frames", 1, 100000));
    } else if (cmd == "refine") {
      expect_words(in, l, 1, "refine");
      st.op = script_op::refine;
    } else if (cmd == "key") {
      expect_words(in, l, 3, "key W|A|S|D|Q|E N");
      st.op = script_op::key, st.key = key_by_name(l.words[1], true);
      if (st.key < 0) in.fail(l.number, "key '" + std::string(l.words[1]) + "' is not one of W A S D Q E");
      st.count = int(in.integer(l, 2, "frames", 1, 100000));
    } else if (cmd == "drag") {
      expect_words(in, l, 3, "drag DX DY");
      st.op = script_op::drag, st.x = in.number(l, 1, "drag x"), st.y = in.number(l, 2, "drag y");
    } else if (cmd == "press") {
      expect_words(in, l, 2, "press KEY");
      st.op = script_op::press, st.key = key_by_name(l.words[1], false);
      if (st.key < 0)
        in.fail(l.number, "cannot press '" + std::string(l.words[1]) + "' (" + pressable_keys() + ")");
    } else if (cmd == "mode") {
      expect_words(in, l, 2, "mode image|reasons|paths|cells");
      st.op = script_op::mode;
      if (!parse_display_mode(l.words[1], st.mode))
        in.fail(l.number, "mode '" + std::string(l.words[1]) + "' is not image, reasons, paths or cells");
    } else if (cmd == "pick") {
      expect_words(in, l, 3, "pick FX FY");
      st.op = script_op::pick, st.x = in.number(l, 1, "pick x"), st.y = in.number(l, 2, "pick y");
      if (!(st.x >= 0 && st.x < 1 && st.y >= 0 && st.y < 1)) in.fail(l.number, "pick takes fractions of the image, from 0 to 1");
    } else if (cmd == "eps") {
      expect_words(in, l, 2, "eps E");
      st.op = script_op::eps, st.x = in.number(l, 1, "eps");
      if (st.x < 0 || st.x > max_eps) in.fail(l.number, "eps must be from 0 to 1e6");
    } else if (cmd == "hud") {
      expect_words(in, l, 2, "hud on|off");
      st.op = script_op::hud, st.on = l.words[1] == "on";
      if (!st.on && l.words[1] != "off") in.fail(l.number, "expected 'hud on' or 'hud off'");
    } else if (cmd == "screenshot") {
      if (l.words.size() != 2 && !(l.words.size() == 3 && l.words[2] == "hud"))
        in.fail(l.number, "expected 'screenshot FILE' or 'screenshot FILE hud'");
      st.op = script_op::screenshot, st.file = l.words[1], st.on = l.words.size() == 3;
      std::filesystem::path dir = std::filesystem::path(st.file).parent_path();
      if (!std::filesystem::is_directory(dir.empty() ? "." : dir))
        in.fail(l.number, "screenshot folder '" + dir.string() + "' does not exist");
    } else if (cmd == "quit") {
      expect_words(in, l, 1, "quit");
      st.op = script_op::quit;
    } else {
      in.fail(l.number, "unknown command '" + std::string(cmd) +
                            "' (frames, refine, key, drag, press, mode, pick, eps, hud, screenshot, quit)");
    }
    out.steps.push_back(st);
  }
  return out;
}

script load_script(const std::string& path) { return parse_script(read_text_file(path), path); }

script screenshot_script(const std::string& out) {
  script s;
  s.file = "--screenshot";
  s.steps.resize(2);
  s.steps[0].op = script_op::refine;
  s.steps[1].op = script_op::screenshot, s.steps[1].file = out;
  return s;
}

script_turn script_player::next(viewer_state& st, const shown_frame& shown) {
  script_turn t;
  while (step_ < s_.steps.size()) {
    const script_step& s = s_.steps[step_];
    const int done = done_in_step_++;
    switch (s.op) {
      case script_op::frames:
      case script_op::key:
        if (done < s.count) {
          t.render = true;
          if (s.op == script_op::key) set_move_key(t.keys, s.key);
          return t;
        }
        break;
      case script_op::refine:
        if (shown.id == 0 || shown.eps != st.eps || !same_view(shown.view, st.view)) {
          t.render = true;
          return t;
        }
        break;
      case script_op::drag:
        if (done == 0) {
          t.render = true, t.drag_x = s.x, t.drag_y = s.y;
          return t;
        }
        break;
      case script_op::screenshot:
        if (shown.id == 0) {  // a script that starts with one: there is no picture yet
          done_in_step_ = 0, t.render = true;
          return t;
        }
        if (s.on && done < screenshot_draws) return t;
        if (done == (s.on ? screenshot_draws : 0)) {
          t.screenshot = s.file, t.screenshot_hud = s.on;
          return t;
        }
        break;
      case script_op::press: press_key(st, s.key); break;
      case script_op::mode: st.mode = s.mode; break;
      case script_op::pick: st.pick_x = s.x, st.pick_y = s.y, st.mode = display_mode::cells; break;
      case script_op::eps: st.eps = s.x; break;
      case script_op::hud: st.hud = s.on; break;
      case script_op::quit: step_ = s_.steps.size(); continue;
    }
    ++step_, done_in_step_ = 0;
  }
  t.done = true;
  return t;
}

}  // namespace epsray
