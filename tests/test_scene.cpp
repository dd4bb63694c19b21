// engine/scene: the NFF parser with epsray's superset, the SPD light convention, transforms,
// and the camera-path parser. Every malformed input must name its exact line (whitted.md,
// contract.md: `file:line: what`).
#include <sys/stat.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "geom/shape_build.h"
#include "image/image_io.h"
#include "scene/camera.h"
#include "scene/input_error.h"
#include "scene/nff.h"
#include "scene/path_file.h"
#include "scene/line_reader.h"
#include "scene/token_reader.h"
#include "scene/camera.h"
#include "shade/whitted.h"
#include "test_util.h"

namespace epsray {
namespace {

using test::temp_dir;

// Seven lines of viewpoint: whatever follows starts on line 8.
const std::string view7 =
    "v\n"
    "from 0 0 5\n"
    "at 0 0 0\n"
    "up 0 1 0\n"
    "angle 45\n"
    "hither 1\n"
    "resolution 16 12\n";

scene parse(std::string_view text) { return parse_scene(text, "t.nff", ""); }

void expect_vec(vec3 got, vec3 want, float tol = 1e-5f) {
  EXPECT_NEAR(got.x, want.x, tol);
  EXPECT_NEAR(got.y, want.y, tol);
  EXPECT_NEAR(got.z, want.z, tol);
}

// --- good input ----------------------------------------------------------------------

TEST(Scene, GoodNffCountsAndView) {
  const std::string text =
      "# a small scene with every NFF primitive\n"
      "b 0.1 0.2 0.3\n"
      "v\n"
      "from 1 2 3\n"
      "at 0 0.5 0\n"
      "up 0 0 1\n"
      "angle 30\n"
      "hither 0.01\n"
      "resolution 64 48\n"
      "l 1 1 1\n"
      "l -1 -1 1 0.5 0.25 0.125\n"
      "l 0 0 10\n"
      "f 1 0.5 0.25 0.8 0.2 10 0 1\n"
      "s 0 0 0 1\n"
      "s 2 0 0 -0.5\n"
      "f 0.3 0.3 0.3 1 0 0 0.5 1.5\n"
      "c 0 0 0 1  0 0 2 0.5\n"
      "p 4\n"
      "0 0 0\n"
      "1 0 0\n"
      "\n"
      "# comments and blank lines inside a polygon are fine\n"
      "1 1 0\n"
      "0 1 0\n"
      "pp 3\n"
      "0 0 1  0 0 1\n"
      "1 0 1  0 0 2\n"
      "0 1 1  0.1 0 1\n";
  scene s = parse(text);
  EXPECT_EQ(s.file, "t.nff");
  ASSERT_EQ(s.prims.size(), 5u);
  EXPECT_EQ(s.lights.size(), 3u);
  EXPECT_EQ(s.materials.size(), 2u);
  EXPECT_TRUE(s.has_view);
  expect_vec(s.view.from, {1, 2, 3});
  expect_vec(s.view.at, {0, 0.5f, 0});
  expect_vec(s.view.up, {0, 0, 1});
  EXPECT_FLOAT_EQ(s.view.angle, 30);
  EXPECT_EQ(s.view.width, 64);
  EXPECT_EQ(s.view.height, 48);
  expect_vec(s.background, {0.1f, 0.2f, 0.3f});

  EXPECT_EQ(s.prims[0].kind, prim_kind::sphere);
  EXPECT_EQ(s.prims[1].kind, prim_kind::sphere);
  EXPECT_EQ(s.prims[2].kind, prim_kind::cone);
  EXPECT_EQ(s.prims[3].kind, prim_kind::polygon);
  EXPECT_EQ(s.prims[4].kind, prim_kind::patch);
  EXPECT_EQ(s.prims[0].line, 14);
  EXPECT_EQ(s.prims[3].line, 18);
  EXPECT_EQ(s.prims[4].line, 25);
  EXPECT_FLOAT_EQ(s.prims[1].r0, -0.5f);
  EXPECT_EQ(s.prims[3].count, 4);
  EXPECT_EQ(s.prims[4].count, 3);
  // Material sharing: the two spheres use the first `f`, the rest the second.
  EXPECT_EQ(s.prims[0].material, s.prims[1].material);
  EXPECT_NE(s.prims[1].material, s.prims[2].material);
  const material& m0 = s.materials[size_t(s.prims[0].material)];
  expect_vec(m0.color, {1, 0.5f, 0.25f});
  EXPECT_FLOAT_EQ(m0.kd, 0.8f);
  EXPECT_FLOAT_EQ(m0.ks, 0.2f);
  EXPECT_FLOAT_EQ(m0.shine, 10);
  const material& m1 = s.materials[size_t(s.prims[2].material)];
  EXPECT_FLOAT_EQ(m1.t, 0.5f);
  EXPECT_FLOAT_EQ(m1.ior, 1.5f);
  // Patch vertex normals are stored normalised.
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(glm::length(s.normals[size_t(s.prims[4].first + i)]), 1.0f, 1e-6f);
}

TEST(Scene, DefaultMaterialBeforeAnyF) {
  scene s = parse(view7 + "s 0 0 0 1\n");
  ASSERT_EQ(s.prims.size(), 1u);
  const material& m = s.materials.at(size_t(s.prims[0].material));
  expect_vec(m.color, {1, 1, 1});
  EXPECT_EQ(m.kd, 1);
  EXPECT_EQ(m.ks, 0);
  EXPECT_EQ(m.shine, 0);
  EXPECT_EQ(m.t, 0);
  EXPECT_EQ(m.ior, 1);
  expect_vec(s.background, {0, 0, 0});
}

TEST(Scene, SpdLightIntensityAndAmbient) {
  // N lines of `l`, coloured or not: uncoloured ones get sqrt(N)/(2N); so does ambient.
  for (int n = 1; n <= 7; ++n) {
    std::string text = view7;
    for (int i = 0; i < n; ++i) text += "l " + std::to_string(i) + " 1 1\n";
    text += "l 5 5 5 0.2 0.4 0.6\n";  // coloured: keeps its colour, still counts in N
    text += "s 0 0 0 1\n";
    scene s = parse(text);
    const int N = n + 1;
    const float want = float(std::sqrt(double(N)) / (2.0 * N));
    ASSERT_EQ(int(s.lights.size()), N);
    for (int i = 0; i < n; ++i) expect_vec(light_intensity(s, s.lights[size_t(i)]), vec3(want), 1e-7f);
    expect_vec(light_intensity(s, s.lights.back()), {0.2f, 0.4f, 0.6f}, 0);
    expect_vec(scene_ambient(s), vec3(want), 1e-7f);
    world w = make_world(s);
    expect_vec(w.ambient, vec3(want), 1e-7f);
    ASSERT_EQ(int(w.light_power.size()), N);
    expect_vec(w.light_power[0], vec3(want), 1e-7f);
    expect_vec(w.light_power.back(), {0.2f, 0.4f, 0.6f}, 0);
  }
}

TEST(Scene, SpdIntensityKnownValues) {
  // sqrt(N)/(2N) = 1/(2 sqrt(N)): 0.5 for one light, 0.35355 for two, 0.28868 for three.
  const float want[] = {0.5f, 0.35355339f, 0.28867513f};
  for (int n = 1; n <= 3; ++n) {
    std::string text = view7;
    for (int i = 0; i < n; ++i) text += "l 1 1 1\n";
    scene s = parse(text + "s 0 0 0 1\n");
    EXPECT_NEAR(light_intensity(s, s.lights[0]).x, want[n - 1], 1e-7f);
    EXPECT_NEAR(scene_ambient(s).y, want[n - 1], 1e-7f);
  }
}

TEST(Scene, NoLightsMeansNoAmbient) {
  scene s = parse(view7 + "s 0 0 0 1\n");
  expect_vec(scene_ambient(s), vec3(0), 0);
}

TEST(Scene, NativeAmbientOverridesSpd) {
  scene s = parse(view7 + "ambient 0.1 0.2 0.3\nl 1 1 1\ns 0 0 0 1\n");
  EXPECT_TRUE(s.has_ambient);
  expect_vec(scene_ambient(s), {0.1f, 0.2f, 0.3f}, 0);
  expect_vec(light_intensity(s, s.lights[0]), vec3(0.5f), 1e-7f);  // lights keep the SPD rule
}

TEST(Scene, NonAsciiInsideCommentIsFine) {
  scene s = parse(view7 + "# caf\xc3\xa9 \x01\x7f\n" + "s 0 0 0 1 # r\xc3\xa9sum\xc3\xa9\n");
  EXPECT_EQ(s.prims.size(), 1u);
}

TEST(Scene, CrLfLineEndingsAndTabs) {
  scene s = parse("v\r\nfrom 0 0 5\r\nat 0 0 0\r\nup\t0 1 0\r\nangle 45\r\nresolution 8 8\r\ns 0\t0 0 1\r\n");
  ASSERT_EQ(s.prims.size(), 1u);
  EXPECT_EQ(s.prims[0].line, 7);
  EXPECT_EQ(s.view.width, 8);
}

TEST(Scene, HitherIsOptional) {
  scene s = parse("v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nresolution 8 8\ns 0 0 0 1\n");
  EXPECT_TRUE(s.has_view);
}

TEST(Scene, SuperSetKeywords) {
  const std::string text = view7 +
                           "box -1 -2 -3 1 2 3\n"                 // 8
                           "disk 0 0 0  0 0 2  0.5\n"             // 9
                           "cc 0 0 0 1  0 0 2 0.5\n"              // 10: cone + 2 caps
                           "cc 0 0 0 1  0 0 2 0\n"                // 11: cone + 1 cap
                           "texture checker 1 0 0  0 0 1  0.5 0.25\n"
                           "s 0 0 0 1\n"
                           "texture none\n"
                           "s 0 0 0 2\n"
                           "ambient 0.1 0.1 0.1\n";
  scene s = parse(text);
  ASSERT_EQ(s.prims.size(), 2u + 3u + 2u + 2u);
  EXPECT_EQ(s.prims[0].kind, prim_kind::box);
  expect_vec(s.prims[0].a, {0, 0, 0});
  expect_vec(s.prims[0].b, {1, 2, 3});
  EXPECT_EQ(s.prims[1].kind, prim_kind::disk);
  expect_vec(s.prims[1].b, {0, 0, 1});  // normalised
  EXPECT_FLOAT_EQ(s.prims[1].r0, 0.5f);
  EXPECT_EQ(s.prims[2].kind, prim_kind::cone);
  EXPECT_EQ(s.prims[3].kind, prim_kind::disk);
  EXPECT_EQ(s.prims[4].kind, prim_kind::disk);
  expect_vec(s.prims[3].a, {0, 0, 0});
  expect_vec(s.prims[3].b, {0, 0, -1});  // the base cap faces away from the apex
  expect_vec(s.prims[4].a, {0, 0, 2});
  expect_vec(s.prims[4].b, {0, 0, 1});
  EXPECT_FLOAT_EQ(s.prims[3].r0, 1);
  EXPECT_FLOAT_EQ(s.prims[4].r0, 0.5f);
  EXPECT_EQ(s.prims[5].kind, prim_kind::cone);
  EXPECT_EQ(s.prims[6].kind, prim_kind::disk);
  EXPECT_EQ(s.prims[5].line, 11);
  EXPECT_EQ(s.prims[6].line, 11);
  ASSERT_EQ(s.textures.size(), 1u);
  EXPECT_EQ(s.textures[0].kind, texture_kind::checker);
  expect_vec(s.textures[0].color_a, {1, 0, 0});
  expect_vec(s.textures[0].color_b, {0, 0, 1});
  EXPECT_FLOAT_EQ(s.textures[0].scale.x, 0.5f);
  EXPECT_FLOAT_EQ(s.textures[0].scale.y, 0.25f);
  EXPECT_EQ(s.materials[size_t(s.prims[7].material)].texture, 0);
  EXPECT_EQ(s.materials[size_t(s.prims[8].material)].texture, -1);
  EXPECT_TRUE(s.has_ambient);
}

TEST(Scene, ImageTextureIsReadRelativeToTheSceneFolder) {
  temp_dir dir;
  image img(2, 2);
  img.at(0, 0) = {1, 0, 0};
  img.at(1, 0) = {0, 1, 0};
  img.at(0, 1) = {0, 0, 1};
  img.at(1, 1) = {0.5f, 0.5f, 0.5f};
  write_png(img, dir.file("tex.png"));
  test::write_file(dir.file("scene.nff"), view7 + "texture image tex.png 1 2\ns 0 0 0 1\n");
  scene s = load_scene(dir.file("scene.nff"));
  ASSERT_EQ(s.textures.size(), 1u);
  const texture& t = s.textures[0];
  EXPECT_EQ(t.kind, texture_kind::image);
  EXPECT_EQ(t.width, 2);
  EXPECT_EQ(t.height, 2);
  ASSERT_EQ(t.texels.size(), 4u);
  expect_vec(t.texels[0], {1, 0, 0}, 1e-6f);
  expect_vec(t.texels[1], {0, 1, 0}, 1e-6f);
  expect_vec(t.texels[2], {0, 0, 1}, 1e-6f);
  expect_vec(t.texels[3], vec3(0.5f), 0.01f);  // through 8-bit sRGB and back
}

TEST(Scene, LoadSceneFromFileNamesTheFile) {
  temp_dir dir;
  const std::string path = dir.file("bad.nff");
  test::write_file(path, view7 + "s 0 0 0\n");
  try {
    load_scene(path);
    FAIL() << "no error";
  } catch (const input_error& e) {
    EXPECT_EQ(e.file, path);
    EXPECT_EQ(e.line, 8);
    EXPECT_EQ(std::string(e.what()), path + ":8: sphere needs 4 numbers, got 3");
  }
}

TEST(Scene, MissingFileIsInputError) {
  EXPECT_THROW(load_scene("/nonexistent/epsray/none.nff"), input_error);
}

// --- transforms ------------------------------------------------------------------------

// Distance along a ray to the first hit in the world built from `s`, or -1.
float first_hit(const world& w, vec3 o, vec3 d) {
  hit h;
  if (!closest_hit(w, make_ray(o, glm::normalize(d)), INFINITY, h)) return -1;
  return h.t;
}

TEST(Scene, TranslateRotateScaleMoveABoxAndASphere) {
  // point(p) = T(1,2,3) * Rz(90) * S(2) * p: (x, y, z) -> (1 - 2y, 2 + 2x, 3 + 2z).
  const std::string text = view7 +
                           "push\n"
                           "translate 1 2 3\n"
                           "rotate 0 0 1 90\n"
                           "scale 2\n"
                           "box 0 0 0  2 1 0.5\n"   // centre (1, .5, .25), half (1, .5, .25)
                           "s 1 0 0 0.5\n"
                           "pop\n"
                           "s 0 0 0 1\n";
  scene s = parse(text);
  ASSERT_EQ(s.prims.size(), 3u);
  const primitive& box = s.prims[0];
  expect_vec(box.a, {0, 4, 3.5f});
  expect_vec(box.b, {2, 1, 0.5f});
  expect_vec(box.frame[0], {0, 1, 0});
  expect_vec(box.frame[1], {-1, 0, 0});
  expect_vec(box.frame[2], {0, 0, 1});
  expect_vec(s.prims[1].a, {1, 4, 3});
  EXPECT_FLOAT_EQ(s.prims[1].r0, 1);
  expect_vec(s.prims[2].a, {0, 0, 0});  // pop restored the identity
  EXPECT_FLOAT_EQ(s.prims[2].r0, 1);

  // The box occupies x in [-1, 1], y in [2, 6], z in [3, 4]: check by tracing.
  world w = make_world(s);
  // Each probe ray below is chosen to miss the sphere (centre (1, 4, 3), radius 1).
  EXPECT_NEAR(first_hit(w, {-0.5f, 4, 100}, {0, 0, -1}), 96, 1e-3f);   // top face z = 4
  EXPECT_NEAR(first_hit(w, {100, 5.5f, 3.5f}, {-1, 0, 0}), 99, 1e-3f);  // face x = 1
  EXPECT_NEAR(first_hit(w, {0, 100, 3.5f}, {0, -1, 0}), 94, 1e-3f);    // face y = 6
  EXPECT_NEAR(first_hit(w, {-100, 2.5f, 3.5f}, {1, 0, 0}), 99, 1e-3f);  // face x = -1
  EXPECT_NEAR(first_hit(w, {0.5f, -100, 3.1f}, {0, 1, 0}), 102, 1e-3f);  // face y = 2
  EXPECT_LT(first_hit(w, {-1.2f, 4, 100}, {0, 0, -1}), 0);             // just beside the box
  EXPECT_LT(first_hit(w, {-0.5f, 6.2f, 100}, {0, 0, -1}), 0);
  // The sphere pokes out of the box on its x = 2 side.
  EXPECT_NEAR(first_hit(w, {100, 4, 3}, {-1, 0, 0}), 98, 1e-3f);
}

TEST(Scene, NestedTransformsComposeInTheLocalFrame) {
  const std::string text = view7 +
                           "push\n"
                           "translate 10 0 0\n"
                           "push\n"
                           "rotate 0 0 1 90\n"
                           "translate 1 0 0\n"     // along the rotated x: world +y
                           "s 0 0 0 1\n"           // (10, 1, 0)
                           "l 0 1 0\n"             // (9, 1, 0)
                           "pop\n"
                           "s 0 0 0 1\n"           // (10, 0, 0)
                           "scale 3\n"
                           "translate 1 0 0\n"     // scaled: world +3
                           "s 0 0 0 1\n"           // (13, 0, 0) radius 3
                           "c 0 0 0 1  0 0 1 0.5\n"  // base (13,0,0) r 3, apex (13,0,3) r 1.5
                           "disk 0 0 0  1 0 0  1\n"  // centre (13,0,0), normal x, radius 3
                           "pop\n"
                           "s 0 0 0 1\n";
  scene s = parse(text);
  ASSERT_EQ(s.prims.size(), 6u);
  expect_vec(s.prims[0].a, {10, 1, 0});
  expect_vec(s.lights[0].position, {9, 1, 0});
  expect_vec(s.prims[1].a, {10, 0, 0});
  expect_vec(s.prims[2].a, {13, 0, 0});
  EXPECT_FLOAT_EQ(s.prims[2].r0, 3);
  expect_vec(s.prims[3].a, {13, 0, 0});
  expect_vec(s.prims[3].b, {13, 0, 3});
  EXPECT_FLOAT_EQ(s.prims[3].r0, 3);
  EXPECT_FLOAT_EQ(s.prims[3].r1, 1.5f);
  expect_vec(s.prims[4].a, {13, 0, 0});
  expect_vec(s.prims[4].b, {1, 0, 0});
  EXPECT_FLOAT_EQ(s.prims[4].r0, 3);
  expect_vec(s.prims[5].a, {0, 0, 0});
}

TEST(Scene, RotatedPolygonAndPatchNormals) {
  // Rotating 90 degrees about x maps +y to +z and +z to -y.
  const std::string text = view7 +
                           "rotate 1 0 0 90\n"
                           "p 3\n0 0 0\n1 0 0\n0 1 0\n"
                           "pp 3\n0 0 0 0 0 2\n1 0 0 0 0 2\n0 1 0 0 0 2\n";
  scene s = parse(text);
  ASSERT_EQ(s.prims.size(), 2u);
  expect_vec(s.vertices[2], {0, 0, 1});
  expect_vec(polygon_normal(s, s.prims[0]), {0, -1, 0});
  expect_vec(s.normals[size_t(s.prims[1].first)], {0, -1, 0});
}

// --- malformed input: each with its exact line and the key phrase of its message ---------

struct bad_case {
  const char* name;
  std::string text;
  int line;
  const char* phrase;
};

void PrintTo(const bad_case& c, std::ostream* os) { *os << c.name; }

std::string with_view(const std::string& tail) { return view7 + tail; }
// The viewpoint with one of its lines replaced (1-based line within view7).
std::string view_with(int line, const std::string& replacement, const std::string& tail = "s 0 0 0 1\n") {
  std::istringstream in(view7);
  std::string out, l;
  for (int i = 1; std::getline(in, l); ++i) out += (i == line ? replacement : l) + "\n";
  return out + tail;
}

std::vector<bad_case> bad_scenes() {
  return {
      // wrong counts of numbers
      {"sphere_3_numbers", with_view("s 0 0 0\n"), 8, "sphere needs 4 numbers, got 3"},
      {"sphere_5_numbers", with_view("s 0 0 0 1 2\n"), 8, "sphere needs 4 numbers, got 5"},
      {"cone_7_numbers", with_view("c 0 0 0 1 0 0 1\n"), 8, "needs 8 numbers, got 7"},
      {"material_7_numbers", with_view("f 1 1 1 1 0 0 0\ns 0 0 0 1\n"), 9,
       "material (f) needs 8 numbers, got 7 (the entity begins at line 8)"},
      {"light_4_numbers", with_view("l 1 2 3 4\ns 0 0 0 1\n"), 9, "light (l) needs 3 or 6 numbers, got 4"},
      {"background_2_numbers", with_view("b 1 1\ns 0 0 0 1\n"), 9, "needs 3 numbers, got 2"},
      {"from_2_numbers", view_with(2, "from 0 0"), 3, "from needs 3 numbers, got 2 (the entity begins at line 2)"},
      {"polygon_vertex_2_numbers", with_view("p 3\n0 0 0\n1 0\n0 1 0\n"), 8,
       "polygon (p) ends early: expected 3 vertices (9 numbers), got 8 numbers"},
      {"patch_vertex_3_numbers", with_view("pp 3\n0 0 0 0 0 1\n1 0 0\n0 1 0 0 0 1\n"), 8,
       "patch (pp) ends early: expected 3 vertices (18 numbers), got 15 numbers"},
      {"polygon_too_many_numbers", with_view("p 3\n0 0 0\n1 0 0\n0 1 0 7\n"), 11, "needs 9 numbers after its count, got more"},
      {"sphere_numbers_on_next_line", with_view("s 0 0 0 1\n2 3\n"), 9, "sphere needs 4 numbers, got 6"},
      {"number_where_entity_expected", "7\n" + view7 + "s 0 0 0 1\n", 1, "number '7' where an entity was expected"},
      {"v_with_a_number", view_with(1, "v 3"), 1, "v takes no numbers, got 1"},
      // non-numbers, nan, inf, out of float range
      {"non_number", with_view("s 0 0 abc 1\n"), 8, "'abc' is not a number"},
      {"nan", with_view("s 0 nan 0 1\n"), 8, "'nan' is not a finite number"},
      {"inf", with_view("s 0 0 0 inf\n"), 8, "'inf' is not a finite number"},
      {"minus_inf", with_view("f 1 1 1 -inf 0 0 0 1\ns 0 0 0 1\n"), 8, "is not a finite number"},
      {"1e999", with_view("s 1e999 0 0 1\n"), 8, "'1e999' is not a finite number"},
      {"beyond_float", with_view("s 0 0 0 1e39\n"), 8, "'1e39' is not a finite number"},
      {"hex_float", with_view("s 0x1p3 0 0 1\n"), 8, "is not a number"},
      {"two_dots", with_view("s 1.2.3 0 0 1\n"), 8, "'1.2.3' is not a number"},
      {"shine_nan", with_view("f 1 1 1 1 0 NaN 0 1\ns 0 0 0 1\n"), 8, "is not a finite number"},
      {"polygon_count_not_integer", with_view("p 3.5\n0 0 0\n1 0 0\n0 1 0\n"), 8, "is not an integer"},
      // resolution, angle
      {"resolution_zero", view_with(7, "resolution 0 0"), 7, "resolution width: 0 is out of range"},
      {"resolution_negative_width", view_with(7, "resolution -16 12"), 7, "resolution width: -16 is out of range"},
      {"resolution_negative_height", view_with(7, "resolution 16 -12"), 7, "resolution height: -12 is out of range"},
      {"resolution_height_1", view_with(7, "resolution 16 1"), 7, "resolution height: 1 is out of range"},
      {"resolution_fraction", view_with(7, "resolution 16.5 12"), 7, "is not an integer"},
      {"angle_0", view_with(5, "angle 0"), 5, "angle must be between 0 and 180"},
      {"angle_180", view_with(5, "angle 180"), 5, "angle must be between 0 and 180"},
      {"angle_negative", view_with(5, "angle -30"), 5, "angle must be between 0 and 180"},
      // degenerate polygons
      {"polygon_collinear_first_edges", with_view("p 4\n0 0 0\n1 0 0\n2 0 0\n0 1 0\n"), 8,
       "first two edges are zero or collinear"},
      {"polygon_zero_length_edge", with_view("p 3\n0 0 0\n0 0 0\n1 1 0\n"), 8, "first two edges are zero or collinear"},
      {"polygon_all_points_equal", with_view("p 3\n1 1 1\n1 1 1\n1 1 1\n"), 8, "degenerate polygon"},
      {"polygon_non_planar", with_view("p 4\n0 0 0\n1 0 0\n1 1 0\n0 1 0.5\n"), 8, "not planar: vertex 3"},
      {"polygon_2_vertices", with_view("p 2\n0 0 0\n1 0 0\n"), 8, "polygon vertex count: 2 is out of range"},
      {"polygon_0_vertices", with_view("s 0 0 0 1\np 0\n"), 9, "polygon vertex count: 0 is out of range"},
      {"polygon_ends_at_eof", with_view("s 0 0 0 1\np 4\n0 0 0\n1 0 0\n\n# end\n"), 9,
       "ends early: expected 4 vertices (12 numbers), got 6 numbers"},
      {"polygon_cut_by_next_entity", with_view("p 4\n0 0 0\n1 0 0\n1 1 0\ns 0 0 0 1\n"), 12,
       "polygon (p) ends early: expected 4 vertices (12 numbers), got 9 numbers (the entity begins at line 8)"},
      {"patch_collinear", with_view("pp 3\n0 0 0 0 0 1\n1 0 0 0 0 1\n2 0 0 0 0 1\n"), 8, "degenerate polygon"},
      {"patch_zero_normal", with_view("pp 3\n0 0 0 0 0 1\n1 0 0 0 0 0\n0 1 0 0 0 1\n"), 10,
       "patch vertex normal is zero"},
      {"patch_2_vertices", with_view("pp 2\n0 0 0 0 0 1\n1 0 0 0 0 1\n"), 8, "patch vertex count: 2 is out of range"},
      // cones, spheres
      {"cone_coincident_ends", with_view("c 1 2 3 1  1 2 3 0.5\n"), 8, "cone ends coincide"},
      {"cone_opposite_radii", with_view("c 0 0 0 1  0 0 1 -0.5\n"), 8, "cone radii have opposite signs"},
      {"cone_opposite_radii_2", with_view("c 0 0 0 -1  0 0 1 0.5\n"), 8, "cone radii have opposite signs"},
      {"cone_both_radii_zero", with_view("c 0 0 0 0  0 0 1 0\n"), 8, "both cone radii are zero"},
      {"sphere_radius_zero", with_view("s 0 0 0 0\n"), 8, "sphere radius is zero"},
      {"sphere_radius_minus_zero", with_view("s 0 0 0 -0.0\n"), 8, "sphere radius is zero"},
      // entities, files
      {"unknown_entity", with_view("s 0 0 0 1\nsphere 0 0 0 1\n"), 9, "unknown entity 'sphere'"},
      {"missing_texture_file", with_view("texture image no-such-file.png 1 1\ns 0 0 0 1\n"), 8,
       "texture file 'no-such-file.png' cannot be read"},
      {"empty_file", "", 1, "empty scene file"},
      {"only_comments", "# one\n\n   # two\n\t\n", 1, "empty scene file"},
      {"no_primitives", with_view("l 1 1 1\n\n# nothing else\n"), 8, "scene has no primitives"},
      // the viewpoint
      {"missing_up", "v\nfrom 0 0 5\nat 0 0 0\nangle 45\nresolution 8 8\ns 0 0 0 1\n", 1, "viewpoint is missing: up"},
      {"missing_resolution_and_angle", "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\ns 0 0 0 1\n", 1,
       "viewpoint is missing: angle resolution"},
      {"missing_viewpoint", "l 1 1 1\ns 0 0 0 1\n", 2, "viewpoint is missing: from at up angle resolution"},
      {"up_parallel_to_view", view_with(4, "up 0 0 -3"), 1, "up is zero or parallel to the view direction"},
      {"up_zero", view_with(4, "up 0 0 0"), 1, "up is zero or parallel to the view direction"},
      {"from_equals_at", view_with(3, "at 0 0 5"), 1, "from and at coincide"},
      // colours and materials
      {"negative_material_colour", with_view("f 1 -0.5 1 1 0 0 0 1\ns 0 0 0 1\n"), 8,
       "material colour must be non-negative"},
      {"negative_light_colour", with_view("l 1 1 1 1 1 -1\ns 0 0 0 1\n"), 8, "light colour must be non-negative"},
      {"negative_background", with_view("b 0 0 -0.1\ns 0 0 0 1\n"), 8, "background colour must be non-negative"},
      {"negative_ambient", with_view("ambient -1 0 0\ns 0 0 0 1\n"), 8, "ambient colour must be non-negative"},
      {"negative_kd", with_view("f 1 1 1 -1 0 0 0 1\ns 0 0 0 1\n"), 8, "Kd must be non-negative"},
      {"negative_ks", with_view("f 1 1 1 1 -0.1 0 0 1\ns 0 0 0 1\n"), 8, "Ks must be non-negative"},
      {"negative_t", with_view("f 1 1 1 1 0 0 -0.5 1\ns 0 0 0 1\n"), 8, "T must be non-negative"},
      {"transparent_ior_zero", with_view("f 1 1 1 1 0 0 0.5 0\ns 0 0 0 1\n"), 8, "ior must be positive when T > 0"},
      {"transparent_ior_negative", with_view("f 1 1 1 1 0 0 0.5 -1.5\ns 0 0 0 1\n"), 8,
       "ior must be positive when T > 0"},
      // bytes
      {"non_ascii_byte", with_view("s 0 0 0 1 \xc3\xa9\n"), 8, "byte 0xc3 is not printable ASCII"},
      {"control_byte", with_view("s 0 0 0 1\n\x01\n"), 9, "byte 0x01 is not printable ASCII"},
      {"non_ascii_before_comment", with_view("s 0 0 0 1 \xff # fine here \xff\n"), 8, "byte 0xff"},
      {"nul_byte", with_view(std::string("s 0 0 0 1\ns 0 0") + '\0' + " 0 1\n"), 9, "byte 0x00"},
      // the superset
      {"pop_without_push", with_view("s 0 0 0 1\npop\n"), 9, "pop without a matching push"},
      {"pop_twice", with_view("push\npop\npop\ns 0 0 0 1\n"), 10, "pop without a matching push"},
      {"scale_zero", with_view("scale 0\ns 0 0 0 1\n"), 8, "scale must be positive"},
      {"scale_negative", with_view("scale -2\ns 0 0 0 1\n"), 8, "scale must be positive"},
      {"rotate_zero_axis", with_view("rotate 0 0 0 45\ns 0 0 0 1\n"), 8, "rotation axis is zero"},
      {"unknown_texture_kind", with_view("texture marble 1 1\ns 0 0 0 1\n"), 8, "unknown texture kind 'marble'"},
      {"texture_scale_zero", with_view("texture checker 1 1 1 0 0 0 0 1\ns 0 0 0 1\n"), 8,
       "texture scales must be positive"},
      {"box_zero_size", with_view("box 0 0 0 1 0 1\n"), 8, "box has zero size along an axis"},
      {"disk_zero_normal", with_view("disk 0 0 0 0 0 0 1\n"), 8, "disk normal is zero"},
      {"disk_zero_radius", with_view("disk 0 0 0 0 0 1 0\n"), 8, "disk radius must be positive"},
      {"capped_cone_negative_radius", with_view("cc 0 0 0 -1 0 0 1 -1\n"), 8,
       "capped cone radii must be non-negative"},
      // line numbers past comments, blank lines and multi-line polygons
      {"line_after_polygon_and_comments",
       with_view("# c\n\np 3\n0 0 0\n1 0 0\n\n0 1 0\n  # indented comment\ns 1 2 3\n"), 16,
       "sphere needs 4 numbers, got 3"},
      {"crlf_line", with_view("s 0 0 0 1\r\ns 0 0 0\r\n"), 9, "sphere needs 4 numbers, got 3"},
  };
}

class BadScene : public testing::TestWithParam<bad_case> {};

TEST_P(BadScene, ReportsLineAndReason) {
  const bad_case& c = GetParam();
  try {
    parse_scene(c.text, "bad.nff", "");
    FAIL() << "parsed without error";
  } catch (const input_error& e) {
    EXPECT_EQ(e.file, "bad.nff");
    EXPECT_EQ(e.line, c.line) << e.what();
    EXPECT_NE(e.what_is_wrong.find(c.phrase), std::string::npos)
        << "message '" << e.what_is_wrong << "' lacks '" << c.phrase << "'";
    EXPECT_EQ(std::string(e.what()), "bad.nff:" + std::to_string(e.line) + ": " + e.what_is_wrong);
    EXPECT_EQ(e.what_is_wrong.find('\n'), std::string::npos) << "the message must fit on one line";
  } catch (const std::exception& e) {
    FAIL() << "threw something other than input_error: " << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(Malformed, BadScene, testing::ValuesIn(bad_scenes()),
                         [](const testing::TestParamInfo<bad_case>& i) { return std::string(i.param.name); });

TEST(Scene, MalformedTableIsLargeEnough) { EXPECT_GE(bad_scenes().size(), 30u); }

// --- camera path files (whitted.md 8) -------------------------------------------------------

TEST(CameraPath, CommentsAndBlankLinesAreSkipped) {
  const std::string text =
      "# a path\n"
      "\n"
      "0 0 5   0 0 0   0 1 0   45\n"
      "   \t\n"
      "1 2 3  -1 -2 -3  0 0 1  30.5  # trailing comment\n"
      "# done\n";
  camera_path p = parse_camera_path(text, "walk.path");
  EXPECT_EQ(p.file, "walk.path");
  ASSERT_EQ(p.frames.size(), 2u);
  expect_vec(p.frames[0].from, {0, 0, 5});
  expect_vec(p.frames[0].at, {0, 0, 0});
  expect_vec(p.frames[0].up, {0, 1, 0});
  EXPECT_FLOAT_EQ(p.frames[0].angle, 45);
  expect_vec(p.frames[1].from, {1, 2, 3});
  expect_vec(p.frames[1].at, {-1, -2, -3});
  expect_vec(p.frames[1].up, {0, 0, 1});
  EXPECT_FLOAT_EQ(p.frames[1].angle, 30.5f);
}

TEST(CameraPath, LoadFromFile) {
  temp_dir dir;
  test::write_file(dir.file("p.path"), "0 0 5 0 0 0 0 1 0 45\n");
  camera_path p = load_camera_path(dir.file("p.path"));
  EXPECT_EQ(p.frames.size(), 1u);
  EXPECT_THROW(load_camera_path(dir.file("missing.path")), input_error);
}

std::vector<bad_case> bad_paths() {
  const std::string ok = "0 0 5 0 0 0 0 1 0 45\n";
  return {
      {"nine_numbers", ok + "0 0 5 0 0 0 0 1 0\n", 2, "camera needs 10 numbers (from, at, up, angle), got 9"},
      {"eleven_numbers", "# c\n" + ok + ok + "0 0 5 0 0 0 0 1 0 45 1\n", 4, "camera needs 10 numbers"},
      {"non_number", ok + "0 0 5 0 x 0 0 1 0 45\n", 2, "'x' is not a number"},
      {"nan", ok + "0 0 5 0 0 0 0 1 0 nan\n", 2, "'nan' is not a finite number"},
      {"angle_zero", ok + ok + "0 0 5 0 0 0 0 1 0 0\n", 3, "angle must be between 0 and 180"},
      {"angle_180", "0 0 5 0 0 0 0 1 0 180\n", 1, "angle must be between 0 and 180"},
      {"angle_negative", "\n\n0 0 5 0 0 0 0 1 0 -45\n", 3, "angle must be between 0 and 180"},
      {"angle_too_big", ok + "0 0 5 0 0 0 0 1 0 270\n", 2, "angle must be between 0 and 180"},
      {"from_equals_at", ok + "1 1 1 1 1 1 0 1 0 45\n", 2, "from and at coincide"},
      {"up_parallel", ok + "0 0 5 0 0 0 0 0 1 45\n", 2, "up is zero or parallel"},
      {"non_ascii", ok + "0 0 5 0 0 0 0 1 0 45 \xe2\x80\x94\n", 2, "is not printable ASCII"},
      {"empty", "", 1, "camera path has no frames"},
      {"only_comments", "# nothing\n\n# here\n", 1, "camera path has no frames"},
  };
}

class BadPath : public testing::TestWithParam<bad_case> {};

TEST_P(BadPath, ReportsLineAndReason) {
  const bad_case& c = GetParam();
  try {
    parse_camera_path(c.text, "bad.path");
    FAIL() << "parsed without error";
  } catch (const input_error& e) {
    EXPECT_EQ(e.file, "bad.path");
    EXPECT_EQ(e.line, c.line) << e.what();
    EXPECT_NE(e.what_is_wrong.find(c.phrase), std::string::npos)
        << "message '" << e.what_is_wrong << "' lacks '" << c.phrase << "'";
  }
}

INSTANTIATE_TEST_SUITE_P(Malformed, BadPath, testing::ValuesIn(bad_paths()),
                         [](const testing::TestParamInfo<bad_case>& i) { return std::string(i.param.name); });

// --- real SPD files --------------------------------------------------------------------------

// Counts the lines starting with `key ` in an NFF file.
size_t count_key(const std::string& text, const std::string& key) {
  std::istringstream in(text);
  std::string l;
  size_t n = 0;
  while (std::getline(in, l))
    if (l.rfind(key + " ", 0) == 0) ++n;
  return n;
}

class SpdParse : public testing::TestWithParam<const char*> {};

TEST_P(SpdParse, CountsMatchTheFile) {
  const std::string name = GetParam();
  EPSRAY_REQUIRE_SPD(name);
  const std::string path = test::spd_scene(name).string();
  const std::string text = test::read_file(path);
  scene s = load_scene(path);
  const size_t prims = count_key(text, "s") + count_key(text, "c") + count_key(text, "p") + count_key(text, "pp");
  EXPECT_EQ(s.prims.size(), prims);
  EXPECT_EQ(s.lights.size(), count_key(text, "l"));
  std::istringstream in(text);
  std::string key;
  int width = 0, height = 0;
  float angle = 0;
  while (in >> key) {
    if (key == "resolution") in >> width >> height;
    else if (key == "angle") in >> angle;
  }
  EXPECT_EQ(s.view.width, width);
  EXPECT_EQ(s.view.height, height);
  EXPECT_FLOAT_EQ(s.view.angle, angle);
}

INSTANTIATE_TEST_SUITE_P(Spd, SpdParse, EPSRAY_SMALL_SPD_SCENES, test::spd_param_name);

// --- fuzzing regressions (docs/fuzzing.md) ---------------------------------------------------

// Inputs the fuzz targets failed on (fuzz/fuzz_scene.cpp, fuzz/fuzz_path.cpp): each must be
// refused with its line, or parse and render to finite radiance.
std::string fuzz_data(const std::string& name) { return std::string(EPSRAY_TEST_DATA_DIR) + "/fuzz/" + name; }

template <class F>
void expect_input_error(F parse_file, int line, const std::string& what) {
  try {
    parse_file();
    ADD_FAILURE() << "expected input_error: " << what;
  } catch (const input_error& e) {
    EXPECT_EQ(e.line, line) << e.what();
    EXPECT_NE(e.what_is_wrong.find(what), std::string::npos) << e.what();
  }
}

TEST(FuzzRegression, RefusedWithTheirLine) {
  expect_input_error([] { load_camera_path(fuzz_data("view-too-far.path")); }, 2, "from and at are too far apart");
  expect_input_error([] { load_camera_path(fuzz_data("up-too-large.path")); }, 2, "up is too large");
  expect_input_error([] { load_scene(fuzz_data("view-too-far.nff")); }, 2, "viewpoint: from and at are too far apart");
  expect_input_error([] { load_scene(fuzz_data("radiance-overflow.nff")); }, 9, "light colour must be at most 1000000");
}

TEST(FuzzRegression, ColourAndFactorBounds) {
  expect_input_error([] { parse(view7 + "f 1001 1 1 1 0 0 0 1\ns 0 0 0 1\n"); }, 8, "material colour must be at most 1000");
  expect_input_error([] { parse(view7 + "f 1 1 1 1 1e4 0 0 1\ns 0 0 0 1\n"); }, 8, "Ks must be at most 1000");
  expect_input_error([] { parse(view7 + "b 0 2e6 0\ns 0 0 0 1\n"); }, 8, "background colour must be at most 1000000");
  EXPECT_NO_THROW(parse(view7 + "ambient 1e6 0 0\nf 1 1 1 1000 1000 0 1000 1\ns 0 0 0 1\n"));
}

TEST(FuzzRegression, LargestColoursGiveFiniteRadiance) {
  world w = make_world(load_scene(fuzz_data("radiance-at-bounds.nff")));
  const camera cam = make_camera(w.sc.view, 3, 3);
  trace_state st;
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 3; ++x) {
      vec3 c = trace_eye(w, make_ray(cam.origin, eye_direction(cam, float(x), float(y))), st);
      EXPECT_TRUE(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z)) << x << "," << y;
    }
  EXPECT_GT(st.counts.refract, 0u);  // the glass sphere was hit: every factor entered
}

}  // namespace
}  // namespace epsray

