// Small helpers shared by the test binaries: paths passed in by tests/CMakeLists.txt,
// temporary folders, whole-file I/O, and worlds built from scene text.
#pragma once
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <string_view>

#include "accel/world.h"
#include "image/image.h"
#include "scene/nff.h"

namespace epsray::test {

namespace fs = std::filesystem;

inline fs::path shared_dir() { return fs::path(EPSRAY_SHARED_DIR); }
inline fs::path spd_dir() { return shared_dir() / "scenes" / "spd"; }
inline fs::path spd_scene(const std::string& name) { return spd_dir() / (name + ".nff"); }

// Skips the calling test when ../shared/scenes/spd (or the one scene) is absent.
#define EPSRAY_REQUIRE_SPD(name)                                                        \
  do {                                                                                  \
    if (!std::filesystem::is_regular_file(::epsray::test::spd_scene(name)))             \
      GTEST_SKIP() << "SPD scene " << ::epsray::test::spd_scene(name) << " is absent"; \
  } while (0)

// The small SPD scenes the parameterised tests run on, and their names as test names.
#define EPSRAY_SMALL_SPD_SCENES                                                                          \
  testing::Values("balls-s3", "gears-s2", "jacks-s3", "lattice-s4", "mount-s4", "rings-s3", "shells-s2", \
                  "sombrero-s1", "teapot-s6", "tetra-s4", "tree-s8")

inline std::string spd_param_name(const testing::TestParamInfo<const char*>& i) {
  std::string n = i.param;
  for (char& c : n)
    if (c == '-') c = '_';
  return n;
}

// A fresh folder under the system temp folder, removed with everything in it.
class temp_dir {
 public:
  temp_dir() {
    static std::atomic<int> counter{0};
    path_ = fs::temp_directory_path() /
            ("epsray-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + "-" +
             std::to_string(std::rand()));
    fs::create_directories(path_);
  }
  ~temp_dir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  temp_dir(const temp_dir&) = delete;
  temp_dir& operator=(const temp_dir&) = delete;
  const fs::path& path() const { return path_; }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

// Bit-identical images (the determinism tests: same pixels for any thread count).
inline bool same_pixels(const image& a, const image& b) {
  return a.width == b.width && a.height == b.height &&
         std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(glm::vec3)) == 0;
}

inline void write_file(const std::string& path, std::string_view text) {
  std::ofstream out(path, std::ios::binary);
  out.write(text.data(), std::streamsize(text.size()));
  ASSERT_TRUE(out.good()) << "cannot write " << path;
}

inline std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline world world_from_text(std::string_view text, const std::string& name = "test.nff") {
  return make_world(parse_scene(text, name, ""));
}

// Draws for the property tests, from a seeded std::mt19937.
inline float uniform(std::mt19937& g, float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(g); }
inline vec3 uniform_vec(std::mt19937& g, float lo, float hi) { return {uniform(g, lo, hi), uniform(g, lo, hi), uniform(g, lo, hi)}; }
// A unit vector, uniform over directions (rejection in the unit ball).
inline vec3 unit_vec(std::mt19937& g) {
  for (;;) {
    vec3 v = uniform_vec(g, -1, 1);
    float l = glm::length(v);
    if (l > 0.1f && l <= 1) return v / l;
  }
}

}  // namespace epsray::test
