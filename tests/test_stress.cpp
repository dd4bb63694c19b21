// stress: build/epsray walks the failure scenes of scenes/stress/ (issue 8) along the camera
// paths of scenes/stress/paths/ with --verify, and holds every frame to the guarantee: exit 0,
// zero pixels over epsilon, max_rel_err <= eps, every PFM value finite, the pixel counts adding
// up; and to the fallback the case is there for (the teleport frames are not span-filled, the
// camera inside a glass box traces every pixel, --eps 1e-6 traces nearly everything, ...).
// Renders are small (128x96, 7 to 9 frames): the suite also runs under ASan+UBSan.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "test_process.h"

namespace epsray {
namespace {

using test::proc_result;
using test::temp_dir;
namespace fs = std::filesystem;

fs::path stress_dir() { return fs::path(EPSRAY_SOURCE_DIR) / "scenes" / "stress"; }

// A PFM file (whitted.md 7) read independently of the engine's reader: header, then
// little-endian floats, rows bottom to top (the order does not matter here).
struct pfm {
  int w = 0, h = 0, channels = 0;
  std::vector<float> v;
};

bool read_pfm_file(const std::string& path, pfm& out, std::string& why) {
  const std::string s = test::read_file(path);
  std::istringstream in(s);
  std::string magic;
  double scale = 0;
  in >> magic >> out.w >> out.h >> scale;
  if (magic != "PF" && magic != "Pf") return why = "bad magic '" + magic + "'", false;
  if (!(scale < 0)) return why = "not little-endian (scale " + std::to_string(scale) + ")", false;
  out.channels = magic == "PF" ? 3 : 1;
  in.get();  // the single whitespace byte after the scale
  const size_t at = size_t(in.tellg()), n = size_t(out.w) * size_t(out.h) * size_t(out.channels);
  if (out.w <= 0 || out.h <= 0 || s.size() != at + 4 * n)
    return why = "size " + std::to_string(s.size()) + " does not match the header", false;
  out.v.resize(n);
  std::memcpy(out.v.data(), s.data() + at, 4 * n);  // the test machines are little-endian
  return true;
}

struct frame_stats {
  std::uint64_t fast = 0, interp = 0, base = 0;
  std::uint64_t deferred = 0;  // of fast and interp: with per-pixel shadow or secondary rays
  double max_rel_err = 0;
  std::uint64_t violations = 0;
  std::uint64_t all() const { return fast + interp + base; }
  double share_fast() const { return double(fast) / double(all()); }
  double share_base() const { return double(base) / double(all()); }
};

struct walk_result {
  std::vector<frame_stats> frames;
  std::vector<pfm> images;
  std::uint64_t fast = 0, interp = 0, base = 0, deferred = 0;
  double share(std::uint64_t n) const { return double(n) / double(fast + interp + base); }
};

struct walk_case {
  std::string scene, path, mode = "full";
  std::string size = "128x96";
  double eps = 0.05;
  int frames = 0;  // expected number of frames
  int min_cell_pixels = 0;  // > 0: --min-cell-pixels (finer cells: more pixels interpolated)
  fs::path scene_dir = stress_dir(), path_dir = stress_dir() / "paths";
  // More flags for the walk. Plain frames off: the walks test the accelerated paths, which
  // plain frames (object_gate.h) would leave on scenes whose cells save little.
  std::vector<std::string> flags = {"--plain-frames", "off"};
};

class Stress : public testing::Test {
 protected:
  temp_dir work, io;

