// mpi: `mpirun -np K build/epsray walk` (docs/mpi.md) under Open MPI's mpirun with 2 and 3
// ranks (--oversubscribe: more ranks than cores). The frames are the one-process walk's
// byte for byte with --keyframe, and without it in base mode; without it interp and full
// keep the bound. One stats file holds every frame once with its rank; bad input is
// refused once with exit 2; an interrupt keeps whole frames and their stats only; a rank
// failing at run time leaves nothing. Skipped where mpirun is absent or epsray was built
// without MPI.
#include <algorithm>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "image/image_io.h"
#include "test_process.h"

namespace epsray {
namespace {

namespace fs = std::filesystem;
using test::temp_dir;

#ifdef EPSRAY_MPIEXEC
const std::string mpiexec = EPSRAY_MPIEXEC;
#else
const std::string mpiexec;
#endif

const std::string artroom = std::string(EPSRAY_SOURCE_DIR) + "/scenes/artroom.nff";
const std::string walk_path = std::string(EPSRAY_SOURCE_DIR) + "/scenes/paths/artroom-walk.path";
const std::string long_path = std::string(EPSRAY_SOURCE_DIR) + "/scenes/paths/artroom-long.path";
constexpr int frames = 30;

// mpirun as root (CI's containers). Under AddressSanitizer (tools/run-sanitizers.sh), Open
// MPI's libraries keep some of what MPI_Init allocates until the process ends, and they
// have no frame pointers: LeakSanitizer needs the slow unwinder to see those stacks and
// match them to tools/lsan.supp, and its note on the suppressions used must stay off
// stderr, which the tests count the lines of.
std::vector<std::string> mpi_environment() {
#ifdef __SANITIZE_ADDRESS__
  const char* asan = std::getenv("ASAN_OPTIONS");
  std::vector<std::string> env = test::environment({"ASAN_OPTIONS", "LSAN_OPTIONS"});
  env.push_back(std::string("ASAN_OPTIONS=") + (asan ? std::string(asan) + ":" : "") + "fast_unwind_on_malloc=0");
  env.push_back(std::string("LSAN_OPTIONS=suppressions=") + EPSRAY_SOURCE_DIR + "/tools/lsan.supp:print_suppressions=0");
#else
  std::vector<std::string> env = test::environment();
#endif
  env.insert(env.end(), {"OMPI_ALLOW_RUN_AS_ROOT=1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1"});
  return env;
}

// Why these tests cannot run here, or empty.
std::string why_not_here() {
  if (mpiexec.empty()) return "epsray was configured without MPI";
  if (::access(mpiexec.c_str(), X_OK) != 0) return mpiexec + " is absent";
  temp_dir io;
  const test::proc_result r = test::run_process({EPSRAY_BINARY, "info"}, io.path(), test::environment(), io, 60);
  if (r.out.find("MPI: none") != std::string::npos) return "epsray was built without MPI";
  return "";
}

#define EPSRAY_REQUIRE_MPI()                                          \
  do {                                                                \
    static const std::string why = why_not_here();                    \
    if (!why.empty()) GTEST_SKIP() << why << "; MPI tests skipped";   \
  } while (0)

using test::appears;
using test::names_in;

class Mpi : public testing::Test {
 protected:
  void SetUp() override {
    // The art room's walk, its first 30 cameras (about 0.2 s of frames at 64x48).
    std::istringstream in(test::read_file(walk_path));
    std::string line, text;
    int n = 0;
    while (std::getline(in, line) && n < frames)
      if (!line.empty() && line[0] != '#') text += line + "\n", ++n;
    test::write_file(work.file("p.path"), text);
  }
  test::proc_result epsray(std::vector<std::string> args) {
    args.insert(args.begin(), EPSRAY_BINARY);
    return test::run_process(args, work.path(), test::environment(), io);
  }
  test::proc_result mpirun(int ranks, std::vector<std::string> args) {
    args.insert(args.begin(), {mpiexec, "-q", "--oversubscribe", "-np", std::to_string(ranks), EPSRAY_BINARY});
    return test::run_process(args, work.path(), mpi_environment(), io);
  }
  std::vector<std::string> walk(const std::string& mode, const std::string& out_dir) {
    return {"walk", artroom, "--path", "p.path", "--size", "64x48", "--mode", mode, "--threads", "1",
            "--out-dir", out_dir, "--pfm", "--quiet"};
  }
  // The frames of two folders that differ, byte for byte.
  std::vector<std::string> differing(const std::string& a, const std::string& b) {
    std::vector<std::string> out;
    const std::vector<std::string> names = names_in(work.path() / a);
    EXPECT_EQ(names.size(), size_t(frames)) << a;
    EXPECT_EQ(names, names_in(work.path() / b)) << a << " against " << b;
    for (const std::string& n : names)
      if (test::read_file(work.file(a + "/" + n)) != test::read_file(work.file(b + "/" + n))) out.push_back(n);
    return out;
  }
  nlohmann::json stats(const std::string& file) { return nlohmann::json::parse(test::read_file(work.file(file))); }
  temp_dir work, io;
};

// Every frame once, in path order, each with the rank whose segment holds it.
void expect_frames_once_with_ranks(const nlohmann::json& j, int ranks, int count) {
  const nlohmann::json& mpi = j.at("machine").at("mpi");
  EXPECT_EQ(mpi.at("ranks"), ranks);
  const nlohmann::json& segs = mpi.at("segments");
  ASSERT_EQ(segs.size(), size_t(ranks));
  ASSERT_EQ(j.at("frames").size(), size_t(count));
  for (int k = 0; k < count; ++k) {
    const nlohmann::json& f = j.at("frames")[size_t(k)];
    EXPECT_EQ(f.at("index"), k);
    const int r = f.at("rank");
    ASSERT_GE(r, 0);
    ASSERT_LT(r, ranks);
    EXPECT_GE(k, segs[size_t(r)][0].get<int>());
    EXPECT_LE(k, segs[size_t(r)][1].get<int>());
  }
  EXPECT_EQ(j.at("interrupted"), false);
}

class MpiModes : public Mpi, public testing::WithParamInterface<const char*> {};

TEST_P(MpiModes, SameFramesAsOneProcessWithKeyframes) {
  EPSRAY_REQUIRE_MPI();
  const std::string mode = GetParam();
  std::vector<std::string> one = walk(mode, "one");
  one.insert(one.end(), {"--keyframe", "10"});
  ASSERT_EQ(epsray(one).code, 0) << epsray(one);
  for (int ranks : {2, 3}) {
    const std::string dir = "ranks" + std::to_string(ranks), json = dir + ".json";
    std::vector<std::string> args = walk(mode, dir);
    args.insert(args.end(), {"--keyframe", "10", "--stats", json});
    const test::proc_result r = mpirun(ranks, args);
    ASSERT_EQ(r.code, 0) << r;
    EXPECT_EQ(differing("one", dir), std::vector<std::string>{}) << ranks << " ranks";
    const nlohmann::json j = stats(json);
    expect_frames_once_with_ranks(j, ranks, frames);
    for (const nlohmann::json& s : j.at("machine").at("mpi").at("segments"))
      if (s[0].get<int>() <= s[1].get<int>()) {
        EXPECT_EQ(s[0].get<int>() % 10, 0) << "segments start at keyframes";
      }
  }
}

INSTANTIATE_TEST_SUITE_P(Modes, MpiModes, testing::Values("base", "interp", "full"),
                         [](const testing::TestParamInfo<const char*>& i) { return std::string(i.param); });

TEST_F(Mpi, WithoutKeyframesBaseIsTheSameAndInterpolationKeepsTheBound) {
  EPSRAY_REQUIRE_MPI();
  ASSERT_EQ(epsray(walk("base", "one")).code, 0);
  std::vector<std::string> base = walk("base", "three");
  base.push_back("--pin");  // ranks on disjoint cores: where they run, never what they compute
  const test::proc_result b = mpirun(3, base);
  ASSERT_EQ(b.code, 0) << b;
  EXPECT_EQ(differing("one", "three"), std::vector<std::string>{});
  for (const char* mode : {"interp", "full"}) {
    std::vector<std::string> args = walk(mode, mode);
    args.insert(args.end(), {"--verify", "--stats", std::string(mode) + ".json"});
    const test::proc_result r = mpirun(3, args);
    ASSERT_EQ(r.code, 0) << r;
    const nlohmann::json j = stats(std::string(mode) + ".json");
    expect_frames_once_with_ranks(j, 3, frames);
    for (const nlohmann::json& f : j.at("frames")) EXPECT_EQ(f.at("verify").at("violations"), 0) << mode;
  }
}

TEST_F(Mpi, BadInputIsRefusedOnceWithExitTwo) {
  EPSRAY_REQUIRE_MPI();
  test::write_file(work.file("bad.nff"),
                   "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 0.1\nresolution 8 8\ns 0 0 0 zz\n");
  struct refusal {
    std::vector<std::string> args;
    std::string says;
  };
  const std::vector<refusal> cases = {
      {{"walk", "bad.nff", "--path", "p.path", "--out-dir", "out", "--png"}, "bad.nff:8: "},
      {{"walk", artroom, "--path", "p.path", "--out-dir", "out", "--png", "--stats", "no/such/folder/s.json"},
       "bad --stats"},
      {{"walk", artroom, "--path", "p.path", "--keyframe", "-3"}, "bad --keyframe"},
      {{"render", artroom, "--png", "a.png"}, "only walk runs over mpirun's ranks"},
  };
  for (const refusal& c : cases) {
    const test::proc_result r = mpirun(3, c.args);
    EXPECT_EQ(r.code, 2) << r;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line from one rank: " << r;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << r;
    EXPECT_EQ(r.out, "") << r;
    EXPECT_EQ(names_in(work.path()), (std::vector<std::string>{"bad.nff", "p.path"})) << "nothing written: " << r;
  }
}

TEST_F(Mpi, RankFailingAtRunTimeLeavesNothing) {
  EPSRAY_REQUIRE_MPI();
  // A folder where frame 20 goes: the rank whose segment holds it cannot write it.
  fs::create_directories(work.path() / "out" / "frame_0020.pfm");
  std::vector<std::string> args = walk("full", "out");
  args.insert(args.end(), {"--stats", "s.json"});
  const test::proc_result r = mpirun(3, args);
  EXPECT_EQ(r.code, 1) << r;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r;
  EXPECT_NE(r.err.find("frame_0020.pfm"), std::string::npos) << r;
  EXPECT_EQ(names_in(work.path() / "out"), std::vector<std::string>{"frame_0020.pfm"})
      << "every rank removes the frames it wrote";
  EXPECT_FALSE(fs::exists(work.path() / "s.json"));
}

TEST_F(Mpi, InterruptedJobKeepsWholeFramesAndTheirStats) {
  EPSRAY_REQUIRE_MPI();
  // The 1,000 frames of the long walk on 2 ranks, stopped by SIGINT to mpirun once both
  // ranks have written frames (rank 1 starts near the middle). mpirun passes SIGTERM to
  // the ranks and kills them a second later; they stop at once, leaving the frame in hand.
  // At 160x120 the walk takes seconds: at 64x48 it could end before the signal arrived.
  std::vector<std::string> argv = {mpiexec, "-q", "--oversubscribe", "-np", "2", EPSRAY_BINARY, "walk", artroom,
                                   "--path", long_path, "--size", "160x120", "--threads", "1", "--out-dir", "out",
                                   "--pfm", "--stats", "s.json"};
  const pid_t pid = test::start_process(argv, work.path(), mpi_environment(), io.file("stdout"), io.file("stderr"));
  ASSERT_GT(pid, 0);
  // Both ranks have written a frame: rank 0's first, and one of rank 1's (from about 500).
  bool started = appears(work.path() / "out" / "frame_0000.pfm", 60);
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  auto second_rank_wrote = [&] {
    const std::vector<std::string> names = names_in(work.path() / "out");
    return std::any_of(names.begin(), names.end(), [](const std::string& n) {
      return n >= "frame_0300" && n.size() > 4 && n.compare(n.size() - 4, 4, ".pfm") == 0;
    });
  };
  while (started && !second_rank_wrote() && std::chrono::steady_clock::now() < end)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  started = started && second_rank_wrote();
  kill(pid, SIGINT);
  int status = 0;
  ASSERT_TRUE(test::wait_or_kill(pid, 60, status)) << "mpirun did not end";
  ASSERT_TRUE(started) << test::read_file(io.file("stderr"));
  const std::string err = test::read_file(io.file("stderr"));
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) != 0) << "mpirun reports the interrupt: " << err;
  EXPECT_NE(err.find("interrupted by SIGTERM"), std::string::npos) << err;

  const nlohmann::json j = stats("s.json");
  EXPECT_EQ(j.at("interrupted"), true);
  std::set<std::string> listed;
  for (const nlohmann::json& f : j.at("frames")) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.pfm", f.at("index").get<int>());
    listed.insert(name);
  }
  EXPECT_LT(listed.size(), 1000u) << "the walk was stopped";
  std::set<int> ranks_done;
  for (const nlohmann::json& f : j.at("frames")) ranks_done.insert(f.at("rank").get<int>());
  EXPECT_EQ(ranks_done.size(), 2u) << "both ranks had frames done";
  const std::vector<std::string> files = names_in(work.path() / "out");
  EXPECT_EQ(std::set<std::string>(files.begin(), files.end()), listed) << "one whole file per frame in the stats";
  for (const std::string& f : files) {
    EXPECT_EQ(f.find(".tmp"), std::string::npos) << f << " left behind";
    const image img = read_pfm((work.path() / "out" / f).string());  // throws if cut short
    EXPECT_EQ(img.width, 160);
  }
}

}  // namespace
}  // namespace epsray
