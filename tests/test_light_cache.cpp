// The light cache (accel/light_cache.h): every shadow ray it answers gets the BVH walk's
// answer, from any scene, any surface point and any thread, rays along its cells' and
// faces' sides included; images do not change with it; it rests where its lists answer few rays.
#include <gtest/gtest.h>

#include <filesystem>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "accel/light_cache.h"
#include "scene/camera.h"
#include "scene/nff.h"
#include "shade/surface.h"
#include "test_util.h"
#include "test_walk.h"

namespace epsray {
namespace {

using test::uniform;
using test::unit_vec;

std::string source(const std::string& rel) { return std::string(EPSRAY_SOURCE_DIR) + "/" + rel; }

// A shadow ray as the tracer casts it (whitted.cpp, light_at): from a surface point lifted
// by delta along the normal facing the incoming ray, towards a light in front of it.
struct shadow_query {
  ray r;
  float dist = 0;
  size_t light = 0;
  int self = -1;  // the flat primitive it leaves, as shadow_blocker passes it
};

// Surface points hit by random rays from anywhere in the box (and random points of the box,
// on no surface), each with its shadow rays to every light in front of it.
std::vector<shadow_query> queries(const world& w, int rays, unsigned seed) {
  std::mt19937 g(seed);
  const vec3 lo = w.box.lo, hi = w.box.hi;
  std::vector<shadow_query> out;
  for (int i = 0; i < rays; ++i) {
    const vec3 o{uniform(g, lo.x, hi.x), uniform(g, lo.y, hi.y), uniform(g, lo.z, hi.z)};
    const ray r = make_ray(o, unit_vec(g));
    vec3 above = o;
    vec3 nf{0};
    int self = -1;
    hit h;
    const bool on_surface = i % 8 != 0 && closest_hit(w, r, INFINITY, h);
    if (on_surface) {
      const surface sf = surface_at(w, h.prim, r, h.t);
      nf = glm::dot(sf.ng, r.d) < 0 ? sf.ns : -sf.ns;
      above = sf.p + w.delta * nf;
      self = shadow_self(w, h.prim);
    }
    for (size_t j = 0; j < w.light_pos.size(); ++j) {
      if (on_surface) {
        const vec3 p = above - w.delta * nf;
        if (!(glm::dot(nf, safe_normalize(w.light_pos[j] - p)) > 0)) continue;  // behind: no shadow ray
      }
      const vec3 so = w.light_pos[j] - above;
      const float dist = safe_length(so);
      if (!(dist > 0)) continue;
      out.push_back({make_ray(above, so / dist), dist, j, self});
    }
  }
  return out;
}

struct agreement {
  size_t answered = 0, asked = 0;
};

// Every answer a list gives is the BVH's: lit exactly where the BVH finds no blocker, and a
// blocker the ray really meets.
agreement expect_bvh_answers(const world& w, const light_cache& lc, const std::vector<shadow_query>& qs,
                             const std::string& what) {
  agreement a;
  int wrong = 0;
  for (const shadow_query& q : qs) {
    const int got = lc.blocker(q.light, q.r, q.dist, q.self);
    ++a.asked;
    if (got == light_cache::not_listed) continue;
    ++a.answered;
    const bool bvh_blocked = first_blocker(w, q.r, q.dist) >= 0;
    float t;
    const bool real = got < 0 || hit_shape(w.shapes[size_t(got)], w.polys, q.r, q.dist, t);
    if ((got >= 0) != bvh_blocked || !real) {
      if (++wrong <= 5)
        ADD_FAILURE() << what << ": light " << q.light << " from (" << q.r.o.x << ", " << q.r.o.y << ", " << q.r.o.z
                      << "): list says " << got << ", BVH says " << (bvh_blocked ? "blocked" : "lit");
    }
  }
  EXPECT_EQ(wrong, 0) << what;
  return a;
}

TEST(LightCache, AnswersAsTheBvhDoesOnTheRepositoryScenes) {
  std::vector<std::string> scenes = {"scenes/artroom.nff", "scenes/tests/shapes.nff", "scenes/tests/glass.nff",
                                     "scenes/tests/mirror.nff"};
  for (int i = 0; i < 8; ++i) scenes.push_back("scenes/random/random-s5-0" + std::to_string(i) + ".nff");
  for (const std::string& s : scenes) {
    const world w = make_world(load_scene(source(s)));
    light_cache lc(w);
    const agreement a = expect_bvh_answers(w, lc, queries(w, 3000, 7), s);
    EXPECT_GT(a.asked, 1000u) << s;
    // Lists must answer most of them, or this test says nothing of them.
    EXPECT_GT(a.answered, a.asked / 2) << s;
  }
}

class LightCacheSpd : public testing::TestWithParam<const char*> {};

TEST_P(LightCacheSpd, AnswersAsTheBvhDoes) {
  EPSRAY_REQUIRE_SPD(GetParam());
  const world w = make_world(load_scene(test::spd_scene(GetParam()).string()));
  light_cache lc(w);
  const agreement a = expect_bvh_answers(w, lc, queries(w, 1500, 11), GetParam());
  EXPECT_GT(a.asked, 500u);
}

INSTANTIATE_TEST_SUITE_P(Scenes, LightCacheSpd,
                         testing::Values("balls-s3", "gears-s2", "mount-s4", "rings-s3", "teapot-s6", "tetra-s4"),
                         test::spd_param_name);

TEST(LightCache, ConcurrentQueriesAgreeWithTheBvh) {
  // Four threads build and read the same nodes at once (TSan runs this one).
  const world w = make_world(load_scene(source("scenes/artroom.nff")));
  light_cache lc(w);
  const std::vector<shadow_query> qs = queries(w, 1500, 3);
  std::vector<int> reference(qs.size());
  for (size_t i = 0; i < qs.size(); ++i) reference[i] = first_blocker(w, qs[i].r, qs[i].dist) >= 0;
  std::vector<int> wrong(4, 0);
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] {
      for (size_t k = 0; k < qs.size(); ++k) {
        const size_t i = (k * 7 + size_t(t) * 131) % qs.size();  // each thread its own order
        const shadow_query& q = qs[i];
        const int got = lc.blocker(q.light, q.r, q.dist, q.self);
        if (got == light_cache::not_listed) continue;
        wrong[size_t(t)] += (got >= 0) != (reference[i] != 0);
      }
    });
  }
  for (std::thread& th : threads) th.join();
  for (int t = 0; t < 4; ++t) EXPECT_EQ(wrong[size_t(t)], 0) << "thread " << t;
}

