// A pixel's error allowance spent down its ray tree (shade/whitted.h, shade/radiance_bound.h):
// the radiance range of each depth holds every ray the tracer can send, and a pixel traced
// under its allowance stays within eps of the reference while casting fewer rays.
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "scene/camera.h"
#include "scene/nff.h"
#include "shade/surface.h"
#include "shade/texture.h"
#include "shade/whitted.h"
#include "test_util.h"

namespace epsray {
namespace {

using test::uniform;
using test::unit_vec;

world scene_file(const std::string& path) { return make_world(load_scene(path)); }

std::string artroom() { return std::string(EPSRAY_SOURCE_DIR) + "/scenes/artroom.nff"; }

// Rays from anywhere in the scene's box (and a little beyond) in every direction, at every depth.
void expect_rays_within_range(const world& w, int rays, unsigned seed) {
  std::mt19937 g(seed);
  const vec3 lo = w.box.lo - 0.1f * w.box.extent(), hi = w.box.hi + 0.1f * w.box.extent();
  int outside = 0;
  for (int i = 0; i < rays; ++i) {
    const vec3 o{uniform(g, lo.x, hi.x), uniform(g, lo.y, hi.y), uniform(g, lo.z, hi.z)};
    const ray r = make_ray(o, unit_vec(g));
    for (int d = 1; d <= max_depth; ++d) {
      trace_state st;
      const vec3 L = radiance(w, r, d, st);
      for (int c = 0; c < 3; ++c) {
        if (L[c] >= w.rad.lo[d][c] && L[c] <= w.rad.hi[d][c]) continue;
        if (++outside <= 5)
          ADD_FAILURE() << "ray " << i << " depth " << d << " channel " << c << ": " << L[c] << " outside ["
                        << w.rad.lo[d][c] << ", " << w.rad.hi[d][c] << "]";
      }
    }
  }
  EXPECT_EQ(outside, 0);
}

TEST(RadianceRange, HoldsEveryRayOfTheArtRoom) {
  const world w = scene_file(artroom());
  for (int d = 1; d <= max_depth; ++d) {
    EXPECT_TRUE(std::isfinite(w.rad.hi[d].x)) << d;
    EXPECT_GE(w.rad.lo[d].x, 0.0f) << d;
    EXPECT_LT(w.rad.lo[d].x, w.rad.hi[d].x) << d;
  }
  // Deeper rays have fewer bounces left below them: their range can only shrink.
  for (int d = 1; d < max_depth; ++d) EXPECT_GE(w.rad.hi[d].x, w.rad.hi[d + 1].x) << d;
  expect_rays_within_range(w, 3000, 7);
}

TEST(RadianceRange, HoldsEveryRayOfGeneratedAndSpdScenes) {
  for (const char* name : {"random-s5-00", "random-s5-03"})
    expect_rays_within_range(scene_file(std::string(EPSRAY_SOURCE_DIR) + "/scenes/random/" + name + ".nff"), 800, 3);
  EPSRAY_REQUIRE_SPD("mount-s4");
  expect_rays_within_range(scene_file(test::spd_scene("mount-s4").string()), 800, 5);
}

TEST(RadianceRange, TexturesAndTheBackgroundWidenIt) {
  const std::string view = "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nresolution 8 8\n";
  const world plain =
      test::world_from_text(view + "b 0.5 0.5 0.5\nl 0 5 0 0.2 0.2 0.2\nf 1 1 1 0.5 0 0 0 1\ns 0 0 0 1\n");
  // A miss gives the background at any depth, so it lies in every range.
  for (int d = 1; d <= max_depth; ++d) {
    EXPECT_LE(plain.rad.lo[d].x, 0.5f) << d;
    EXPECT_GE(plain.rad.hi[d].x, 0.5f) << d;
  }
  const world textured = test::world_from_text(
      view + "b 0.5 0.5 0.5\nl 0 5 0 0.2 0.2 0.2\nf 1 1 1 0.5 0 0 0 1\ntexture checker 2 2 2 0.1 0.1 0.1 1 1\n"
      "s 0 0 0 1\n");
  EXPECT_GT(textured.rad.hi[1].x, plain.rad.hi[1].x);
}

struct pixel_check {
  int over = 0, pixels = 0, differ = 0;
  ray_counts exact, within;
};

// Every pixel of a small view: shade_within against shade_hit, the reference.
pixel_check check_view(const world& w, const camera& cam, float eps) {
  pixel_check out;
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      const ray r = eye_ray(w, cam, eye_direction(cam, float(x), float(y)));
      hit h;
      if (!closest_hit(w, r, INFINITY, h)) continue;
      ++out.pixels;
      trace_state ref, acc;
      const vec3 Lw = shade_hit(w, r, h, 1, ref);
      const vec3 La = shade_within(w, r, h, eps, acc);
      EXPECT_EQ(acc.error_left, nullptr);
      out.exact += ref.counts, out.within += acc.counts;
      out.differ += La != Lw;
      for (int c = 0; c < 3; ++c) {
        const float e = std::fabs(La[c] - Lw[c]) / std::max(Lw[c], 1.0f / 255);
        if (!(e <= eps) && ++out.over <= 5)
          ADD_FAILURE() << "pixel " << x << "," << y << " channel " << c << ": error " << e << " over eps " << eps;
      }
    }
  return out;
}

TEST(Allowance, ArtRoomPixelsStayWithinEpsAndCastFewerRays) {
  const world w = scene_file(artroom());
  const camera cam = make_camera(w.sc.view, 80, 60);
  for (float eps : {0.01f, 0.05f, 0.2f, 0.5f}) {
    const pixel_check pc = check_view(w, cam, eps);
    EXPECT_EQ(pc.over, 0) << "eps " << eps;
    EXPECT_GT(pc.pixels, 4000);
    EXPECT_LE(pc.within.total(), pc.exact.total()) << "eps " << eps;
    if (eps >= 0.2f) {
      EXPECT_GT(pc.within.shadow_bounded, pc.within.shadow / 10) << "eps " << eps;
      EXPECT_LT(pc.within.shadow, pc.exact.shadow * 9 / 10) << "eps " << eps;
    }
  }
  // A vanishing allowance bounds nothing: the reference's radiance bit for bit, its rays.
  const pixel_check tiny = check_view(w, cam, 1e-7f);
  EXPECT_EQ(tiny.differ, 0);
  EXPECT_EQ(tiny.within.total(), tiny.exact.total());
  // Just above it, nothing the pixel would notice: secondary rays are all traced.
  const pixel_check small = check_view(w, cam, 2e-5f);
  EXPECT_EQ(small.over, 0);
  EXPECT_EQ(small.within.secondary_bounded, 0u);
  EXPECT_EQ(small.within.reflect + small.within.refract, small.exact.reflect + small.exact.refract);
}

TEST(Allowance, GlassAndMirrorsOfSpdScenesStayWithinEps) {
  EPSRAY_REQUIRE_SPD("mount-s4");
  for (const char* name : {"mount-s4", "balls-s3"}) {
    const world w = scene_file(test::spd_scene(name).string());
    const camera cam = make_camera(w.sc.view, 64, 64);
    for (float eps : {0.05f, 0.3f}) {
      const pixel_check pc = check_view(w, cam, eps);
      EXPECT_EQ(pc.over, 0) << name << " eps " << eps;
      EXPECT_LT(pc.within.total(), pc.exact.total()) << name << " eps " << eps;
    }
  }
}

// A faintly polished floor under a matt room: at a large eps the floor's reflection is
// taken at the middle of the depth-2 range, with no reflected ray at all.
TEST(Allowance, AWeakReflectionIsBoundedWithoutItsRay) {
  const world w = test::world_from_text(
      "b 0.05 0.05 0.05\nambient 0.2 0.2 0.2\n"
      "v\nfrom 0 1.5 5\nat 0 0.5 0\nup 0 1 0\nangle 50\nresolution 40 30\n"
      "l -2 3 2 0.4 0.4 0.4\nl 2 3 -1 0.4 0.4 0.4\n"
      "f 0.9 0.9 0.9 0.8 0.02 20 0 1\n"
      "p 4\n-5 0 -5\n-5 0 5\n5 0 5\n5 0 -5\n"
      "f 0.7 0.6 0.5 0.8 0 0 0 1\n"
      "s 0 0.8 -1 0.8\n");
  const camera cam = make_camera(w.sc.view, 40, 30);
  const pixel_check loose = check_view(w, cam, 0.3f), tight = check_view(w, cam, 0.002f);
  EXPECT_EQ(loose.over + tight.over, 0);
  EXPECT_GT(loose.within.secondary_bounded, 300u);
  EXPECT_LT(loose.within.reflect, loose.exact.reflect / 2);
  EXPECT_EQ(tight.within.secondary_bounded, 0u);
  EXPECT_EQ(tight.within.reflect, tight.exact.reflect);
}

// A reflected hit's deferred lights under a pixel's allowance, as a mirror cell takes them
// (reproject/mirror.cpp): in units of a term of weight k, the pixel's radiance and error
// divided by k. The weighted sum is then off from the exact one by no more than k times
// what the allowance says it spent, and that stays within the pixel's own room; with no
// allowance (eps 0), the exact sum, up to the rounding of fused multiply-adds.
TEST(Allowance, WeightedDeferredLightsChargeWhatTheySkip) {
  const world w = scene_file(artroom());
  const camera cam = make_camera(w.sc.view, 48, 36);
  const std::uint32_t all = (1u << std::min(w.light_pos.size(), size_t(max_deferred_lights))) - 1;
  int skipped = 0, checked = 0;
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      const ray r = eye_ray(w, cam, eye_direction(cam, float(x), float(y)));
      hit h;
      if (!closest_hit(w, r, INFINITY, h)) continue;
      const surface sf = surface_at(w, h.prim, r, h.t);
      const material& m = w.sc.materials[size_t(w.info[size_t(h.prim)].material)];
      const vec3 T = m.texture >= 0 ? sample_texture(w.sc.textures[size_t(m.texture)], surface_uv(w, h.prim, sf.p))
                                    : vec3(1);
      trace_state ref;
      const vec3 exact = deferred_terms(w, r, h, sf, T, all, 0, nullptr, ref);
      const vec3 known{0.4f, 0.3f, 0.2f}, err{0.002f};  // the pixel so far
      for (float k : {0.08f, 0.5f}) {
        for (float eps : {0.0f, 0.05f, 0.2f}) {
          trace_state st;
          error_allowance allow{known / k, err / k, eps};
          const vec3 L = deferred_terms(w, r, h, sf, T, all, 0, nullptr, st, &allow);
          const vec3 room = error_room(known, err, eps);
          ++checked;
          skipped += int(st.counts.shadow_bounded);
          for (int c = 0; c < 3; ++c) {
            const float tol = 1e-6f * (1 + exact[c]);
            if (eps == 0) {
              EXPECT_NEAR(L[c], exact[c], tol) << x << "," << y;
            }
            EXPECT_LE(k * std::fabs(L[c] - exact[c]), k * allow.spent[c] + tol)
                << x << "," << y << " k " << k << " eps " << eps;
            EXPECT_LE(k * allow.spent[c], room[c] + tol) << x << "," << y << " k " << k << " eps " << eps;
          }
        }
      }
    }
  EXPECT_GT(checked, 3000);
  EXPECT_GT(skipped, 500) << "a loose allowance skips shadow rays";
}

}  // namespace
}  // namespace epsray