// --- NFF as a token stream (whitted.md 2) ---------------------------------------------

namespace epsray {
namespace {

// The scene's tokens with comments dropped, as the reader under test splits them.
std::vector<std::string> nff_tokens(const std::string& text) {
  token_reader in(text, "tokens");
  std::vector<std::string> out;
  while (!in.peek().end()) out.emplace_back(in.next().text);
  return out;
}

// The same tokens laid out again: `gap(i)` is what stands between token i and i+1.
template <class Gap>
std::string relayout(const std::vector<std::string>& toks, Gap gap) {
  std::string out;
  for (size_t i = 0; i < toks.size(); ++i) out += toks[i] + gap(i);
  return out;
}

// Every layout writers use: one token a line (LF, CRLF, CR), the whole file on one line,
// Haines' layout (keyword alone on its line, then three numbers a line), and random mixes
// of blanks, tabs, blank lines and line ends.
std::vector<std::pair<std::string, std::string>> layouts(const std::string& text) {
  const std::vector<std::string> t = nff_tokens(text);
  std::vector<std::pair<std::string, std::string>> out;
  out.push_back({"one_token_a_line_lf", relayout(t, [](size_t) { return "\n"; })});
  out.push_back({"one_token_a_line_crlf", relayout(t, [](size_t) { return "\r\n"; })});
  out.push_back({"one_token_a_line_cr", relayout(t, [](size_t) { return "\r"; })});
  out.push_back({"one_line", relayout(t, [](size_t) { return " "; })});
  out.push_back({"haines", relayout(t, [&](size_t i) {
                   static int run = 0;
                   bool next_is_word = i + 1 < t.size() && !looks_decimal(t[i + 1]);
                   if (!looks_decimal(t[i]) || next_is_word) return run = 0, std::string("\n");
                   return std::string(++run % 3 == 0 ? "\n" : " ");
                 })});
  for (unsigned seed : {1u, 2u, 3u}) {
    std::mt19937 g(seed);
    const char* gaps[] = {" ", "\t", "\n", "\r\n", "\r", "  \t ", "\n\n", "\r\n\r\n", " # a comment\n", "\t\r"};
    out.push_back({"mixed_" + std::to_string(seed),
                   relayout(t, [&](size_t) { return std::string(gaps[g() % (sizeof gaps / sizeof *gaps)]); })});
  }
  return out;
}

// A picture of the scene by the reference tracer: every layout must give these bytes.
image reference_picture(const scene& sc, int w = 48, int h = 36) {
  world wd = make_world(scene(sc));
  camera cam = make_camera(wd.sc.view, w, h);
  image img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      trace_state st;
      img.at(x, y) = trace_eye(wd, make_ray(cam.origin, eye_direction(cam, float(x), float(y))), st);
    }
  return img;
}

void expect_same_scene(const scene& a, const scene& b) {
  ASSERT_EQ(a.prims.size(), b.prims.size());
  for (size_t i = 0; i < a.prims.size(); ++i) {
    const primitive &p = a.prims[i], &q = b.prims[i];
    EXPECT_TRUE(p.kind == q.kind && p.material == q.material && p.a == q.a && p.b == q.b && p.r0 == q.r0 &&
                p.r1 == q.r1 && p.first == q.first && p.count == q.count && p.frame == q.frame)
        << "primitive " << i;
  }
  EXPECT_EQ(a.vertices, b.vertices);
  EXPECT_EQ(a.normals, b.normals);
  ASSERT_EQ(a.lights.size(), b.lights.size());
  ASSERT_EQ(a.materials.size(), b.materials.size());
  ASSERT_EQ(a.textures.size(), b.textures.size());
  EXPECT_EQ(a.view.from, b.view.from);
  EXPECT_EQ(a.view.width, b.view.width);
}

void check_layouts(const std::string& text, const std::string& dir) {
  const scene base = parse_scene(text, "base.nff", dir);
  const image want = reference_picture(base);
  for (const auto& [name, laid] : layouts(text)) {
    SCOPED_TRACE(name);
    scene s = parse_scene(laid, name + ".nff", dir);
    expect_same_scene(base, s);
    EXPECT_TRUE(test::same_pixels(reference_picture(s), want));
  }
}

TEST(NffLayout, TheArtRoomInEveryLayoutGivesTheSameImage) {
  const std::string dir = std::string(EPSRAY_SOURCE_DIR) + "/scenes";
  check_layouts(test::read_file(dir + "/artroom.nff"), dir);
}

TEST(NffLayout, AnSpdSceneInEveryLayoutGivesTheSameImage) {
  for (const char* name : {"rings-s3", "teapot-s6"}) {
    EPSRAY_REQUIRE_SPD(name);
    check_layouts(test::read_file(test::spd_scene(name).string()), "");
  }
}

// Haines' own NFF document: `c` alone on its line, then base and apex; `p n`, then a
// vertex a line; a polygon written on one line, as other writers do.
TEST(NffLayout, HainesConeAndOneLinePolygonAreRead) {
  scene a = parse(view7 + "c\n0 0 0 1\n0 0 2 0.5\np 3 0 0 0 1 0 0 0 1 0\n");
  scene b = parse(view7 + "c 0 0 0 1 0 0 2 0.5\np 3\n0 0 0\n1 0 0\n0 1 0\n");
  expect_same_scene(a, b);
  ASSERT_EQ(a.prims.size(), 2u);
  EXPECT_EQ(a.prims[0].kind, prim_kind::cone);
  EXPECT_EQ(a.prims[0].line, 8);
  EXPECT_EQ(a.prims[1].kind, prim_kind::polygon);
}

TEST(NffLayout, CrOnlyLineEndsCountLines) {
  std::string text = with_view("s 0 0 0 1\ns 0 0 0\n");
  for (char& c : text)
    if (c == '\n') c = '\r';
  try {
    parse(text);
    FAIL() << "a sphere of 3 numbers was read";
  } catch (const input_error& e) {
    EXPECT_EQ(e.line, 9) << e.what();
  }
}

TEST(NffLayout, TheSupersetFollowsTheSameRule) {
  scene a = parse(view7 +
                  "push\ntranslate\n1\n2 3\nrotate 0 0\n1 90\nscale\n2\ntexture\nchecker 1 0 0\n0 0 1\n1 1\n"
                  "box\n0 0 0\n1 1 1\ndisk 0 0 0 0 0 1\n2\npop\nambient\n0.1 0.1 0.1\n");
  scene b = parse(view7 +
                  "push\ntranslate 1 2 3\nrotate 0 0 1 90\nscale 2\ntexture checker 1 0 0 0 0 1 1 1\n"
                  "box 0 0 0 1 1 1\ndisk 0 0 0 0 0 1 2\npop\nambient 0.1 0.1 0.1\n");
  expect_same_scene(a, b);
  EXPECT_EQ(a.textures.size(), 1u);
  EXPECT_TRUE(a.has_ambient);
}

TEST(NffLayout, AHugeNumberIsEchoedCut) {
  const std::string big(10'000'000, '7');
  try {
    parse(with_view("s 0 0 0 1" + big + "x\n"));
    FAIL();
  } catch (const input_error& e) {
    EXPECT_LT(std::string(e.what()).size(), 200u);
    EXPECT_NE(std::string(e.what()).find("characters"), std::string::npos) << e.what();
  }
}

// --- only regular files, with a bound -------------------------------------------------

template <class F>
void expect_refused_fast(F&& load, const char* phrase) {
  const auto t0 = std::chrono::steady_clock::now();
  try {
    load();
    FAIL() << "accepted";
  } catch (const input_error& e) {
    EXPECT_NE(std::string(e.what()).find(phrase), std::string::npos) << e.what();
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 1.0);
}

TEST(InputFiles, DevicesAndFifosAreRefusedAtOnce) {
  expect_refused_fast([] { load_scene("/dev/zero"); }, "not a regular file");
  expect_refused_fast([] { load_camera_path("/dev/zero"); }, "not a regular file");
  test::temp_dir d;
  const std::string fifo = d.file("scene.fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  expect_refused_fast([&] { load_scene(fifo); }, "not a regular file");
  expect_refused_fast([&] { load_camera_path(fifo); }, "not a regular file");
  expect_refused_fast([&] { read_text_file(fifo); }, "not a regular file");  // the viewer's scripts
  test::write_file(d.file("t.nff"), with_view("texture image scene.fifo 1 1\ns 0 0 0 1\n"));
  expect_refused_fast([&] { load_scene(d.file("t.nff")); }, "not a regular file");
  expect_refused_fast([&] { load_scene(d.path().string()); }, "is a folder");
}

TEST(InputFiles, ASparseFileOverTheLimitIsRefusedBeforeItIsRead) {
  test::temp_dir d;
  const std::string big = d.file("big.nff");
  { std::ofstream(big) << "# sparse\n"; }
  std::error_code ec;
  std::filesystem::resize_file(big, std::uintmax_t(3) << 30, ec);  // 3 GiB of holes
  if (ec) GTEST_SKIP() << "no sparse files here: " << ec.message();
  expect_refused_fast([&] { load_scene(big); }, "over the limit of 2147483648 bytes");
}

// Image headers that claim more texels than the cap: refused from the header, before a
// byte of texels is decoded (stb would allocate gigabytes first).
TEST(InputFiles, TexturesOverTheTexelCapAreRefusedFromTheirHeader) {
  test::temp_dir d;
  // A TGA header: uncompressed true colour, 25000 x 25000, 24 bits, then a few bytes.
  std::string tga(18, '\0');
  tga[2] = 2;
  tga[12] = char(25000 & 255), tga[13] = char(25000 >> 8), tga[14] = char(25000 & 255), tga[15] = char(25000 >> 8);
  tga[16] = 24;
  test::write_file(d.file("huge.tga"), tga + std::string(64, '\x7f'));
  // A PNG whose IHDR says 16384 x 16384 (the rest of the file is missing).
  const unsigned char png[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R',
                               0, 0, 0x40, 0, 0, 0, 0x40, 0, 8, 2, 0, 0, 0, 0, 0, 0, 0};
  test::write_file(d.file("huge.png"), std::string(reinterpret_cast<const char*>(png), sizeof png));
  for (const char* f : {"huge.tga", "huge.png"}) {
    SCOPED_TRACE(f);
    test::write_file(d.file("t.nff"), with_view(std::string("texture image ") + f + " 1 1\ns 0 0 0 1\n"));
    expect_refused_fast([&] { load_scene(d.file("t.nff")); }, "over the limit of 67108864 texels");
  }
}

TEST(InputFiles, ACorruptImagesMessageIsPrintable) {
  test::temp_dir d;
  test::write_file(d.file("bad.png"), std::string("\x89PNG\r\n\x1a\n\x01\x02\x03garbage", 19));
  test::write_file(d.file("t.nff"), with_view("texture image bad.png 1 1\ns 0 0 0 1\n"));
  try {
    load_scene(d.file("t.nff"));
    FAIL();
  } catch (const input_error& e) {
    for (unsigned char c : std::string(e.what())) EXPECT_TRUE(c >= 32 && c < 127) << int(c) << " in " << e.what();
  }
}

// --- transforms checked like the primitives they make -------------------------------

TEST(Transforms, OverflowUnderflowAndDegenerateResultsAreRefusedAtTheirLine) {
  struct tcase {
    const char* text;
    int line;
    const char* phrase;
  };
  const tcase cases[] = {
      {"scale 1e30\nscale 1e30\ns 0 0 0 1\n", 9, "scale is beyond float range"},
      {"scale 1e-30\nscale 1e-30\nbox 0 0 0 1 1 1\n", 9, "scale underflows to zero"},
      {"scale 1e-19\nbox 0 0 0 1e-20 1 1\n", 9, "box size underflows to zero once scaled"},
      {"scale 1e-19\ndisk 0 0 0 0 0 1 1e-20\n", 9, "disk radius underflows"},
      {"scale 1e-19\ns 0 0 0 1e-20\n", 9, "sphere radius underflows"},
      {"scale 1e20\ns 0 0 0 1e19\n", 9, "sphere radius is beyond float range"},
      {"scale 1e20\ns 1e19 0 0 1\n", 9, "sphere centre is beyond float range"},
      {"translate 3e38 0 0\ntranslate 3e38 0 0\ns 0 0 0 1\n", 9, "translation is beyond float range"},
      {"scale 1e20\np 3\n0 0 0\n1e19 0 0\n0 1 0\n", 9, "vertex is beyond float range"},
      {"scale 1e20\nl 1e19 0 0\ns 0 0 0 1\n", 9, "light position is beyond float range"},
      {"scale 1e20\nc 0 0 0 1  1e19 0 0 1\n", 9, "cone apex is beyond float range"},
      {"s 3e38 0 0 1e38\n", 8, "sphere extends beyond float range"},
  };
  for (const tcase& c : cases) {
    SCOPED_TRACE(c.text);
    try {
      parse(with_view(c.text));
      ADD_FAILURE() << "accepted";
    } catch (const input_error& e) {
      EXPECT_EQ(e.line, c.line) << e.what();
      EXPECT_NE(e.what_is_wrong.find(c.phrase), std::string::npos) << e.what();
    }
  }
}

TEST(Transforms, ATinyRotationAxisIsStillItsDirection) {
  scene a = parse(with_view("rotate 1e-30 0 0 90\np 3\n0 0 0\n0 1 0\n0 0 1\n"));
  scene b = parse(with_view("rotate 1 0 0 90\np 3\n0 0 0\n0 1 0\n0 0 1\n"));
  EXPECT_EQ(a.vertices, b.vertices);
  expect_vec(a.vertices[1], vec3(0, 0, 1));
}

}  // namespace
}  // namespace epsray