TEST(LightCache, RestsWhereItsListsAnswerFewRaysAndTriesAgain) {
  const world w = make_world(load_scene(source("scenes/tests/shapes.nff")));
  light_cache lc(w);
  EXPECT_TRUE(lc.in_use());
  lc.next_frame(true, 10000, 9000);  // lists answered 90%: kept
  EXPECT_TRUE(lc.in_use());
  lc.next_frame(true, 10000, 7000);  // under 3/4
  int rested = 0;
  while (!lc.in_use()) lc.next_frame(false, 0, 0), ++rested;
  EXPECT_EQ(rested, 8);
  lc.next_frame(true, 10000, 100);  // still few: twice as long
  rested = 0;
  while (!lc.in_use()) lc.next_frame(false, 0, 0), ++rested;
  EXPECT_EQ(rested, 16);
  lc.next_frame(true, 500, 0);  // too few rays to judge: kept
  EXPECT_TRUE(lc.in_use());
}

// Shadow rays grazing small triangles, from a light inside the scene along the sides and
// corners of its cube of directions (where the lookup picks a face by comparing equal
// magnitudes), and from a light far outside it (whose grids span a small part of one face,
// so that cells are narrow): every answer is still the BVH's, and many rays are blocked.
TEST(LightCache, RaysAlongFaceSidesAndNarrowCellsAgreeWithTheBvh) {
  for (const bool far : {false, true}) {
    std::mt19937 g(29);
    const vec3 light = far ? vec3(400, 200, 0) : vec3(0.5f, 0.25f, 0);
    std::vector<vec3> dirs;
    for (int i = 0; i < 400; ++i) {
      vec3 d = test::unit_vec(g);
      if (far) {
        d = glm::normalize(-light) + 0.006f * d;  // within about 3 of the origin at the scene
      } else {
        const int a = i % 3, b = (a + 1) % 3;
        if (i % 4 != 3) d[b] = (i % 2 ? -1.0f : 1.0f) * std::fabs(d[a]);  // |d[a]| = |d[b]|
        if (i % 8 == 1) d[(a + 2) % 3] = d[a];                                // a corner
      }
      dirs.push_back(glm::normalize(d));
    }
    const float at = far ? glm::length(light) : 4;  // the origins' distance from the light
    std::string text = "v\nfrom 9 7 8\nat 0 0 0\nup 0 1 0\nangle 40\nhither 0.01\nresolution 8 8\nb 0 0 0\nl " +
                       std::to_string(light.x) + " " + std::to_string(light.y) + " " + std::to_string(light.z) +
                       "\nf 1 1 1 1 0 0 0 0\n";
    // A small triangle across each direction, before the origins below.
    for (const vec3& d : dirs) {
      const vec3 c = light + (at + test::uniform(g, -3, -1)) * d;
      text += "p 3\n";
      for (int k = 0; k < 3; ++k) {
        const vec3 v = c + 0.03f * test::unit_vec(g);
        text += std::to_string(v.x) + " " + std::to_string(v.y) + " " + std::to_string(v.z) + "\n";
      }
    }
    const world w = test::world_from_text(text);
    light_cache lc(w);
    std::vector<shadow_query> qs;
    for (const vec3& d : dirs)
      for (int k = 0; k < 24; ++k) {
        // Origins 1-2 past the triangles along d, nudged across it by 0 or 1e-9 to 1e-2.
        const vec3 nudge = k % 9 ? std::pow(10.0f, -float(k % 8)) * 0.01f * test::unit_vec(g) : vec3(0);
        const vec3 o = light + (at + test::uniform(g, 0, 1)) * glm::normalize(d + nudge);
        const vec3 so = light - o;
        const float dist = safe_length(so);
        if (dist > 0) qs.push_back({make_ray(o, so / dist), dist, 0, -1});
      }
    const char* what = far ? "far light" : "light inside";
    // A far light sees the scene through one face: the other five hold one empty cell each.
    const size_t face = size_t(lc.resolution(0)) * size_t(lc.resolution(0));
    ASSERT_GT(face, 0u) << what;
    EXPECT_EQ(lc.cells(0), far ? face + 5 : 6 * face) << what;
    const agreement a = expect_bvh_answers(w, lc, qs, what);
    EXPECT_GT(a.answered, 9 * a.asked / 10) << what;
    size_t blocked = 0;
    for (const shadow_query& q : qs) blocked += first_blocker(w, q.r, q.dist) >= 0;
    EXPECT_GT(blocked, qs.size() / 10) << what << ": too few rays meet the triangles to test anything";
  }
}

