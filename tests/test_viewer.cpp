// viewer: the pieces of `epsray view` that need no window (script parsing, camera moves,
// screenshot bytes), then build/epsray view as a subprocess. Without a display it refuses in
// one line; under an Xvfb that the test starts itself it is driven by --script, and its
// screenshots must show the rendered frame (compared with `epsray render` of the same
// camera) with no HUD unless asked, the compact HUD and the full panel within the window,
// the error-coded and per-path displays and their legends, the cells display's hint, and
// recorded and played paths.
#include <poll.h>
#include <stb/stb_image.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "image/image_io.h"
#include "interp/interp_shade.h"
#include "scene/input_error.h"
#include "scene/path_file.h"
#include "test_process.h"
#include "viewer/camera_control.h"
#include "viewer/controls.h"
#include "viewer/frame_bytes.h"
#include "viewer/screenshot.h"
#include "viewer/script.h"

namespace epsray {
namespace {

using test::temp_dir;

// --- without a window ------------------------------------------------------------------

TEST(ViewerScript, ParsesEveryCommand) {
  const script s = parse_script(
      "# a comment\n"
      "frames 3\nrefine\nkey w 2\ndrag 10 -5\npress Tab\npress ]\nmode reasons\neps 0.1\nhud off\n"
      "screenshot out.png\nscreenshot win.png hud\nquit\n",
      "t.script");
  ASSERT_EQ(s.steps.size(), 12u);
  EXPECT_EQ(s.steps[0].op, script_op::frames);
  EXPECT_EQ(s.steps[0].count, 3);
  EXPECT_EQ(s.steps[2].op, script_op::key);
  EXPECT_EQ(s.steps[2].count, 2);
  EXPECT_EQ(s.steps[3].x, 10);
  EXPECT_EQ(s.steps[3].y, -5);
  EXPECT_EQ(s.steps[6].mode, display_mode::reasons);
  EXPECT_FLOAT_EQ(s.steps[7].x, 0.1f);
  EXPECT_FALSE(s.steps[8].on);
  EXPECT_EQ(s.steps[9].file, "out.png");
  EXPECT_FALSE(s.steps[9].on) << "the picture alone";
  EXPECT_EQ(s.steps[10].file, "win.png");
  EXPECT_TRUE(s.steps[10].on) << "the window, HUD included";
  EXPECT_EQ(s.steps[11].op, script_op::quit);
}

TEST(ViewerScript, PickChoosesTheCellsDisplay) {
  const script s = parse_script("pick 0.25 0.75\nmode cells\n", "t.script");
  ASSERT_EQ(s.steps.size(), 2u);
  EXPECT_EQ(s.steps[0].op, script_op::pick);
  EXPECT_FLOAT_EQ(s.steps[0].x, 0.25f);
  EXPECT_FLOAT_EQ(s.steps[0].y, 0.75f);
  EXPECT_EQ(s.steps[1].mode, display_mode::cells);
}

TEST(ViewerScript, BadLinesNameTheLine) {
  const std::pair<const char*, const char*> cases[] = {
      {"frames\n", "expected 'frames N'"},
      {"frames 0\n", "frames"},
      {"key P 3\n", "not one of W A S D Q E"},
      {"press W\n", "cannot press 'W' (+ - ] [ Tab R P L F1 H Esc)"},
      {"mode fancy\n", "not image, reasons, paths or cells"},
      {"pick 0.5\n", "expected 'pick FX FY'"},
      {"pick 1.5 0.5\n", "fractions of the image"},
      {"eps -1\n", "eps must be"},
      {"hud maybe\n", "hud on"},
      {"screenshot /no/such/folder/x.png\n", "does not exist"},
      {"screenshot x.png hub\n", "expected 'screenshot FILE' or 'screenshot FILE hud'"},
      {"jump\n", "unknown command 'jump'"},
  };
  for (const auto& [text, phrase] : cases) {
    try {
      parse_script(std::string("refine\n") + text, "t.script");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const input_error& e) {
      EXPECT_EQ(e.line, 2) << text;
      EXPECT_NE(std::string(e.what()).find(phrase), std::string::npos) << e.what();
    }
  }
}

TEST(ViewerCamera, MovesKeepTheViewAndStopShortOfUp) {
  const camera_view home{{0, 1, 5}, {0, 1, 0}, {0, 1, 0}, 40};
  camera_view v = home;
  fly(v, move_keys{}, 2, 1);
  look(v, 0, 0);
  EXPECT_TRUE(same_view(v, home)) << "no input leaves the view bit for bit";
  move_keys fwd;
  fwd.forward = true;
  fly(v, fwd, 2, 0.5f);
  EXPECT_NEAR(v.from.z, 4, 1e-6);
  EXPECT_NEAR(v.at.z, -1, 1e-6);
  look(v, 360, 0);  // 90 degrees right: from looking down -z to looking down +x
  EXPECT_NEAR(glm::length(v.at - v.from), 5, 1e-5);
  EXPECT_NEAR(v.at.x - v.from.x, 5, 1e-4);
  look(v, 0, -10000);  // far up: stops at 89 degrees
  const vec3 f = glm::normalize(v.at - v.from);
  EXPECT_NEAR(std::asin(f.y), glm::radians(89.0f), 1e-4);
}

TEST(ViewerControls, F1SwitchesThePanelAndHHidesTheHud) {
  const int f1 = key_by_name("F1", false), h = key_by_name("h", false);
  viewer_state s;
  EXPECT_TRUE(s.hud);
  EXPECT_FALSE(s.hud_full) << "compact by default";
  press_key(s, f1);
  EXPECT_TRUE(s.hud && s.hud_full);
  press_key(s, f1);
  EXPECT_TRUE(s.hud && !s.hud_full);
  press_key(s, h);
  EXPECT_FALSE(s.hud);
  press_key(s, f1);
  EXPECT_TRUE(s.hud && s.hud_full) << "F1 brings a hidden HUD back, as the full panel";
  press_key(s, h);
  press_key(s, h);
  EXPECT_TRUE(s.hud && s.hud_full) << "H keeps the panel chosen";
}

// The legend's colours: interpolated and reprojected, the two commonest, far apart (the
// engine marks them in two blues), and no two reasons alike.
TEST(ViewerReasons, EveryReasonHasItsOwnColour) {
  const auto& c = reason_bytes();
  const auto distance = [](const rgb8& a, const rgb8& b) {
    int d = 0;
    for (size_t i = 0; i < 3; ++i) d = std::max(d, std::abs(int(a[i]) - int(b[i])));
    return d;
  };
  EXPECT_GE(distance(c[size_t(pixel_reason::interpolated)], c[size_t(pixel_reason::reprojected)]), 120);
  for (size_t a = 0; a < c.size(); ++a)
    for (size_t b = a + 1; b < c.size(); ++b) EXPECT_GE(distance(c[a], c[b]), 60) << a << " and " << b;
}

TEST(ViewerScreenshot, ScreenBytesSurviveWritePng) {
  for (int b = 0; b < 256; ++b) EXPECT_EQ(srgb_byte(linear_from_srgb_byte((unsigned char)b)), b);
}

// --- build/epsray view as a subprocess --------------------------------------------------

using test::proc_result;

// build/epsray `args` in `dir`, with DISPLAY set to `display` (unset when empty).
proc_result run_epsray(const std::vector<std::string>& args, const temp_dir& dir, const std::string& display) {
  std::vector<std::string> argv{EPSRAY_BINARY};
  argv.insert(argv.end(), args.begin(), args.end());
  if (display.empty())
    return test::run_process(argv, dir.path(), test::environment({"DISPLAY", "WAYLAND_DISPLAY"}), dir, 60);
  // Under AddressSanitizer (tools/run-sanitizers.sh): Mesa's software GL driver, loaded and
  // unloaded by libGL, leaves a few small blocks that LeakSanitizer can neither name nor
  // suppress once the driver is gone, so runs with a window are not leak-checked (the
  // other checks stay on, and the runs without a window keep leak checking).
  const char* asan = std::getenv("ASAN_OPTIONS");
  const std::string asan_options = std::string("ASAN_OPTIONS=") + (asan ? asan : "") + ":detect_leaks=0";
  return test::run_process(argv, dir.path(),
                           test::environment({"DISPLAY", "WAYLAND_DISPLAY", "ASAN_OPTIONS"},
                                             {"DISPLAY=" + display, asan_options}),
                           dir, 60);
}

std::string scene_file(const char* name) { return std::string(EPSRAY_SOURCE_DIR) + "/scenes/tests/" + name; }

TEST(ViewerCli, NoDisplayIsOneLineAndExitTwo) {
  temp_dir dir;
  const proc_result r = run_epsray({"view", scene_file("sphere.nff"), "--size", "160x120"}, dir, "");
  ASSERT_TRUE(r.exited) << r;
  EXPECT_EQ(r.code, 2) << r;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r;
  EXPECT_EQ(r.err.rfind("epsray: view needs a display", 0), 0u) << r;
  EXPECT_TRUE(r.out.empty()) << r;
}

TEST(ViewerCli, BadScriptIsBadInputBeforeAnyWindow) {
  temp_dir dir;
  test::write_file(dir.file("bad.script"), "frames 1\nfly 3\n");
  const proc_result r = run_epsray({"view", scene_file("sphere.nff"), "--script", "bad.script"}, dir, ":0");
  ASSERT_TRUE(r.exited) << r;
  EXPECT_EQ(r.code, 2) << r;
  EXPECT_EQ(r.err, "bad.script:2: unknown command 'fly' (frames, refine, key, drag, press, mode, pick, eps, hud, "
                   "screenshot, quit)\n");
}

// An Xvfb of its own: -displayfd makes the server pick a free display and say which, so
// tests running side by side never race for one (as xvfb-run -a can).
class xvfb {
 public:
  xvfb() {
    for (const char* p : {"/usr/bin/Xvfb", "/usr/local/bin/Xvfb"})
      if (::access(p, X_OK) == 0) binary_ = p;
    if (binary_.empty()) return;
    int fds[2];
    if (pipe(fds) != 0) return;
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addclose(&fa, fds[0]);
    posix_spawn_file_actions_adddup2(&fa, fds[1], 3);
    posix_spawn_file_actions_addopen(&fa, 2, "/dev/null", O_WRONLY, 0);
    std::vector<std::string> args{binary_, "-displayfd", "3", "-screen", "0", "1024x768x24", "-nolisten", "tcp"};
    std::vector<std::string> env = test::environment({"DISPLAY"});
    if (posix_spawn(&pid_, binary_.c_str(), &fa, nullptr, test::c_strings(args).data(), test::c_strings(env).data()) !=
        0)
      pid_ = -1;
    posix_spawn_file_actions_destroy(&fa);
    close(fds[1]);
    // The display number, then a newline, once the server accepts connections.
    std::string number;
    pollfd pfd{fds[0], POLLIN, 0};
    char c;
    while (pid_ > 0 && poll(&pfd, 1, 10000) == 1 && read(fds[0], &c, 1) == 1 && c != '\n') number += c;
    close(fds[0]);
    if (!number.empty()) display_ = ":" + number;
  }
  ~xvfb() {
    if (pid_ <= 0) return;
    kill(pid_, SIGTERM);
    int status;
    test::wait_or_kill(pid_, 10, status);
  }
  bool installed() const { return !binary_.empty(); }
  const std::string& display() const { return display_; }

