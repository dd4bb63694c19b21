// engine/baselines: the alternatives the speed-against-accuracy suite compares with. Each
// must be what it claims (a degenerate setting equals the base tracer exactly), deterministic
// for any thread count, and finite.
#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

#include "baselines/upsample.h"
#include "scene/camera.h"
#include "sched/frame_render.h"
#include "test_util.h"

namespace epsray {
namespace {

using test::same_pixels;

// A lit room corner: a glossy sphere, a box, a textured floor, two lights.
const char* scene_text =
    "b 0.1 0.1 0.2\n"
    "v\nfrom 0 -5 2\nat 0 0 0.8\nup 0 0 1\nangle 50\nhither 0.1\nresolution 64 48\n"
    "l 3 -3 5\nl -3 -1 4 0.5 0.5 0.5\n"
    "f 0.8 0.8 0.8 0.7 0.2 20 0 1\n"
    "texture checker 1 1 1  0.3 0.3 0.3  1 1\n"
    "p 4\n-4 -4 0\n4 -4 0\n4 4 0\n-4 4 0\n"
    "texture none\n"
    "f 0.9 0.3 0.2 0.6 0.5 60 0.3 1\n"
    "s 0 0 1 0.8\n"
    "f 0.2 0.5 0.9 0.8 0.1 10 0 1\n"
    "box 1.2 -0.5 0  2 0.3 1.2\n";

bool all_finite(const image& im) {
  for (const glm::vec3& p : im.pixels)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return false;
  return true;
}

// A short walk in one mode: the frames' images, rendered with `threads` workers.
std::vector<frame_result> walk(const world& w, render_mode mode, int threads, int frames, float step,
                               void (*knob)(frame_params&) = nullptr) {
  workers pool(threads);
  auto trees = std::make_unique<linetree_set>(w.prim_bounds, 0);
  reprojection_state carried;
  frame_params fp;
  fp.mode = mode;
  fp.trees = trees.get();
  fp.reproj = &carried;
  if (knob) knob(fp);
  std::vector<frame_result> out;
  for (int k = 0; k < frames; ++k) {
    camera_view v = w.sc.view;
    v.from += glm::vec3(step * float(k), 0, 0);
    out.push_back(render_frame(pool, w, make_camera(v, 64, 48), fp));
  }
  return out;
}

image base_image(const world& w, float x_offset) {
  workers pool(2);
  camera_view v = w.sc.view;
  v.from += glm::vec3(x_offset, 0, 0);
  frame_params fp;
  return render_frame(pool, w, make_camera(v, 64, 48), fp).img;
}

TEST(Upsample, ReducedCameraLooksTheSameWay) {
  const world w = test::world_from_text(scene_text);
  const camera cam = make_camera(w.sc.view, 64, 48);
  const camera low = reduced_camera(cam, 4);
  EXPECT_EQ(low.width, 16);
  EXPECT_EQ(low.height, 12);
  // Full pixel x looks where low pixel (x - 31.5) / 4 + 7.5 does (centres about the axis).
  for (float x : {0.0f, 17.0f, 33.5f, 63.0f}) {
    for (float y : {0.0f, 23.5f, 47.0f}) {
      const glm::vec3 a = eye_direction(cam, x, y), b = eye_direction(low, (x - 31.5f) / 4 + 7.5f, (y - 23.5f) / 4 + 5.5f);
      EXPECT_NEAR(glm::dot(a, b), 1.0f, 1e-6f) << x << " " << y;
    }
  }
}

TEST(Upsample, FactorOneIsTheBaseTracer) {
  const world w = test::world_from_text(scene_text);
  auto frames = walk(w, render_mode::upsample, 2, 1, 0, [](frame_params& p) { p.upsample = 1; });
  EXPECT_TRUE(same_pixels(frames[0].img, base_image(w, 0)));
}

TEST(Upsample, TracesOnlyTheReducedFrame) {
  const world w = test::world_from_text(scene_text);
  auto frames = walk(w, render_mode::upsample, 2, 1, 0, [](frame_params& p) { p.upsample = 4; });
  EXPECT_EQ(frames[0].pixels.base, 16u * 12u);
  EXPECT_EQ(frames[0].rays.eye, 16u * 12u);
  EXPECT_TRUE(all_finite(frames[0].img));
  EXPECT_FALSE(same_pixels(frames[0].img, base_image(w, 0)));
}

TEST(Reuse, AgeZeroIsTheBaseTracer) {
  const world w = test::world_from_text(scene_text);
  auto frames = walk(w, render_mode::reuse, 2, 3, 0.05f, [](frame_params& p) { p.reuse_age = 0; });
  for (int k = 0; k < 3; ++k) {
    EXPECT_TRUE(same_pixels(frames[size_t(k)].img, base_image(w, 0.05f * float(k)))) << "frame " << k;
    EXPECT_EQ(frames[size_t(k)].pixels.fast, 0u);
  }
}

TEST(Reuse, StillCameraReusesEveryHitPixelUnchanged) {
  const world w = test::world_from_text(scene_text);
  auto frames = walk(w, render_mode::reuse, 2, 2, 0, [](frame_params& p) { p.reuse_age = 8; });
  EXPECT_EQ(frames[0].pixels.fast, 0u);
  // Every pixel that saw a surface lands on itself again; only the background is traced,
  // which casts no shadow or secondary rays.
  EXPECT_GT(frames[1].pixels.fast, 64u * 48u / 2);
  EXPECT_EQ(frames[1].rays.eye, frames[1].pixels.base);
  EXPECT_EQ(frames[1].rays.shadow + frames[1].rays.reflect + frames[1].rays.refract, 0u);
  EXPECT_TRUE(same_pixels(frames[1].img, frames[0].img));
}

TEST(Reuse, MovingCameraGoesStaleWithoutNoticing) {
  const world w = test::world_from_text(scene_text);
  auto frames = walk(w, render_mode::reuse, 2, 4, 0.15f, [](frame_params& p) { p.reuse_age = 100; });
  EXPECT_GT(frames[3].pixels.fast, 0u);
  EXPECT_TRUE(all_finite(frames[3].img));
  // No error control: highlights and reflections are carried from the old eye.
  EXPECT_FALSE(same_pixels(frames[3].img, base_image(w, 0.45f)));
}

TEST(LightField, InterpolatesWithoutAskingThePredicate) {
  const world w = test::world_from_text(scene_text);
  auto frames = walk(w, render_mode::lightfield, 2, 1, 0, [](frame_params& p) { p.lf_depth = 4; });
  EXPECT_GT(frames[0].pixels.interp, 0u);
  EXPECT_TRUE(all_finite(frames[0].img));
  // Discontinuities (shadow edges, the checker) are interpolated across.
  EXPECT_FALSE(same_pixels(frames[0].img, base_image(w, 0)));
}

TEST(Baselines, IdenticalForOneTwoEightThreads) {
  const world w = test::world_from_text(scene_text);
  for (render_mode m : {render_mode::upsample, render_mode::reuse, render_mode::lightfield}) {
    auto knob = [](frame_params& p) { p.upsample = 3, p.reuse_age = 3, p.lf_depth = 3; };
    auto one = walk(w, m, 1, 4, 0.1f, knob), two = walk(w, m, 2, 4, 0.1f, knob), eight = walk(w, m, 8, 4, 0.1f, knob);
    for (size_t k = 0; k < one.size(); ++k) {
      EXPECT_TRUE(same_pixels(one[k].img, two[k].img)) << mode_name(m) << " frame " << k;
      EXPECT_TRUE(same_pixels(one[k].img, eight[k].img)) << mode_name(m) << " frame " << k;
      EXPECT_EQ(one[k].pixels.fast, eight[k].pixels.fast);
      EXPECT_EQ(one[k].pixels.interp, eight[k].pixels.interp);
      EXPECT_EQ(one[k].pixels.base, eight[k].pixels.base);
    }
  }
}

}  // namespace
}  // namespace epsray