  // Runs `epsray walk` on the case and checks what holds for every stress walk; the stats and
  // the frames come back for the case's own checks.
  walk_result walk(const walk_case& c) {
    walk_result res;
    std::ostringstream eps;
    eps << c.eps;
    std::vector<std::string> argv{EPSRAY_BINARY,
                                        "walk",
                                        (c.scene_dir / c.scene).string(),
                                        "--path",
                                        (c.path_dir / c.path).string(),
                                        "--mode",
                                        c.mode,
                                        "--eps",
                                        eps.str(),
                                        "--size",
                                        c.size,
                                        "--verify",
                                        "--stats",
                                        "stats.json",
                                        "--out-dir",
                                        "frames",
                                        "--pfm",
                                        "--quiet"};
    if (c.min_cell_pixels > 0) argv.insert(argv.end(), {"--min-cell-pixels", std::to_string(c.min_cell_pixels)});
    argv.insert(argv.end(), c.flags.begin(), c.flags.end());
    const proc_result r = test::run_process(argv, work.path(), test::environment(), io, 240);
    EXPECT_TRUE(r.exited && r.code == 0) << c.scene << " " << c.path << ": " << r;
    if (!r.exited || r.code != 0) return res;

    const nlohmann::json j = nlohmann::json::parse(test::read_file(work.file("stats.json")));
    EXPECT_EQ(j["mode"], c.mode);
    EXPECT_NEAR(j["eps"].get<double>(), c.eps, 1e-6 * c.eps);
    const int w = j["size"][0], h = j["size"][1];
    EXPECT_EQ(int(j["frames"].size()), c.frames);
    for (const auto& f : j["frames"]) {
      const int k = f["index"];
      SCOPED_TRACE("frame " + std::to_string(k));
      frame_stats s;
      s.fast = f["pixels"]["fast"], s.interp = f["pixels"]["interp"], s.base = f["pixels"]["base"];
      s.deferred = f["deferred_pixels"];
      EXPECT_EQ(s.all(), std::uint64_t(w) * std::uint64_t(h)) << "every pixel is counted once";
      EXPECT_LE(s.deferred, s.fast + s.interp) << "only fast and interpolated pixels defer";
      // The thread time of the pixels that cast per-pixel rays is part of fast + interp's.
      const double deferred_ms = f["deferred_ms"], fi_ms = double(f["path_ms"]["fast"]) + double(f["path_ms"]["interp"]);
      EXPECT_GE(deferred_ms, 0.0);
      EXPECT_LE(deferred_ms, fi_ms * (1 + 1e-9) + 1e-9);
      if (s.deferred == 0) {
        EXPECT_EQ(deferred_ms, 0.0);
      }
      if (c.mode == "interp") {
        EXPECT_EQ(s.fast, 0u) << "no span filling without reprojection";
      }
      EXPECT_TRUE(f.contains("verify")) << "--verify must report every frame";
      if (f.contains("verify")) {
        // A NaN or infinite error would not be a JSON number.
        EXPECT_TRUE(f["verify"]["max_rel_err"].is_number()) << f["verify"];
        s.max_rel_err = f["verify"]["max_rel_err"].is_number() ? f["verify"]["max_rel_err"].get<double>() : INFINITY;
        s.violations = f["verify"]["violations"];
        EXPECT_EQ(s.violations, 0u) << "pixels over eps " << c.eps;
        EXPECT_LE(s.max_rel_err, c.eps);
        EXPECT_GE(s.max_rel_err, 0.0);
      }
      res.fast += s.fast, res.interp += s.interp, res.base += s.base, res.deferred += s.deferred;
      res.frames.push_back(s);

      char name[32];
      std::snprintf(name, sizeof name, "frame_%04d.pfm", k);
      pfm img;
      std::string why;
      EXPECT_TRUE(read_pfm_file(work.file(std::string("frames/") + name), img, why)) << name << ": " << why;
      EXPECT_EQ(img.w, w);
      EXPECT_EQ(img.h, h);
      size_t bad = 0, first_bad = 0;
      for (size_t i = 0; i < img.v.size(); ++i)
        if (!std::isfinite(img.v[i]) && bad++ == 0) first_bad = i;
      EXPECT_EQ(bad, 0u) << name << ": non-finite value at float " << first_bad;
      res.images.push_back(std::move(img));
    }
    return res;
  }
};

// Pixels of the behind.nff sphere's orange (1, 0.5, 0.1): red well above blue. Nothing else in
// that scene is (wall and floor are grey, the occluder blue).
int orange_pixels(const pfm& img) {
  int n = 0;
  for (size_t i = 0; i + 2 < img.v.size(); i += 3) n += img.v[i] > 0.15f && img.v[i] > 3 * img.v[i + 2];
  return n;
}

// --- grazing angles ---------------------------------------------------------------------------

TEST_F(Stress, GrazingSmoothFull) {
  const walk_result r = walk({"grazing.nff", "smooth.path", "full", "128x96", 0.05, 9});
  for (const frame_stats& f : r.frames) EXPECT_GT(f.base, 0u) << "the horizon and the edge-on wall are traced";
}

// At 128x96 with the default cell size the grazing floor is all traced; finer cells at
// 192x144 get the interpolants onto the floor near the horizon.
TEST_F(Stress, GrazingSmoothFullFineCells) {
  const walk_result r = walk({"grazing.nff", "smooth.path", "full", "192x144", 0.05, 9, 2});
  EXPECT_GT(r.share(r.fast + r.interp), 0.03);
}

TEST_F(Stress, GrazingFastTurnFull) { walk({"grazing.nff", "fast-turn.path", "full", "128x96", 0.05, 8}); }

TEST_F(Stress, GrazingTeleportInterp) { walk({"grazing.nff", "teleport.path", "interp", "128x96", 0.05, 7}); }

// --- glass with total internal reflection -------------------------------------------------------

TEST_F(Stress, TirGlassSmoothFull) {
  const walk_result r = walk({"tir-glass.nff", "smooth.path", "full", "128x96", 0.05, 9});
  // The glass covers about a sixth of the frame and the rest interpolates (the checker's
  // dark squares too, since textured cells are split until both squares pass).
  for (const frame_stats& f : r.frames) EXPECT_GE(f.share_base(), 0.12) << "the glass is mostly traced";
  EXPECT_GT(r.fast, 0u) << "the wall and floor are span-filled";
}

TEST_F(Stress, TirGlassBackwardsFull) { walk({"tir-glass.nff", "backwards.path", "full", "128x96", 0.05, 9}); }

TEST_F(Stress, TirGlassTeleportInterp) {
  const walk_result r = walk({"tir-glass.nff", "teleport.path", "interp", "128x96", 0.05, 7});
  // Glass pixels are traced, or interpolate only their surface's own terms and trace their
  // reflected and transmitted rays per pixel (deferred). One viewpoint sees only the
  // checkered wall, which interpolates whole (textures are looked up per pixel).
  EXPECT_EQ(r.frames[3].interp, r.frames[3].all());
  EXPECT_GE(r.share(r.base + r.deferred), 0.3) << "the glass is mostly traced";
}

// --- sub-pixel objects ----------------------------------------------------------------------------

TEST_F(Stress, SubpixelSmoothFull) {
  const walk_result r = walk({"subpixel.nff", "smooth.path", "full", "128x96", 0.05, 9});
  EXPECT_GT(r.share(r.fast + r.interp), 0.2) << "the wall between the tiny objects is interpolated";
}

TEST_F(Stress, SubpixelBackwardsFull) { walk({"subpixel.nff", "backwards.path", "full", "128x96", 0.05, 9}); }

TEST_F(Stress, SubpixelFastTurnInterp) { walk({"subpixel.nff", "fast-turn.path", "interp", "128x96", 0.05, 8}); }

// --- very shiny highlights ------------------------------------------------------------------------

TEST_F(Stress, ShinySmoothFull) {
  const walk_result r = walk({"shiny.nff", "smooth.path", "full", "128x96", 0.05, 9});
  EXPECT_GE(r.share(r.base), 0.5) << "the highlights are traced";
}

TEST_F(Stress, ShinyTeleportFull) { walk({"shiny.nff", "teleport.path", "full", "128x96", 0.05, 7}); }

// --- many lights ----------------------------------------------------------------------------------

TEST_F(Stress, ManyLightsSmoothFull) { walk({"many-lights.nff", "smooth.path", "full", "128x96", 0.05, 9}); }

TEST_F(Stress, ManyLightsTeleportInterp) {
  walk({"many-lights.nff", "teleport.path", "interp", "128x96", 0.05, 7});
}

// --- an object moving into view from behind another ----------------------------------------------

TEST_F(Stress, BehindSmoothFull) {
  const walk_result r = walk({"behind.nff", "smooth.path", "full", "128x96", 0.05, 9});
  ASSERT_EQ(r.images.size(), 9u);
  EXPECT_EQ(orange_pixels(r.images.front()), 0) << "the sphere is hidden in the first frame";
  EXPECT_GT(orange_pixels(r.images.back()), 40) << "and in view in the last";
  EXPECT_GT(r.share(r.fast), 0.15) << "the wall and floor are span-filled from the last frame";
}

TEST_F(Stress, BehindSmoothInterp) { walk({"behind.nff", "smooth.path", "interp", "128x96", 0.05, 9}); }

TEST_F(Stress, BehindBackwardsFull) {
  const walk_result r = walk({"behind.nff", "backwards.path", "full", "128x96", 0.05, 9});
  // Backing away, every frame sees a border the last one did not: never all span-filled.
  // The last view covers 79-88% of each new one at the look-at point's depth; cells carried
  // from it may hold lines beyond it (the wall's and the floor's own facepairs give cells a
  // wide spread of directions), so more than that may be fast (92% in frames 7 and 8).
  for (size_t k = 1; k < r.frames.size(); ++k) EXPECT_LT(r.frames[k].share_fast(), 0.97) << "frame " << k;
}

// --- fast turns and teleports (full mode: what reprojection may carry) ---------------------------

TEST_F(Stress, BehindFastTurnFull) {
  const walk_result r = walk({"behind.nff", "fast-turn.path", "full", "128x96", 0.05, 8});
  // A 25-degree turn leaves about half of a 52-degree-wide view outside the last frame.
  // Cells carried from it may still hold lines beyond it (the wall's and the floor's own
  // facepairs give cells a wide spread of directions), so somewhat more than half may be
  // span-filled, every pixel verified; not most of the view. (The pillar's faces' own cells,
  // world::face_prims, took frame 6 from 69% to 75%: cap 0.8.)
  for (size_t k = 1; k < r.frames.size(); ++k) EXPECT_LT(r.frames[k].share_fast(), 0.8) << "frame " << k;
}

TEST_F(Stress, BehindTeleportFull) {
  const walk_result r = walk({"behind.nff", "teleport.path", "full", "128x96", 0.05, 7});
  // Frames 1..5 jump to views unrelated to the last one: almost nothing may be span-filled.
  for (size_t k = 1; k + 1 < r.frames.size(); ++k) EXPECT_LT(r.frames[k].share_fast(), 0.1) << "frame " << k;
  for (const frame_stats& f : r.frames) EXPECT_GT(f.base + f.interp, 0u);
}

// --- the camera inside an object, and on a surface ------------------------------------------------

TEST_F(Stress, InsideSmoothFull) {
  const walk_result r = walk({"inside.nff", "smooth.path", "full", "128x96", 0.05, 9});
  for (const frame_stats& f : r.frames) EXPECT_GE(f.share_base(), 0.4) << "the enclosure is seen from inside";
}

TEST_F(Stress, InsideTeleportFull) {
  const walk_result r = walk({"inside.nff", "teleport.path", "full", "128x96", 0.05, 7});
  ASSERT_EQ(r.frames.size(), 7u);
  // Frame 4 looks out from inside the glass box: every eye ray's first hit is the box seen
  // from inside, which no interpolant holds.
  EXPECT_EQ(r.frames[4].base, r.frames[4].all());
}

TEST_F(Stress, OnSurfaceSmoothFull) {
  const walk_result r = walk({"on-surface.nff", "smooth.path", "full", "128x96", 0.05, 9});
  for (const frame_stats& f : r.frames) EXPECT_GT(f.base, 0u);
}

TEST_F(Stress, OnSurfaceSmoothFullFineCells) {
  const walk_result r = walk({"on-surface.nff", "smooth.path", "full", "192x144", 0.05, 9, 2});
  EXPECT_GT(r.share(r.interp), 0.05) << "the objects above and below the plane are interpolated";
}

TEST_F(Stress, OnSurfaceFastTurnFull) { walk({"on-surface.nff", "fast-turn.path", "full", "128x96", 0.05, 8}); }

TEST_F(Stress, OnSurfaceBackwardsInterp) {
  walk({"on-surface.nff", "backwards.path", "interp", "128x96", 0.05, 9});
}

// --- extreme scales ---------------------------------------------------------------------------------

TEST_F(Stress, TinyScaleSmoothFull) { walk({"tiny-scale.nff", "tiny-smooth.path", "full", "128x96", 0.05, 9}); }

TEST_F(Stress, TinyScaleTeleportFull) {
  walk({"tiny-scale.nff", "tiny-teleport.path", "full", "128x96", 0.05, 7});
}

TEST_F(Stress, TinyScaleBackwardsInterp) {
  walk({"tiny-scale.nff", "tiny-backwards.path", "interp", "128x96", 0.05, 9});
}

TEST_F(Stress, TinyScaleSmoothFullFineCells) {
  walk({"tiny-scale.nff", "tiny-smooth.path", "full", "192x144", 0.05, 9, 2});
}

TEST_F(Stress, HugeScaleSmoothFullFineCells) {
  walk({"huge-scale.nff", "huge-smooth.path", "full", "192x144", 0.05, 9, 2});
}

TEST_F(Stress, HugeScaleSmoothFull) { walk({"huge-scale.nff", "huge-smooth.path", "full", "128x96", 0.05, 9}); }

TEST_F(Stress, HugeScaleTeleportFull) {
  walk({"huge-scale.nff", "huge-teleport.path", "full", "128x96", 0.05, 7});
}

TEST_F(Stress, HugeScaleBackwardsInterp) {
  walk({"huge-scale.nff", "huge-backwards.path", "interp", "128x96", 0.05, 9});
}

// --- epsilon extremes -------------------------------------------------------------------------------

// --eps 1e-6: no interpolant can prove that bound (float rounding alone is larger), so nearly
// every pixel falls back to the base tracer; still zero violations.
TEST_F(Stress, TinyEpsBehindSmoothFull) {
  const walk_result r = walk({"behind.nff", "smooth.path", "full", "128x96", 1e-6, 9});
  EXPECT_GE(r.share(r.base), 0.99);
}

TEST_F(Stress, TinyEpsTirGlassTeleportInterp) {
  const walk_result r = walk({"tir-glass.nff", "teleport.path", "interp", "128x96", 1e-6, 7});
  EXPECT_GE(r.share(r.base), 0.99);
}

// --eps 10: a relative error of 1000% is allowed (whitted.md 6: |La - Lw| <= eps max(Lw, 1/255));
// the interpolants are used at least as much as at 0.05, and the bound still holds.
TEST_F(Stress, HugeEpsBehindSmoothFull) {
  const walk_result r = walk({"behind.nff", "smooth.path", "full", "128x96", 10, 9});
  EXPECT_GT(r.share(r.fast + r.interp), 0.4);
}

TEST_F(Stress, HugeEpsSubpixelSmoothInterp) {
  const walk_result r = walk({"subpixel.nff", "smooth.path", "interp", "128x96", 10, 9});
  EXPECT_GT(r.share(r.interp), 0.2);
}

TEST_F(Stress, HugeEpsShinyTeleportFull) { walk({"shiny.nff", "teleport.path", "full", "128x96", 10, 7}); }

// --- random scenes ------------------------------------------------------------------------------

// scenes/random/: scenes nobody wrote (tools/random-scene.py --count 8 --seed 5 --hard 0.3
// --paths), each with its own path (an orbit closing in, then two fast turns). Every
// primitive kind, mirrors, glass both ways of ior, textures, coloured lights, transforms, and
// the hard cases: coplanar polygons, nested glass, a light inside glass or just above a disk,
// slivers, interpenetrating solids, a plane seen edge on. The bound must hold on them as on
// the cases above.
class RandomScene : public Stress, public testing::WithParamInterface<int> {
 protected:
  walk_case at(const std::string& mode, double eps, int min_cell_pixels = 0) const {
    char name[32];
    std::snprintf(name, sizeof name, "random-s5-%02d", GetParam());
    const fs::path dir = fs::path(EPSRAY_SOURCE_DIR) / "scenes" / "random";
    return {std::string(name) + ".nff", std::string(name) + ".path", mode, "128x96", eps, 10, min_cell_pixels, dir, dir};
  }
};

TEST_P(RandomScene, FullHoldsTheBound) {
  walk_case gated = at("full", 0.05);  // with the object gate and plain frames, which may trace
  gated.flags = {};                      // a scene whose cells do not pay
  walk(gated);
  // Every object keeping its cells, so that the accelerated paths are tested on every scene.
  walk_case all = at("full", 0.05);
  all.flags = {"--object-gate", "off"};
  const walk_result r = walk(all);
  EXPECT_GT(r.fast + r.interp, 0u) << "some pixels take the accelerated paths, or the scene tests nothing";
}

TEST_P(RandomScene, InterpHoldsTheBoundAtSmallEps) { walk(at("interp", 0.01)); }

TEST_P(RandomScene, FullHoldsTheBoundWithFineCells) { walk(at("full", 0.2, 1)); }

INSTANTIATE_TEST_SUITE_P(Seed5, RandomScene, testing::Range(0, 8));

}  // namespace
}  // namespace epsray