 private:
  std::string binary_, display_;
  pid_t pid_ = -1;
};

#define EPSRAY_START_XVFB(x)                                                  \
  xvfb x;                                                                     \
  if (!x.installed()) GTEST_SKIP() << "Xvfb is not installed (Debian: xvfb)"; \
  ASSERT_FALSE(x.display().empty()) << "Xvfb did not start"

struct png {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;
  const unsigned char* at(int x, int y) const { return &rgb[(size_t(y) * size_t(width) + size_t(x)) * 3]; }
};

png read_png(const std::string& path) {
  png p;
  int comp = 0;
  unsigned char* data = stbi_load(path.c_str(), &p.width, &p.height, &comp, 3);
  if (!data) {
    ADD_FAILURE() << path << ": " << stbi_failure_reason();
    return p;
  }
  p.rgb.assign(data, data + size_t(p.width) * size_t(p.height) * 3);
  stbi_image_free(data);
  return p;
}

// The largest byte difference of two screenshots; `differing` counts the pixels where any
// channel differs by more than 24 (far beyond an epsilon).
int max_difference(const png& a, const png& b, int* differing = nullptr) {
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  if (a.rgb.size() != b.rgb.size()) return 256;
  int worst = 0, count = 0;
  for (size_t i = 0; i < a.rgb.size(); i += 3) {
    int d = 0;
    for (size_t c = 0; c < 3; ++c) d = std::max(d, std::abs(int(a.rgb[i + c]) - int(b.rgb[i + c])));
    worst = std::max(worst, d), count += d > 24;
  }
  if (differing) *differing = count;
  return worst;
}

// Where two screenshots of one frame differ by more than 24 in some channel (an overlay
// drawn over one of them): the bounding box, and the rows and pixels that differ.
struct overlay_area {
  int x0 = 0, y0 = 0, x1 = -1, y1 = -1;  // inclusive; empty when x1 < x0
  int rows = 0, pixels = 0;
  int pixels_in(int ax0, int ay0, int ax1, int ay1) const;  // within [ax0, ax1) x [ay0, ay1)
  std::vector<bool> mask;
  int width = 0;
};

overlay_area differing_area(const png& a, const png& b) {
  overlay_area o;
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  if (a.rgb.size() != b.rgb.size()) return o;
  o.width = a.width, o.x0 = a.width, o.y0 = a.height;
  o.mask.assign(size_t(a.width) * size_t(a.height), false);
  for (int y = 0; y < a.height; ++y) {
    bool row = false;
    for (int x = 0; x < a.width; ++x) {
      const unsigned char *p = a.at(x, y), *q = b.at(x, y);
      bool d = false;
      for (int c = 0; c < 3; ++c) d = d || std::abs(int(p[c]) - int(q[c])) > 24;
      if (!d) continue;
      o.mask[size_t(y) * size_t(a.width) + size_t(x)] = true;
      row = true, ++o.pixels;
      o.x0 = std::min(o.x0, x), o.x1 = std::max(o.x1, x), o.y0 = std::min(o.y0, y), o.y1 = std::max(o.y1, y);
    }
    o.rows += row;
  }
  return o;
}

int overlay_area::pixels_in(int ax0, int ay0, int ax1, int ay1) const {
  if (mask.empty()) return 0;
  int n = 0;
  for (int y = ay0; y < ay1; ++y)
    for (int x = ax0; x < ax1; ++x) n += mask[size_t(y) * size_t(width) + size_t(x)];
  return n;
}

// How far apart, in sRGB bytes, a pixel within `eps` of the Whitted radiance may be from it:
// a relative change eps of a linear value moves its sRGB code by at most about eps/2.4 of
// it (the curve's exponent), the dark linear segment by less; plus one byte of rounding.
int byte_tolerance(double eps) { return 1 + int(std::ceil(255 * eps / 2.4)); }

class ViewerXvfb : public testing::Test {
 protected:
  temp_dir dir;
  const std::string scene = scene_file("shapes.nff");  // interpolates at 160x120, unlike sphere.nff
  static constexpr double eps = 0.05;

