// sched + engine/image: frames over tiles on any number of threads give bit-identical images
// and ray counts (contract.md: "The images must not depend on N"); PFM and PNG files.
#include <stb/stb_image.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include "image/image_io.h"
#include "scene/camera.h"
#include "sched/frame_render.h"
#include "sched/tiles.h"
#include "sched/topology.h"
#include "test_util.h"

namespace epsray {
namespace {

using test::same_pixels;

using test::temp_dir;

// Every primitive kind, glass, mirrors, patches, textures and three lights.
const char* builtin_scene =
    "b 0.1 0.2 0.3\n"
    "v\nfrom 1 -6 3\nat 0 0 0.6\nup 0 0 1\nangle 45\nhither 0.1\nresolution 64 48\n"
    "l 3 -3 6\n"
    "l -4 -2 3\n"
    "l 0 4 5 0.3 0.2 0.1\n"
    "f 0.9 0.9 0.9 0.6 0.4 30 0 1\n"
    "texture checker 1 1 1  0.2 0.2 0.2  1 1\n"
    "p 4\n-5 -5 0\n5 -5 0\n5 5 0\n-5 5 0\n"
    "texture none\n"
    "f 1 0.2 0.2 0.5 0.3 40 0.6 1.5\n"
    "s 0 0 1 0.9\n"
    "f 0.2 1 0.2 0.8 0.1 10 0 1\n"
    "s -1.8 0.5 0.6 -0.6\n"
    "c 1.8 0.5 0 0.5  1.8 0.5 1.5 0.2\n"
    "cc -1 2 0 0.4  -1 2 1 0.4\n"
    "f 0.3 0.3 1 0.7 0.5 50 0.2 1.2\n"
    "box 1 -2 0  2 -1.2 0.8\n"
    "disk -2 -1.5 0.3  0.3 -1 1  0.5\n"
    "push\ntranslate 0 2 1.2\nrotate 0 0 1 30\nscale 0.7\n"
    "pp 4\n-1 -1 0 0.2 0 1\n1 -1 0 0 0.2 1\n1 1 0 -0.2 0 1\n-1 1 0 0 -0.2 1\n"
    "pop\n";

void expect_same_counts(const ray_counts& a, const ray_counts& b) {
  EXPECT_EQ(a.eye, b.eye);
  EXPECT_EQ(a.reflect, b.reflect);
  EXPECT_EQ(a.refract, b.refract);
  EXPECT_EQ(a.shadow, b.shadow);
}

void expect_same_trees(const ray_tree_store& a, const ray_tree_store& b) {
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(a.node_begin, b.node_begin);
  EXPECT_EQ(a.light_begin, b.light_begin);
  EXPECT_EQ(a.lights, b.lights);
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  for (size_t i = 0; i < a.nodes.size(); ++i) {
    EXPECT_EQ(a.nodes[i].prim, b.nodes[i].prim);
    EXPECT_EQ(a.nodes[i].reflect, b.nodes[i].reflect);
    EXPECT_EQ(a.nodes[i].refract, b.nodes[i].refract);
    EXPECT_EQ(a.nodes[i].lights, b.nodes[i].lights);
  }
}

frame_result render(const world& w, int threads, int width, int height, int tile_rows = 0, bool trees = false) {
  workers pool(threads);
  frame_params fp;
  fp.tile_rows = tile_rows;
  fp.keep_ray_trees = trees;
  return render_frame(pool, w, make_camera(w.sc.view, width, height), fp);
}

void check_thread_independence(const world& w, int width, int height) {
  frame_result one = render(w, 1, width, height, 0, true);
  EXPECT_EQ(one.rays.eye, std::uint64_t(width) * std::uint64_t(height));
  EXPECT_EQ(one.pixels.base, std::uint64_t(width) * std::uint64_t(height));
  EXPECT_EQ(one.pixels.fast + one.pixels.interp, 0u);
  EXPECT_GT(one.memory_bytes, 0u);
  for (const glm::vec3& p : one.img.pixels)
    ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
  for (int threads : {2, 8}) {
    SCOPED_TRACE(threads);
    frame_result other = render(w, threads, width, height, 0, true);
    EXPECT_TRUE(same_pixels(one.img, other.img)) << "image differs with " << threads << " threads";
    expect_same_counts(one.rays, other.rays);
    expect_same_trees(one.trees, other.trees);
  }
}

TEST(Frame, BuiltinSceneIdenticalForOneTwoEightThreads) {
  world w = test::world_from_text(builtin_scene);
  frame_result fr = render(w, 1, 64, 48);
  // The scene must exercise every secondary ray kind for the test to mean much.
  EXPECT_GT(fr.rays.reflect, 0u);
  EXPECT_GT(fr.rays.refract, 0u);
  EXPECT_GT(fr.rays.shadow, 0u);
  check_thread_independence(w, 64, 48);
}

TEST(Frame, BuiltinSceneOddSizeIdenticalForOneTwoEightThreads) {
  world w = test::world_from_text(builtin_scene);
  check_thread_independence(w, 37, 23);
}

TEST(Topology, HwlocSeesThisMachine) {
  machine_topology m = discover_topology();
  EXPECT_GE(m.cores, 1);
  EXPECT_GE(m.pus, m.cores);
  EXPECT_GE(m.packages, 1);
  EXPECT_NE(m.summary().find("core"), std::string::npos) << m.summary();
}

TEST(Topology, PinnedWorkersRenderTheSameImage) {
  world w = test::world_from_text(builtin_scene);
  const camera cam = make_camera(w.sc.view, 48, 36);
  workers free_pool(2);
  frame_result a = render_frame(free_pool, w, cam, frame_params{});
  frame_result b;
  std::thread t([&] {  // pinning binds the calling thread too: keep it off the test's thread
    workers pinned_pool(2, true);
    b = render_frame(pinned_pool, w, cam, frame_params{});
    EXPECT_GE(pinned_pool.pinned(), 1) << "hwloc could not bind any thread";
  });
  t.join();
  EXPECT_TRUE(same_pixels(a.img, b.img));
}

class SpdFrame : public testing::TestWithParam<const char*> {};

TEST_P(SpdFrame, IdenticalForOneTwoEightThreads) {
  EPSRAY_REQUIRE_SPD(GetParam());
  world w = make_world(load_scene(test::spd_scene(GetParam()).string()));
  check_thread_independence(w, 96, 80);
}

INSTANTIATE_TEST_SUITE_P(Spd, SpdFrame, EPSRAY_SMALL_SPD_SCENES, test::spd_param_name);

// The repository's own scenes (scenes/*.nff, scenes/tests/*.nff): they parse, render finite,
// and do so identically on one and on eight threads.
std::vector<std::string> repo_scenes() {
  std::vector<std::string> out;
  const std::filesystem::path root = std::filesystem::path(EPSRAY_SOURCE_DIR) / "scenes";
  if (!std::filesystem::is_directory(root)) return out;
  for (const auto& e : std::filesystem::recursive_directory_iterator(root))
    if (e.is_regular_file() && e.path().extension() == ".nff") out.push_back(e.path().string());
  std::sort(out.begin(), out.end());
  return out;
}

TEST(Frame, RepositoryScenesRenderFiniteOnAnyThreadCount) {
  const std::vector<std::string> scenes = repo_scenes();
  if (scenes.empty()) GTEST_SKIP() << "no scenes/ folder";
  for (const std::string& path : scenes) {
    SCOPED_TRACE(path);
    world w = make_world(load_scene(path));
    frame_result a = render(w, 1, 40, 30), b = render(w, 8, 40, 30, 1);
    EXPECT_TRUE(same_pixels(a.img, b.img));
    expect_same_counts(a.rays, b.rays);
    for (const glm::vec3& p : a.img.pixels)
      ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && p.x >= 0 && p.y >= 0 && p.z >= 0);
    EXPECT_TRUE(a.finite && b.finite);  // each tile's own check agrees
  }
}

// The tiles' finiteness check (frame_result::finite) sees a NaN or an infinity in any
// channel of the rows it is given, and nothing outside them.
TEST(Frame, AllFiniteFindsEveryNonFiniteChannelInItsRows) {
  const float bad[] = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                       -std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::quiet_NaN()};
  image im(7, 5);
  im.at(3, 2) = glm::vec3(std::numeric_limits<float>::max(), std::numeric_limits<float>::denorm_min(), -0.0f);
  EXPECT_TRUE(all_finite(im, 0, 5));
  for (float v : bad)
    for (int c = 0; c < 3; ++c) {
      image j = im;
      j.at(6, 2)[c] = v;
      EXPECT_FALSE(all_finite(j, 0, 5));
      EXPECT_FALSE(all_finite(j, 2, 3));
      EXPECT_TRUE(all_finite(j, 0, 2));
      EXPECT_TRUE(all_finite(j, 3, 5));
      EXPECT_TRUE(all_finite(j, 2, 2));
    }
}

