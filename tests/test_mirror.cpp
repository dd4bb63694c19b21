// Planar reflections through the mirrored eye (engine/reproject/mirror.h): the mirrored
// camera looks along the reflected rays, the reflector and what lies behind its plane are
// never a cell's candidates, and a walk whose floor reflections come from reprojected mirror
// cells stays within epsilon, with an occluder sweeping through the reflected view, for
// any thread count.
#include <gtest/gtest.h>

#include "reproject/mirror.h"
#include "sched/frame_render.h"
#include "sched/verify.h"
#include "test_util.h"
#include "test_walk.h"

namespace epsray {
namespace {

// A polished floor, a lit back wall with a coloured panel, a sphere on the floor, and a
// small red ball that the camera's slide carries across the sphere's reflection.
const char* floor_scene = R"(
v
from 0 1.2 6
at 0 0.6 0
up 0 1 0
angle 45
hither 0.01
resolution 64 48
l 2 4 4
l -3 3 2 0.4 0.4 0.5
f 0.9 0.9 0.85 0.6 0.3 20 0 1
p 4
-8 0 -4
8 0 -4
8 0 8
-8 0 8
f 0.8 0.75 0.7 0.9 0 0 0 1
p 4
-8 0 -3
8 0 -3
8 5 -3
-8 5 -3
f 0.2 0.4 0.9 0.9 0 0 0 1
p 4
-1 0.5 -2.95
1 0.5 -2.95
1 2 -2.95
-1 2 -2.95
f 0.9 0.7 0.2 0.7 0.2 20 0 1
s 0 0.8 -1 0.8
f 0.9 0.1 0.1 0.8 0 0 0 1
s 0.6 0.4 1.2 0.15
)";

// The world's index of the scene's primitive k (the world keeps its own order).
int world_prim(const world& w, int k) {
  for (size_t i = 0; i < w.scene_prims; ++i)
    if (w.info[i].source == k) return int(i);
  return -1;
}

TEST(Mirror, MirroredCameraLooksAlongTheReflectedRays) {
  const world w = test::world_from_text(floor_scene);
  const camera cam = make_camera(w.sc.view, 64, 48);
  const mirror_view m = choose_mirror(w, cam);
  ASSERT_EQ(m.reflector, world_prim(w, 0)) << "the floor covers most of the image";
  EXPECT_FLOAT_EQ(m.n.y, 1.0f);
  EXPECT_NEAR(m.cam.origin.y, -1.2f, 1e-6f);
  for (int y = 0; y < 48; y += 7)
    for (int x = 0; x < 64; x += 9) {
      const glm::vec3 d = eye_direction(cam, float(x), float(y)), dm = eye_direction(m.cam, float(x), float(y));
      const glm::vec3 r = d - 2 * glm::dot(d, m.n) * m.n;
      EXPECT_LT(glm::length(dm - r), 1e-5f) << x << "," << y;
    }
  // The reflected line of a pixel that sees the floor passes through the eye box.
  const glm::vec3 d = eye_direction(cam, 32, 40);
  ASSERT_LT(d.y, 0);
  const glm::vec3 p = cam.origin + (-cam.origin.y / d.y) * d;
  const glm::vec3 o = p + w.delta * m.n, r = d - 2 * glm::dot(d, m.n) * m.n;
  const glm::vec3 back = o - (glm::length(p - cam.origin)) * r;
  for (int i = 0; i < 3; ++i) {
    EXPECT_GE(back[i], m.eye_box.lo[i]);
    EXPECT_LE(back[i], m.eye_box.hi[i]);
  }
}

TEST(Mirror, NoReflectorWithoutAPolishedPlane) {
  world w = test::world_from_text(floor_scene);
  w.sc.materials[size_t(w.info[size_t(world_prim(w, 0))].material)].ks = 0;
  EXPECT_EQ(choose_mirror(w, make_camera(w.sc.view, 64, 48)).reflector, -1);
}

TEST(Mirror, WhatLiesOnOrBehindThePlaneIsBehindIt) {
  const world w = test::world_from_text(floor_scene);
  const mirror_view m = choose_mirror(w, make_camera(w.sc.view, 64, 48));
  EXPECT_TRUE(behind_mirror(m, bounds{{-1, -2, -1}, {1, 0, 1}}));
  EXPECT_FALSE(behind_mirror(m, bounds{{-1, -2, -1}, {1, 0.01f, 1}}));
  EXPECT_TRUE(behind_mirror(m, w.prim_bounds[size_t(world_prim(w, 0))])) << "the floor itself";
  EXPECT_FALSE(behind_mirror(m, w.prim_bounds[size_t(world_prim(w, 1))])) << "the back wall stands on it";
}

struct mirror_walk {
  std::vector<image> frames;
  std::uint64_t filled = 0, looked_up = 0;
};

mirror_walk walk(const world& w, int threads, bool verify, float eps = 0.05f) {
  frame_params p;
  p.mode = render_mode::full;
  p.interp.eps = eps;
  p.interp.mirror = true, p.interp.plain_frames = false;
  mirror_walk out;
  for (frame_result& fr : test::verified_walk(w, p, 10, threads, verify, [&](int k) {
         camera_view v = w.sc.view;
         v.from.x -= 0.12f * float(k);
         return make_camera(v, 96, 72);
       })) {
    out.filled += fr.mirror_filled, out.looked_up += fr.mirror_looked_up;
    out.frames.push_back(std::move(fr.img));
  }
  return out;
}

TEST(Mirror, WalkWithReprojectedReflectionsStaysWithinEps) {
  const world w = test::world_from_text(floor_scene);
  const mirror_walk m = walk(w, 2, true);
  EXPECT_GT(m.filled, 500u) << "reflections come from reprojected mirror cells";
  EXPECT_GT(m.looked_up, 0u);
}

// A loose epsilon lets the mirror cells' deferred lights skip shadow rays under the
// pixel's allowance: what they skip must be charged to the pixel's error.
TEST(Mirror, WalkAtALooseEpsilonStaysWithinEps) {
  const world w = test::world_from_text(floor_scene);
  const mirror_walk m = walk(w, 2, true, 0.2f);
  EXPECT_GT(m.filled, 500u);
}

TEST(Mirror, WalkIgnoresThreadCount) {
  const world w = test::world_from_text(floor_scene);
  const mirror_walk a = walk(w, 1, false);
  for (int threads : {2, 8}) {
    const mirror_walk b = walk(w, threads, false);
    ASSERT_EQ(a.frames.size(), b.frames.size());
    for (size_t k = 0; k < a.frames.size(); ++k)
      EXPECT_TRUE(test::same_pixels(a.frames[k], b.frames[k])) << threads << " threads, frame " << k;
    EXPECT_EQ(a.filled, b.filled);
    EXPECT_EQ(a.looked_up, b.looked_up);
  }
}

}  // namespace
}  // namespace epsray