  proc_result view(std::vector<std::string> args, const std::string& display, const char* size = "160x120") {
    args.insert(args.begin(), {"view", scene, "--size", size, "--eps", "0.05"});
    return run_epsray(args, dir, display);
  }
  // `text` as a script file, played by `epsray view` with `args` besides.
  proc_result play(const std::string& text, const std::string& display, const char* size = "160x120",
                   std::vector<std::string> args = {}) {
    test::write_file(dir.file("s.script"), text);
    args.insert(args.begin(), {"--script", "s.script"});
    return view(args, display, size);
  }
  // `epsray render` in base mode (Whitted, every pixel traced) of the scene's view or of
  // frame `frame` of `path`.
  png render(const std::string& path = "", int frame = 0, const char* size = "160x120") {
    std::vector<std::string> args{"render", scene, "--mode", "base", "--size", size, "--png", "ref.png", "--quiet"};
    if (!path.empty()) args.insert(args.end(), {"--path", path, "--frame", std::to_string(frame)});
    const proc_result r = run_epsray(args, dir, "");
    EXPECT_EQ(r.code, 0) << r;
    return read_png(dir.file("ref.png"));
  }
};

TEST_F(ViewerXvfb, ScreenshotsShowTheFrameEachDisplayAndTheHud) {
  EPSRAY_START_XVFB(x);
  const proc_result r = play(
      "hud off\nrefine\nscreenshot image.png\n"
      "mode reasons\nscreenshot reasons.png\n"
      "press Tab\nscreenshot paths.png\n"
      "press Tab\npress Tab\npress F1\nscreenshot hud.png hud\n",
      x.display(), "160x120", {"--plain-frames", "off"});  // the cells' paths are what it shows
  ASSERT_EQ(r.code, 0) << r;

  // The image within epsilon of Whitted, pixel for pixel.
  const png image = read_png(dir.file("image.png"));
  const png whitted = render();
  ASSERT_EQ(image.width, 160);
  ASSERT_EQ(image.height, 120);
  EXPECT_LE(max_difference(image, whitted), byte_tolerance(eps));

  // The error-coded image holds only the legend's colours; the paths display only the paths'
  // colours, with pixels that were not traced among them.
  const std::set<rgb8> reason_colours(reason_bytes().begin(), reason_bytes().end());
  const png reasons = read_png(dir.file("reasons.png"));
  const png paths = read_png(dir.file("paths.png"));
  int not_traced = 0;
  for (int y = 0; y < 120; ++y)
    for (int px = 0; px < 160; ++px) {
      const unsigned char* c = reasons.at(px, y);
      ASSERT_TRUE(reason_colours.count(rgb8{c[0], c[1], c[2]})) << "reasons pixel " << px << "," << y;
      const unsigned char* p = paths.at(px, y);
      const auto is = [&](int i) { return std::equal(p, p + 3, path_colours[size_t(i)].begin()); };
      ASSERT_TRUE(is(0) || is(1) || is(2)) << "paths pixel " << px << "," << y;
      not_traced += is(0) || is(1);
    }
  EXPECT_GT(not_traced, 100);

  // F1 brings the hidden HUD back as the full panel, over most of so small a window.
  int differing = 0;
  max_difference(read_png(dir.file("hud.png")), image, &differing);
  EXPECT_GT(differing, 160 * 120 / 10);
}

TEST_F(ViewerXvfb, CellsDisplayOutlinesThePickedObjectsCells) {
  EPSRAY_START_XVFB(x);
  // The middle of shapes.nff's view is an object drawn with interpolants at this size.
  const proc_result r = play("refine\npick 0.5 0.5\nframes 1\nscreenshot cells.png\n", x.display(), "320x240");
  ASSERT_EQ(r.code, 0) << r;
  const png cells = read_png(dir.file("cells.png"));
  const png whitted = render("", 0, "320x240");
  ASSERT_EQ(cells.width, 320);
  // Everything but the picked object is dimmed; the object shows its cells, outlined in
  // near-black where neighbouring pixels fall in different cells.
  int dimmed = 0, outline_near_middle = 0;
  for (int y = 0; y < 240; ++y)
    for (int px = 0; px < 320; ++px) {
      const unsigned char* c = cells.at(px, y);
      const unsigned char* w = whitted.at(px, y);
      dimmed += int(c[0]) + int(c[1]) + int(c[2]) + 60 < int(w[0]) + int(w[1]) + int(w[2]);
      const bool dark = c[0] <= 40 && c[1] <= 40 && c[2] <= 40;
      outline_near_middle += dark && std::abs(px - 160) < 30 && std::abs(y - 120) < 30;
    }
  EXPECT_GT(dimmed, 320 * 240 / 2);
  EXPECT_GT(outline_near_middle, 10);
}

TEST_F(ViewerXvfb, RecordedAndPlayedPathsMatchRenderAndWalk) {
  EPSRAY_START_XVFB(x);
  test::write_file(dir.file("play.path"),
                   "0 3.2 7  0 0.6 0  0 1 0  40\n"
                   "1 3 6.5  0 0.6 0  0 1 0  40\n"
                   "2 2.8 6  0 0.6 0  0 1 0  38\n");
  const proc_result r = play(
      "press P\nkey W 3\ndrag 30 -10\nkey D 2\npress P\nrefine\nscreenshot moved.png\n"
      "press L\nframes 3\nrefine\nscreenshot played.png\n",
      x.display(), "160x120", {"--record", "rec.path", "--path", "play.path"});
  ASSERT_EQ(r.code, 0) << r;

  // One camera per frame rendered while recording: 3 + 1 + 2, the last one on screen.
  const camera_path rec = load_camera_path(dir.file("rec.path"));
  ASSERT_EQ(rec.frames.size(), 6u);
  EXPECT_GT(glm::length(rec.frames[5].from - vec3(0, 3.2f, 7)), 0.05f) << "the camera moved";
  EXPECT_LE(max_difference(read_png(dir.file("moved.png")), render("rec.path", 5)), byte_tolerance(eps));
  // Playing ends on the path's last camera.
  EXPECT_LE(max_difference(read_png(dir.file("played.png")), render("play.path", 2)), byte_tolerance(eps));
}

TEST_F(ViewerXvfb, ScreenshotFlagSavesTheRefinedFrameAndExits) {
  EPSRAY_START_XVFB(x);
  const proc_result r = view({"--screenshot", "shot.png"}, x.display(), "640x480");
  ASSERT_EQ(r.code, 0) << r;
  const png shot = read_png(dir.file("shot.png"));
  ASSERT_EQ(shot.width, 640);
  ASSERT_EQ(shot.height, 480);
  // The HUD is on, but the screenshot is the picture alone: every pixel within epsilon.
  EXPECT_LE(max_difference(shot, render("", 0, "640x480")), byte_tolerance(eps));
}

// At 640x480: a default screenshot is the picture, which is what the window shows with the
// HUD hidden; the compact HUD keeps to a band at the top; the full panel fits in the window.
TEST_F(ViewerXvfb, CompactHudIsABandAndTheFullPanelFits) {
  EPSRAY_START_XVFB(x);
  const proc_result r = play(
      "refine\nscreenshot plain.png\nscreenshot compact.png hud\n"
      "press F1\nscreenshot full.png hud\npress H\nscreenshot hidden.png hud\n",
      x.display(), "640x480");
  ASSERT_EQ(r.code, 0) << r;
  const png plain = read_png(dir.file("plain.png"));
  ASSERT_EQ(plain.width, 640);
  ASSERT_EQ(plain.height, 480);
  EXPECT_LE(max_difference(plain, render("", 0, "640x480")), byte_tolerance(eps)) << "no HUD pixels";
  EXPECT_EQ(max_difference(read_png(dir.file("hidden.png")), plain), 0) << "H hides everything";

  const overlay_area compact = differing_area(read_png(dir.file("compact.png")), plain);
  EXPECT_GT(compact.pixels, 2000) << "the compact HUD is drawn";
  EXPECT_LE(compact.y1, 480 * 12 / 100) << "within a band at the top";
  EXPECT_LT(compact.x1, 640 - 4) << "not cut at the right";

  const overlay_area full = differing_area(read_png(dir.file("full.png")), plain);
  EXPECT_GT(full.rows, compact.rows * 3) << "F1 shows the full panel";
  EXPECT_LT(full.x1, 640 - 4) << "not cut at the right";
  EXPECT_LT(full.y1, 480 - 4) << "not cut at the bottom";
}

// The reasons and paths displays say what their colours mean, below the compact HUD.
TEST_F(ViewerXvfb, DiagnosticDisplaysShowALegend) {
  EPSRAY_START_XVFB(x);
  const proc_result r = play(
      "refine\nscreenshot image.png hud\nmode reasons\nscreenshot reasons.png\nscreenshot reasons-hud.png hud\n"
      "mode paths\nscreenshot paths.png\nscreenshot paths-hud.png hud\n",
      x.display(), "640x480");
  ASSERT_EQ(r.code, 0) << r;
  const png image_hud = read_png(dir.file("image.png"));
  const overlay_area none = differing_area(image_hud, render("", 0, "640x480"));
  EXPECT_EQ(none.pixels_in(0, 480 / 2, 640, 480), 0) << "the image display has no legend";
  for (const char* mode : {"reasons", "paths"}) {
    const std::string name = mode;
    const overlay_area legend =
        differing_area(read_png(dir.file(name + "-hud.png")), read_png(dir.file(name + ".png")));
    EXPECT_GT(legend.pixels_in(0, 480 / 2, 640, 480), 1000) << mode << ": a legend along the bottom";
    EXPECT_LT(legend.x1, 640 - 4) << mode << ": not cut at the right";
  }
}

// With nothing picked the cells display dims the whole image and says how to pick; once an
// object is picked the hint goes.
TEST_F(ViewerXvfb, CellsDisplayHintsUntilAnObjectIsPicked) {
  EPSRAY_START_XVFB(x);
  const proc_result r = play(
      "refine\nmode cells\nframes 1\nscreenshot none.png\nscreenshot none-hud.png hud\n"
      "pick 0.5 0.5\nframes 1\nscreenshot picked.png\nscreenshot picked-hud.png hud\n",
      x.display(), "640x480");
  ASSERT_EQ(r.code, 0) << r;
  const png none = read_png(dir.file("none.png"));
  const png whitted = render("", 0, "640x480");
  ASSERT_EQ(none.width, 640);
  int dimmed = 0;
  for (int y = 0; y < 480; ++y)
    for (int px = 0; px < 640; ++px) {
      const unsigned char *c = none.at(px, y), *w = whitted.at(px, y);
      dimmed += int(c[0]) + int(c[1]) + int(c[2]) + 60 < int(w[0]) + int(w[1]) + int(w[2]);
    }
  EXPECT_GT(dimmed, 640 * 480 / 2) << "nothing picked: everything dimmed";
  // The middle of the window, where the hint goes (and where the picked object lies).
  const auto middle = [](const overlay_area& o) { return o.pixels_in(320 - 60, 240 - 12, 320 + 60, 240 + 12); };
  EXPECT_GT(middle(differing_area(read_png(dir.file("none-hud.png")), none)), 200) << "the hint is drawn";
  EXPECT_EQ(middle(differing_area(read_png(dir.file("picked-hud.png")), read_png(dir.file("picked.png")))), 0)
      << "no hint once an object is picked";
}

// A budget far below one frame's working set evicts between every pair of frames; the
// refined frame is still the Whitted image within epsilon.
TEST_F(ViewerXvfb, TinyMemoryBudgetStillGivesTheFrameWithinEpsilon) {
  EPSRAY_START_XVFB(x);
  const proc_result r =
      play("frames 8\nrefine\nframes 4\nscreenshot shot.png\n", x.display(), "320x240", {"--memory-mb", "1"});
  ASSERT_EQ(r.code, 0) << r;
  const png shot = read_png(dir.file("shot.png"));
  ASSERT_EQ(shot.width, 320);
  EXPECT_LE(max_difference(shot, render("", 0, "320x240")), byte_tolerance(eps));
}

}  // namespace
}  // namespace epsray