TEST(Frame, TileSizesGiveIdenticalImages) {
  world w = test::world_from_text(builtin_scene);
  frame_result ref = render(w, 2, 50, 41, 0, true);
  for (int rows : {1, 2, 3, 7, 40, 41, 1000}) {
    SCOPED_TRACE(rows);
    frame_result fr = render(w, 2, 50, 41, rows, true);
    EXPECT_TRUE(same_pixels(ref.img, fr.img));
    expect_same_counts(ref.rays, fr.rays);
    expect_same_trees(ref.trees, fr.trees);
  }
}

TEST(Frame, SmallestImages) {
  world w = test::world_from_text(builtin_scene);
  for (auto [width, height] : {std::pair{1, 2}, std::pair{2, 2}, std::pair{1, 9}, std::pair{9, 2}}) {
    frame_result a = render(w, 1, width, height), b = render(w, 8, width, height, 1);
    EXPECT_TRUE(same_pixels(a.img, b.img));
    EXPECT_EQ(a.rays.eye, std::uint64_t(width * height));
  }
}

TEST(Tiles, CoverEveryRowOnce) {
  for (int height : {1, 2, 7, 64, 513}) {
    for (int rows : {0, 1, 3, 8, 600}) {
      std::vector<tile> tiles = make_tiles(height, rows);
      int next = 0;
      for (const tile& t : tiles) {
        EXPECT_EQ(t.y0, next);
        EXPECT_GT(t.y1, t.y0);
        next = t.y1;
      }
      EXPECT_EQ(next, height);
    }
    for (int threads : {1, 2, 16}) {
      int r = default_tile_rows(height, threads);
      EXPECT_GE(r, 1);
      EXPECT_LE(r, 16);
    }
  }
}

