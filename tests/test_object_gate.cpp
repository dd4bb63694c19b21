// The object gate (engine/interp/object_gate.h): an object whose cells cost more than they
// save, by counts of rays and pixels, is traced for the next frames and tried again later;
// what it decides depends on counts alone, so a walk's images do not depend on threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "interp/object_gate.h"
#include "sched/frame_render.h"
#include "sched/verify.h"
#include "test_util.h"
#include "test_walk.h"

namespace epsray {
namespace {

TEST(ObjectGate, GainIsSavedRaysLessWhatThePathsAndBuildsCost) {
  gate_tally t;
  t.fast = 10, t.span = 20, t.interp = 5, t.saved = 140, t.own = 30, t.traced = 4, t.traced_rays = 20;
  const gate_weights wt;
  const double paths = wt.fast * 10 + wt.span * 20 + wt.interp * 5 + wt.failed_lookup * 4;
  EXPECT_DOUBLE_EQ(gate_gain(t, false), 140 - 30 - paths);
  t.builds = 2;  // a corner line costs what a traced pixel of the object does: (140 + 20) / 39 rays
  EXPECT_DOUBLE_EQ(gate_gain(t, false), 140 - 30 - paths) << "a resting camera keeps its cells: builds are free";
  EXPECT_DOUBLE_EQ(gate_gain(t, true), 140 - 30 - paths - 16 * wt.corner_share * (160.0 / 39) * 2);
}

TEST(ObjectGate, LosingObjectIsTracedThenTriedAgainLaterEachTime) {
  object_gate g;
  g.resize(3);
  const float px[3] = {100, 100, 100};  // each object's box on screen, in pixels
  gate_entry losing{1, {}}, paying{2, {}};
  losing.t.fast = 100, losing.t.saved = 300, losing.t.own = 295;  // saves 5 rays, costs 60: -0.55 a pixel
  gate_entry close{0, {}};
  close.t.fast = 100, close.t.saved = 300, close.t.own = 290;  // -0.5 a pixel: within the margin
  paying.t.span = 100, paying.t.saved = 400;
  g.update({losing, paying, close}, false, px);
  EXPECT_FALSE(g.off(0, 100)) << "a loss within gate_margin keeps the cells";
  EXPECT_TRUE(g.off(1, 100));
  EXPECT_FALSE(g.off(2, 100));
  EXPECT_TRUE(g.off(1, 400)) << "four times larger on screen: still off";
  EXPECT_FALSE(g.off(1, 401)) << "more: tried again at once";
  EXPECT_EQ(g.objects_off(), 1u);
  // Off for 8 frames, in which nothing of it is counted; then tried again.
  for (int k = 0; k < 7; ++k) {
    g.update({paying}, true, px);
    EXPECT_TRUE(g.off(1, 100)) << k;
  }
  g.update({paying}, true, px);
  EXPECT_FALSE(g.off(1, 100));
  // Losing again: off for 16 frames this time.
  g.update({losing}, true, px);
  int frames_off = 0;
  while (g.off(1, 100)) g.update({}, true, px), ++frames_off;
  EXPECT_EQ(frames_off, 16);
  // The entries of one object are summed before the decision: two halves that pay together.
  gate_entry half_a{0, {}}, half_b{0, {}};
  half_a.t.fast = 10, half_a.t.saved = 40, half_a.t.own = 40;  // alone: -6
  half_b.t.span = 100, half_b.t.saved = 100;                    // +90
  g.update({half_a, half_b}, false, px);
  EXPECT_FALSE(g.off(0, 100));
}

TEST(ObjectGate, FramesGoPlainWhileCellsSaveUnderAFifthOfABaseFramesRays) {
  object_gate g;
  g.resize(2);
  const float px[2] = {100, 100};
  gate_entry paying{0, {}}, losing{1, {}};
  paying.t.span = 10, paying.t.saved = 31;                       // gains 30 rays
  losing.t.fast = 50, losing.t.saved = 100, losing.t.own = 100;  // turned off: its loss is not the frame's
  // 30 saved against 60 cast: a third of a base frame's rays (60 + 30).
  g.update({paying, losing}, false, px, 60);
  EXPECT_TRUE(g.off(1, 100));
  EXPECT_FALSE(g.plain()) << "the objects still on saved over a fifth";
  g.update({paying}, false, px, 120);  // 30 / 150: a fifth exactly
  EXPECT_FALSE(g.plain());
  g.update({paying}, false, px, 125);  // 30 / 155 = 0.19: 8 plain frames
  for (int k = 0; k < 8; ++k) {
    EXPECT_TRUE(g.plain()) << k;
    g.plain_done(0, 0);
  }
  EXPECT_FALSE(g.plain());
  // Low again: 16 plain frames; a frame at or over the share ends the doubling.
  g.update({paying}, false, px, 200);
  int frames = 0;
  while (g.plain()) g.plain_done(0, 0), ++frames;
  EXPECT_EQ(frames, 16);
  g.update({paying}, false, px, 60);
  EXPECT_FALSE(g.plain()) << "cells that pay keep their frames";
  g.update({paying}, false, px, 200);
  frames = 0;
  while (g.plain()) g.plain_done(0, 0), ++frames;
  EXPECT_EQ(frames, 8);
  g.update({paying}, false, px, 0);
  EXPECT_FALSE(g.plain()) << "no rays given: no plain frames";
}

TEST(ObjectGate, PlainFramesKeepTheAllowanceWhereItBoundsEnough) {
  object_gate g;
  g.resize(1);
  EXPECT_TRUE(g.plain_allowance()) << "tried first";
  g.plain_done(20, 80);  // a fifth of the rays bounded: kept
  EXPECT_TRUE(g.plain_allowance());
  g.plain_done(5, 95);  // 5%: its checks cost more than the rays they save
  for (int k = 0; k < 8; ++k) {
    EXPECT_FALSE(g.plain_allowance()) << k;
    g.plain_done(0, 0);
  }
  EXPECT_TRUE(g.plain_allowance()) << "tried again after 8 exact plain frames";
}

TEST(ObjectGate, ProbeOfAViewWithNoCountsSendsItPlainWhenItsCellsWouldNotPay) {
  object_gate g;
  g.resize(2);
  const float px[2] = {100, 100};
  gate_entry paying{0, {}}, losing{1, {}};
  paying.t.span = 10, paying.t.saved = 31;                       // gains 30 rays
  losing.t.fast = 50, losing.t.saved = 100, losing.t.own = 100;  // loses 30 + 50 x 0.6
  EXPECT_TRUE(g.probe_due()) << "a first frame has no counts";
  EXPECT_FALSE(g.probe({paying, losing}, 60, 0, 0)) << "30 of 90: cells";
  EXPECT_FALSE(g.plain());
  EXPECT_FALSE(g.off(1, 100)) << "a probe turns no object off: its few pixels judge the frame only";
  EXPECT_TRUE(g.probe_due()) << "only a frame counted in full ends the probing";
  g.update({paying, losing}, false, px, 60);
  EXPECT_FALSE(g.probe_due());
  EXPECT_TRUE(g.off(1, 100));
  g.update({paying}, false, px, 200);  // 30 of 230: 8 plain frames
  for (int k = 0; k < 8; ++k) {
    EXPECT_TRUE(g.plain()) << k;
    g.plain_done(0, 0);
  }
  EXPECT_TRUE(g.probe_due()) << "after plain frames the view is new again";
  // The probe judges as update does, builds aside, with the objects that lost left out.
  EXPECT_TRUE(g.probe({paying, losing}, 125, 20, 80)) << "30 of 155";
  EXPECT_TRUE(g.plain_allowance()) << "the allowance bounded a fifth of the probe's rays";
  int frames = 0;
  while (g.plain()) g.plain_done(0, 0), ++frames;
  EXPECT_EQ(frames, 16) << "a probe's plain frames double as update's do";
  gate_tally built = paying.t;
  built.builds = 100;  // what a probe pixel's own cells cost is not charged
  EXPECT_FALSE(g.probe({gate_entry{0, built}}, 60, 0, 0));
  EXPECT_TRUE(g.probe({paying}, 200, 5, 95));
  EXPECT_FALSE(g.plain_allowance()) << "5% bounded: the plain frames trace exactly";
}

// A matte wall that its cells serve well, and before it a large glass sphere, whose cells
// fail or leave its refraction of the wall's squares to per-pixel rays while their
// corner lines carry the refraction chains: they cost more than they save.
const char* glass_scene = R"(
v
from 0 0.5 6
at 0 0.5 0
up 0 1 0
angle 40
hither 0.01
resolution 64 48
l 2 4 6
f 0.8 0.8 0.75 0.9 0 0 0 1
p 4
-6 -3 -2
6 -3 -2
6 5 -2
-6 5 -2
f 0.2 0.3 0.9 0.9 0 0 0 1
p 4
-1.5 -0.5 -1.9
-0.5 -0.5 -1.9
-0.5 0.5 -1.9
-1.5 0.5 -1.9
f 0.9 0.2 0.2 0.9 0 0 0 1
p 4
0.5 0.5 -1.9
1.5 0.5 -1.9
1.5 1.5 -1.9
0.5 1.5 -1.9
f 1 1 1 0.05 0.1 30 0.9 1.5
s 0 0.5 1 1.3
)";

// The glass sphere seen from close by: almost every pixel is the sphere's, whose cells do
// not pay, so once it is gated the cells left save under plain_gain rays a pixel.
std::string close_glass_scene() {
  std::string s = glass_scene;
  s.replace(s.find("from 0 0.5 6"), 12, "from 0 0.5 3.2");
  return s;
}

struct gated_walk {
  std::vector<image> frames;
  std::vector<std::uint64_t> off;
  std::vector<int> plain;
  std::vector<std::uint64_t> probe;  // the probe's pixels, per frame
  std::uint64_t fast = 0, base = 0;
  std::uint64_t eye_rays = 0;  // frames 1 on: the visibility rays and the builds' corner lines
};

gated_walk walk(const world& w, int frames, int threads, bool gate, bool verify, tile_order order,
               bool plain_frames = true) {
  frame_params p;
  p.mode = render_mode::full;
  p.interp.object_gate = gate;
  p.interp.plain_frames = plain_frames;
  p.order = order;
  gated_walk out;
  int k = 0;
  for (frame_result& fr : test::verified_walk(w, p, frames, threads, verify, [&](int i) {
         camera_view v = w.sc.view;
         v.from.x += 0.08f * float(i), v.at.x += 0.08f * float(i);
         return make_camera(v, 96, 72);
       })) {
    out.off.push_back(fr.objects_off);
    out.plain.push_back(fr.plain);
    out.probe.push_back(fr.probe_pixels);
    out.fast += fr.pixels.fast, out.base += fr.pixels.base;
    if (k++ > 0) out.eye_rays += fr.rays.eye;
    out.frames.push_back(std::move(fr.img));
  }
  return out;
}

TEST(ObjectGate, GlassSphereIsTracedWhileTheWallKeepsItsCellsWithinEps) {
  // Plain frames off: this is the object gate's own choice (the walls' cells save about a
  // fifth of the frame's rays here, where plain frames may take over). One thread, tiles in
  // scan order: which pixel reaches a cell first, and so which corner lines the shared
  // samples already hold, follows the tile order, which the costly-first order takes from
  // the last frame's clocks, and with more threads two may both build a cell; either moves
  // the eye-ray count by more than the gate saves in this small scene (about 40 lines).
  // Images and the gate's choices do not depend on them (GatedWalkIgnoresThreadCountAndTileOrder).
  const world w = test::world_from_text(glass_scene);
  const gated_walk on = walk(w, 12, 1, true, true, tile_order::scan, false);
  const gated_walk off = walk(w, 12, 1, false, false, tile_order::scan);
  std::uint64_t most = 0;
  for (std::uint64_t n : on.off) most = std::max(most, n);
  EXPECT_GE(most, 1u) << "the glass sphere's cells do not pay: it is traced for a while";
  for (std::uint64_t n : off.off) EXPECT_EQ(n, 0u) << "--object-gate off traces nothing for the gate";
  EXPECT_GT(on.fast, off.fast / 2) << "the walls keep their cells";
  EXPECT_LT(on.eye_rays, off.eye_rays) << "no lines are traced for the gated sphere's cells";
}

TEST(ObjectGate, CloseGlassGoesPlainWithinEps) {
  const world w = test::world_from_text(close_glass_scene());
  const gated_walk on = walk(w, 16, 2, true, true, tile_order::costly_first);
  int plain = 0;
  for (int k : on.plain) plain += k;
  EXPECT_GE(plain, 4) << "the cells serve too little: frames are traced plainly";
  size_t first = 0;
  while (first < on.plain.size() && !on.plain[first]) ++first;
  for (size_t k = first; k < std::min(on.plain.size(), first + 8); ++k)
    EXPECT_EQ(on.plain[k], 1) << "once plain, 8 frames in a row: frame " << k;
  EXPECT_EQ(on.plain[0], 0) << "the first frame's probe counts the sphere's pixels as reprojected ones";
  // A probe before each frame with cells that follows none: the first, and the one after
  // the 8 plain frames, which here finds that the cells left would not pay.
  EXPECT_GT(on.probe[0], 0u);
  for (size_t k = 1; k < first + 8 && k < on.probe.size(); ++k) EXPECT_EQ(on.probe[k], 0u) << "frame " << k;
  ASSERT_LT(first + 8, on.plain.size());
  EXPECT_GT(on.probe[first + 8], 0u);
  EXPECT_EQ(on.plain[first + 8], 1) << "probed and sent plain";
  const gated_walk off = walk(w, 12, 2, false, false, tile_order::costly_first);
  for (int k : off.plain) EXPECT_EQ(k, 0) << "--object-gate off: never plain";
}

TEST(ObjectGate, GatedWalkIgnoresThreadCountAndTileOrder) {
  for (const std::string& text : {std::string(glass_scene), close_glass_scene()}) {
    const world w = test::world_from_text(text);
    const gated_walk a = walk(w, 12, 1, true, false, tile_order::costly_first);
    for (int threads : {2, 8}) {
      const gated_walk b =
          walk(w, 12, threads, true, false, threads == 8 ? tile_order::scan : tile_order::costly_first);
      ASSERT_EQ(a.frames.size(), b.frames.size());
      for (size_t k = 0; k < a.frames.size(); ++k) {
        EXPECT_TRUE(test::same_pixels(a.frames[k], b.frames[k])) << threads << " threads, frame " << k;
        EXPECT_EQ(a.off[k], b.off[k]) << threads << " threads, frame " << k;
        EXPECT_EQ(a.plain[k], b.plain[k]) << threads << " threads, frame " << k;
        EXPECT_EQ(a.probe[k], b.probe[k]) << threads << " threads, frame " << k;
      }
    }
  }
}

}  // namespace
}  // namespace epsray
