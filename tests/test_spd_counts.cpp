// The Standard Procedural Databases' published ray counts (513x513, depth 5: the SPD testing
// procedure of whitted.md 4) as a check of the whole tracer: frame 0 of each scene must land
// within 10% of the published reflect / refract / shadow figures, and a zero stays zero.
#include <cmath>
#include <cstdint>
#include <string>

#include "scene/camera.h"
#include "sched/frame_render.h"
#include "test_util.h"

namespace epsray {
namespace {

struct published {
  std::uint64_t reflect, refract, shadow;
};

// Within 10% of a published figure; zero must be matched exactly.
testing::AssertionResult within_10_percent(const char* what, std::uint64_t got, std::uint64_t want) {
  if (want == 0) {
    if (got == 0) return testing::AssertionSuccess();
    return testing::AssertionFailure() << what << ": got " << got << ", published 0 (must stay 0)";
  }
  double rel = (double(got) - double(want)) / double(want);
  if (std::fabs(rel) <= 0.10) return testing::AssertionSuccess();
  return testing::AssertionFailure() << what << ": got " << got << ", published " << want << " (" << rel * 100
                                     << "%)";
}

void check_counts(const std::string& name, published want) {
  const auto path = test::spd_scene(name);
  if (!std::filesystem::is_regular_file(path)) GTEST_SKIP() << path << " is absent";
  world w = make_world(load_scene(path.string()));
  workers pool(hardware_threads());
  frame_params fp;
  frame_result fr = render_frame(pool, w, make_camera(w.sc.view, 513, 513), fp);
  EXPECT_EQ(fr.rays.eye, 513u * 513u);
  EXPECT_TRUE(within_10_percent("reflect", fr.rays.reflect, want.reflect));
  EXPECT_TRUE(within_10_percent("refract", fr.rays.refract, want.refract));
  EXPECT_TRUE(within_10_percent("shadow", fr.rays.shadow, want.shadow));
  testing::Test::RecordProperty("reflect", std::to_string(fr.rays.reflect));
  testing::Test::RecordProperty("refract", std::to_string(fr.rays.refract));
  testing::Test::RecordProperty("shadow", std::to_string(fr.rays.shadow));
}

TEST(SpdCounts, BallsS4) { check_counts("balls-s4", {175095, 0, 954368}); }
TEST(SpdCounts, MountS6) { check_counts("mount-s6", {354769, 354769, 412922}); }
TEST(SpdCounts, RingsS7) { check_counts("rings-s7", {315236, 0, 1085002}); }
TEST(SpdCounts, TeapotS12) { check_counts("teapot-s12", {225248, 0, 407656}); }
TEST(SpdCounts, TetraS6) { check_counts("tetra-s6", {0, 0, 46112}); }
TEST(SpdCounts, TreeS11) { check_counts("tree-s11", {0, 0, 1097419}); }

}  // namespace
}  // namespace epsray