TEST(TileHistory, OrdersDearestFirstAndForgetsAnotherTiling) {
  tile_history h;
  EXPECT_EQ(h.order(4, tile_order::costly_first), (std::vector<std::uint32_t>{0, 1, 2, 3})) << "no history: top to bottom";
  h.ticks = {5, 9, 1, 9};
  EXPECT_EQ(h.order(4, tile_order::costly_first), (std::vector<std::uint32_t>{1, 3, 0, 2})) << "ties keep their rows' order";
  EXPECT_EQ(h.order(4, tile_order::scan), (std::vector<std::uint32_t>{0, 1, 2, 3}));
  EXPECT_EQ(h.order(3, tile_order::costly_first), (std::vector<std::uint32_t>{0, 1, 2})) << "another tiling";
}

TEST(TileQueue, RunsEveryTileOnceOnMoreThreadsThanTiles) {
  for (int threads : {1, 3, 16}) {
    for (size_t tiles : {size_t(0), size_t(1), size_t(7), size_t(500)}) {
      SCOPED_TRACE(testing::Message() << threads << " threads, " << tiles << " tiles");
      workers pool(threads);
      std::vector<std::atomic<int>> runs(tiles);
      std::vector<std::uint32_t> order(tiles);
      for (size_t i = 0; i < tiles; ++i) order[i] = std::uint32_t(tiles - 1 - i);  // bottom to top
      const phase_times t = run_tiles(pool, order, [&](size_t i) { runs[i].fetch_add(1); });
      for (size_t i = 0; i < tiles; ++i) EXPECT_EQ(runs[i].load(), 1) << "tile " << i;
      // Each thread's waits lie within the phase.
      EXPECT_GE(t.wall_ms, 0);
      EXPECT_GE(t.join_ms, 0);
      EXPECT_GE(t.tail_ms, 0);
      EXPECT_LE(t.join_ms + t.tail_ms, t.wall_ms * 1.0001 + 1e-9);
    }
  }
}