// A far light over nested spheres: every cell that lists anything lists them all, more than
// max_list, so no buffer is kept and every ray walks the BVH.
TEST(LightCache, NoBufferWhereMostCellsAreCrowded) {
  std::string text = "v\nfrom 0 0 9\nat 0 0 0\nup 0 1 0\nangle 40\nhither 0.01\nresolution 8 8\nb 0 0 0\n"
                     "l 1000 0 0\nf 1 1 1 1 0 0 0 0\n";
  for (int i = 0; i < 2 * light_cache::max_list; ++i) text += "s 0 0 0 " + std::to_string(1 + 0.01 * i) + "\n";
  const world w = test::world_from_text(text);
  const light_cache lc(w);
  EXPECT_EQ(lc.resolution(0), 0);
  EXPECT_EQ(lc.bytes(), 0u);
  const ray r = make_ray(vec3(0, 0, 3), glm::normalize(vec3(1000, 0, -3)));
  EXPECT_EQ(lc.blocker(0, r, 1000, -1), light_cache::not_listed);
}

TEST(LightCache, NoLightsMeansNoLists) {
  const world w = test::world_from_text("v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 1\nresolution 8 8\n"
                                        "b 0 0 0\nf 1 1 1 1 0 0 0 0\ns 0 0 0 1\n");
  light_cache lc(w);
  const ray r = make_ray(vec3(0, 0, 2), vec3(0, 0, 1));
  EXPECT_EQ(lc.blocker(0, r, 1, -1), light_cache::not_listed);
  EXPECT_EQ(lc.bytes(), 0u);
}

// Full and interp walks give the same images with the cache as without, and the cache
// answers shadow rays in them.
void expect_same_walk(render_mode mode, const std::string& scene_file = source("scenes/artroom.nff")) {
  const world w = make_world(load_scene(scene_file));
  auto walk = [&](bool lists) {
    frame_params p;
    p.mode = mode;
    p.interp.light_cache = lists;
    p.interp.plain_frames = false;
    // One thread: with more, which pixel builds a cell (and so casts its corners' rays) is a race.
    return test::verified_walk(w, p, 4, 1, false, [&](int i) {
      camera_view v = w.sc.view;
      v.from.x += 0.05f * float(i), v.at.x += 0.05f * float(i);
      return make_camera(v, 120, 90);
    });
  };
  const std::vector<frame_result> with = walk(true), without = walk(false);
  std::uint64_t listed = 0;
  for (size_t k = 0; k < with.size(); ++k) {
    EXPECT_TRUE(test::same_pixels(with[k].img, without[k].img)) << "frame " << k;
    EXPECT_EQ(with[k].rays.shadow, without[k].rays.shadow) << "frame " << k;
    EXPECT_EQ(without[k].rays.shadow_asked, 0u);
    listed += with[k].rays.shadow_listed;
  }
  EXPECT_GT(listed, 0u);
}

TEST(LightCache, FullWalkImagesDoNotChange) { expect_same_walk(render_mode::full); }
TEST(LightCache, InterpWalkImagesDoNotChange) { expect_same_walk(render_mode::interp); }

// Meshes of small triangles and many lights (gears-s2: five, polygons of up to 144 vertices;
// teapot-s6: a floor whose shadow rays graze the teapot), where cells list many slots.
TEST_P(LightCacheSpd, FullWalkImagesDoNotChange) {
  EPSRAY_REQUIRE_SPD(GetParam());
  expect_same_walk(render_mode::full, test::spd_scene(GetParam()).string());
}

TEST(LightCache, BaseModeNeverAsks) {
  const world w = make_world(load_scene(source("scenes/artroom.nff")));
  frame_params p;
  p.mode = render_mode::base;
  const std::vector<frame_result> frames = test::verified_walk(w, p, 2, 2, false, [&](int) {
    return make_camera(w.sc.view, 64, 48);
  });
  for (const frame_result& fr : frames) EXPECT_EQ(fr.rays.shadow_asked, 0u);
}

}  // namespace
}  // namespace epsray