// --- image files -----------------------------------------------------------------------------

image test_image(int width, int height) {
  image img(width, height);
  const float specials[] = {0.0f, -0.0f, 1.0f, 0.5f, 1.0f / 3.0f, 1e-30f, std::numeric_limits<float>::denorm_min(),
                            65504.0f, 3.0e38f, 0.0031308f, 2.5f, 1e-7f};
  size_t k = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x, ++k)
      img.at(x, y) = {specials[k % 12], float(x) / float(width) + 0.001f * float(y), specials[(k * 7 + 3) % 12]};
  return img;
}

TEST(ImageIo, PfmRoundTripIsExact) {
  temp_dir dir;
  const image img = test_image(13, 7);
  const std::string path = dir.file("a.pfm");
  write_pfm(img, path);
  image back = read_pfm(path);
  EXPECT_TRUE(same_pixels(img, back));
  // The header, then rows bottom to top (whitted.md 7), little-endian floats.
  const std::string bytes = test::read_file(path);
  const std::string header = "PF\n13 7\n-1.0\n";
  ASSERT_EQ(bytes.size(), header.size() + 13u * 7u * 12u);
  EXPECT_EQ(bytes.substr(0, header.size()), header);
  float first[3];
  std::memcpy(first, bytes.data() + header.size(), sizeof first);
  EXPECT_EQ(std::memcmp(first, &img.at(0, 6), sizeof first), 0) << "the first stored row is the bottom one";
  std::vector<std::string> left;
  for (const auto& e : std::filesystem::directory_iterator(dir.path())) left.push_back(e.path().filename().string());
  EXPECT_EQ(left, std::vector<std::string>{"a.pfm"}) << "no temporary file may be left behind";
}

TEST(ImageIo, PfmOfARenderedFrameRoundTrips) {
  temp_dir dir;
  world w = test::world_from_text(builtin_scene);
  frame_result fr = render(w, 2, 32, 24);
  write_pfm(fr.img, dir.file("f.pfm"));
  EXPECT_TRUE(same_pixels(fr.img, read_pfm(dir.file("f.pfm"))));
}

TEST(ImageIo, ReadPfmRejectsGarbage) {
  temp_dir dir;
  test::write_file(dir.file("bad.pfm"), "P6\n2 2\n255\nxxxxxxxxxxxx");
  EXPECT_THROW(read_pfm(dir.file("bad.pfm")), std::runtime_error);
  test::write_file(dir.file("short.pfm"), "PF\n2 2\n-1.0\n0123");
  EXPECT_THROW(read_pfm(dir.file("short.pfm")), std::runtime_error);
  EXPECT_THROW(read_pfm(dir.file("missing.pfm")), std::runtime_error);
}

TEST(ImageIo, WriteIntoMissingFolderThrowsAndWritesNothing) {
  temp_dir dir;
  const image img = test_image(4, 3);
  EXPECT_THROW(write_pfm(img, dir.file("no/such/a.pfm")), std::runtime_error);
  EXPECT_THROW(write_png(img, dir.file("no/such/a.png")), std::runtime_error);
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

TEST(ImageIo, PngHoldsTheSrgbBytes) {
  temp_dir dir;
  image img = test_image(11, 5);
  img.at(0, 0) = {-1, 0.2f, std::numeric_limits<float>::quiet_NaN()};
  const std::string path = dir.file("a.png");
  write_png(img, path);
  const std::string bytes = test::read_file(path);
  ASSERT_GE(bytes.size(), 8u);
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  int w = 0, h = 0, comp = 0;
  unsigned char* data = stbi_load(path.c_str(), &w, &h, &comp, 3);
  ASSERT_NE(data, nullptr) << stbi_failure_reason();
  EXPECT_EQ(w, 11);
  EXPECT_EQ(h, 5);
  EXPECT_EQ(comp, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c)
        EXPECT_EQ(data[(y * w + x) * 3 + c], srgb_byte(img.at(x, y)[c])) << x << "," << y << " channel " << c;
  stbi_image_free(data);
}

// whitted.md 7: clamp to [0, 1], the piecewise sRGB curve, rounded to the nearest of 8 bits.
int srgb_reference(double x) {
  x = std::clamp(x, 0.0, 1.0);
  double s = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1 / 2.4) - 0.055;
  return int(std::lround(s * 255));
}

TEST(ImageIo, SrgbByteFollowsThePiecewiseCurve) {
  EXPECT_EQ(srgb_byte(0.0f), 0);
  EXPECT_EQ(srgb_byte(1.0f), 255);
  EXPECT_EQ(srgb_byte(0.5f), 188);        // 1.055 * 0.5^(1/2.4) - 0.055 = 0.7354 -> 187.5
  EXPECT_EQ(srgb_byte(0.0031308f), 10);   // the knee: 12.92 * 0.0031308 = 0.04045 -> 10.3
  EXPECT_EQ(srgb_byte(0.0031308f), srgb_reference(0.0031308));
  EXPECT_EQ(srgb_byte(0.5f), srgb_reference(0.5));
  EXPECT_EQ(srgb_byte(0.001f), 3);        // linear part: 12.92e-3 * 255 = 3.29
  EXPECT_EQ(srgb_byte(0.21586f), 128);    // ((128/255 + 0.055) / 1.055)^2.4 = 0.21586
  EXPECT_EQ(srgb_byte(-0.5f), 0);
  EXPECT_EQ(srgb_byte(7.0f), 255);
  EXPECT_EQ(srgb_byte(std::numeric_limits<float>::infinity()), 255);
  EXPECT_EQ(srgb_byte(std::numeric_limits<float>::quiet_NaN()), 0);
  // Away from the rounding midpoints, the curve everywhere on a fine grid.
  for (int i = 0; i <= 4000; ++i) {
    double x = i / 4000.0;
    double code = (x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1 / 2.4) - 0.055) * 255;
    if (std::fabs(code - std::floor(code) - 0.5) < 1e-3) continue;
    EXPECT_EQ(int(srgb_byte(float(x))), srgb_reference(double(float(x)))) << x;
  }
  // Monotone.
  for (int i = 1; i <= 1000; ++i) EXPECT_LE(srgb_byte((i - 1) / 1000.0f), srgb_byte(i / 1000.0f));
}

}  // namespace
}  // namespace epsray

namespace epsray {
namespace {

TEST(ImageIo, SrgbLookupEqualsTheDirectCurveForEveryFloatSampled) {
  // Every float in [0, 1] whose low 8 mantissa bits are zero (~4 million values), plus
  // the neighbours of each threshold the table is built from, and values outside [0, 1].
  for (std::uint32_t bits = 0; bits <= 0x3f800000u; bits += 256) {
    float f;
    std::memcpy(&f, &bits, 4);
    ASSERT_EQ(srgb_byte(f), srgb_byte_exact(f)) << f;
  }
  for (float f : {-1.0f, -0.0f, 1.0f, 1.5f, 1e30f, std::numeric_limits<float>::quiet_NaN(),
                  std::numeric_limits<float>::infinity()})
    EXPECT_EQ(srgb_byte(f), srgb_byte_exact(f)) << f;
  for (int k = 1; k < 256; ++k) {
    // Bisect for the step to byte k and check both sides of it.
    float lo = 0, hi = 1;
    for (int i = 0; i < 64; ++i) {
      float mid = 0.5f * (lo + hi);
      (srgb_byte_exact(mid) >= k ? hi : lo) = mid;
    }
    for (float f : {std::nextafter(hi, 0.0f), hi, std::nextafter(hi, 2.0f)})
      EXPECT_EQ(srgb_byte(f), srgb_byte_exact(f)) << "near step " << k;
  }
}

}  // namespace
}  // namespace epsray
